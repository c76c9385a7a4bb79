// What every walk through a density grid shares (scene/heterogeneous_medium.cpp,
// scene/medium_emission.cpp): the ray in the grid's voxel coordinates, exponential steps that
// always advance, and the hash that seeds a query's own random numbers (deterministic
// whatever the thread count).
#pragma once
#include <cmath>
#include <cstring>
#include <limits>

#include "brume/math/ray.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/medium.h"

namespace brume::grid {

inline uint64_t bitsOf(float f) {
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

inline uint64_t hashQuery(const Ray& ray, float a, float b, float c) {
    uint64_t h = mixBits(bitsOf(ray.o.x) ^ (bitsOf(ray.o.y) << 32));
    h = mixBits(h ^ bitsOf(ray.o.z) ^ (bitsOf(ray.d.x) << 32));
    h = mixBits(h ^ bitsOf(ray.d.y) ^ (bitsOf(ray.d.z) << 32));
    return mixBits(h ^ bitsOf(a) ^ (bitsOf(b) << 32) ^ (bitsOf(c) << 16));
}

// The ray in a grid's local voxel coordinates: q(t) = q0 + t·dq, t the ray's own parameter.
struct LocalRay {
    Vec3 q0, dq;
    Vec3 at(float t) const { return q0 + dq * t; }
};

inline LocalRay toLocal(const GridPlacement& g, const Ray& ray) {
    return {g.worldToLocal.point(ray.o), g.worldToLocal.vector(ray.d)};
}

// u is a multiple of 2^-24 (toUnitFloat), so 1 − u is exact and logf is as accurate as
// log1pf here, at about half its cost (log1pf was a fifth of a heterogeneous render).
inline float sampleExp(float rate, float u) { return -std::log(1.0f - u) / rate; }

// t + s, but at least the next float after t: a tentative step shorter than t's float spacing
// would not move t, and a walk through a piece with no real collision would never end. Only
// where the majorant's optical depth over one float step of t exceeds ~1 (the loader bounds
// it, gltf_media.cpp kMaxVoxelOpticalDepth) does this lengthen a step.
inline float advance(float t, float s) {
    const float next = t + s;
    return next > t ? next : std::nextafter(t, std::numeric_limits<float>::infinity());
}

}  // namespace brume::grid
