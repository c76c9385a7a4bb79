// Denoising features (`brume render --aov albedo,normal`, docs/denoising.md): per pixel, the
// mean over kSamples jittered camera rays of the guides a denoiser takes (Blender's
// compositor Denoise node, Intel Open Image Denoise): the expected albedo and normal of the
// first thing each ray meets, weighted by the probability that it is met first:
//   - a collision in a piece of medium, with probability T·(1 − T_piece) per channel: the
//     single-scattering albedo σs/σt (a grid medium's too: both scale with the density), and
//     −d as the normal, as for a surface facing the camera;
//   - the surface ending the ray (not an invisible medium boundary), with probability T: its
//     BSDF's albedo (the base colour, 1 for glass) and its shading normal, turned to face the
//     camera;
//   - nothing (the ray leaves the scene): 0 and 0.
// Expected values rather than one sampled collision: a guide must not be grainy. (Grid media
// give T by ratio tracking, which is noisy where they are dense.) Normals in the scene's
// world space (glTF's, y up). The jitter of pixel (x, y) is a hash of (seed, x, y): the same
// image for any thread count.
#pragma once
#include <cstdint>
#include <vector>

#include "brume/scene/scene.h"

namespace brume {

struct DenoiseFeatures {
    static constexpr int kSamples = 16;
    std::vector<float> albedo, normal;  // 3 per pixel, row-major, top row first
};

DenoiseFeatures denoiseFeatures(const Scene& scene, int width, int height, uint64_t seed, int threads);

}  // namespace brume
