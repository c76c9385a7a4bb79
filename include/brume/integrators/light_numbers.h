// The numbers a light connection draws, only where the light needs them: every draw is a
// hash (sampling/sampler.h), and at a place of its own, so a draw skipped changes no other.
#pragma once
#include "brume/integrators/sample_dimensions.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/scene.h"

namespace brume {

// The light a connection goes to, from the light distribution; a number only when there is a
// choice. The distribution must not be empty.
inline int pickLight(const Scene& scene, const Sampler& sampler, uint32_t dims, uint32_t repeat, float* pick) {
    const auto& d = scene.lightDistribution();
    return d.sample(d.size() > 1 ? sampler.get1D(dims + dim::kPick, repeat) : 0.5f, pick);
}

// The same, chosen by where the connection starts (light_selection.h): from the point x (a
// vertex's connection), or along the segment o + t·d, t ∈ [0, tEnd] (a connection that places
// its point on the segment). Power's pick where the scene's selection is not spatial.
inline int pickLightAt(const Scene& scene, const Sampler& sampler, uint32_t dims, uint32_t repeat, Vec3 x, float* pick) {
    const float u = scene.lights().size() > 1 ? sampler.get1D(dims + dim::kPick, repeat) : 0.5f;
    return scene.lightSelection().sampleAt(x, u, pick);
}
inline int pickLightAlong(const Scene& scene, const Sampler& sampler, uint32_t dims, uint32_t repeat, Vec3 o, Vec3 d,
                          float tEnd, float* pick) {
    const float u = scene.lights().size() > 1 ? sampler.get1D(dims + dim::kPick, repeat) : 0.5f;
    return scene.lightSelection().sampleAlong(o, d, tEnd, u, pick);
}

// The numbers for a point on the light (dimension `dim`): a triangle or sphere light has
// extent; a point, spot or directional light's sample is fixed and draws nothing.
inline Sample2 lightPointNumbers(const Light& light, const Sampler& sampler, uint32_t dim, uint32_t repeat) {
    return light.hasSurface() ? sampler.get2D(dim, repeat) : Sample2{0.5f, 0.5f};
}

}  // namespace brume
