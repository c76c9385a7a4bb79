// GGX (Trowbridge–Reitz) microfacet distribution in a local frame with the normal on +z.
// alpha = roughness².
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

// D(h) = α² / (π ((α²−1) cos²θh + 1)²); ∫ D(h) cosθh dω = 1.
float ggxD(Vec3 h, float alpha);

// Smith masking for one direction: G1 = 2 / (1 + sqrt(1 + α² tan²θ)).
float ggxG1(Vec3 w, float alpha);

// Samples h with density D(h)·cosθh: cos²θh = (1−ξ) / (1 + (α²−1)ξ).
Vec3 sampleGgxNormal(float alpha, Sample2 u);
inline float ggxNormalPdf(Vec3 h, float alpha) { return h.z > 0 ? ggxD(h, alpha) * h.z : 0.0f; }

}  // namespace brume
