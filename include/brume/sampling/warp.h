// Warps from the unit square to directions and points, each with its density.
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

// Uniform on the unit sphere; pdf 1/(4π) per steradian.
Vec3 sampleUniformSphere(Sample2 u);
constexpr float uniformSpherePdf() { return kInv4Pi; }

// Cosine-weighted on the hemisphere z > 0; pdf cosθ/π.
Vec3 sampleCosineHemisphere(Sample2 u);
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0.0f; }

// Uniform in the cone of directions with cosθ ≥ cosMax around +z; pdf 1/(2π(1−cosMax)).
Vec3 sampleUniformCone(Sample2 u, float cosMax);
inline float uniformConePdf(float cosMax) { return 1.0f / (2.0f * kPi * (1.0f - cosMax)); }

// Concentric map of the square to the unit disk (Shirley & Chiu).
Sample2 sampleConcentricDisk(Sample2 u);

// Uniform barycentrics (b0, b1) on a triangle; b2 = 1 − b0 − b1. Area pdf 1/area.
Sample2 sampleUniformTriangle(Sample2 u);

}  // namespace brume
