#include "brume/sampling/warp.h"

namespace brume {

Vec3 sampleUniformSphere(Sample2 u) {
    float z = 1.0f - 2.0f * u.u;
    float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    float phi = 2.0f * kPi * u.v;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

Sample2 sampleConcentricDisk(Sample2 u) {
    float a = 2.0f * u.u - 1.0f, b = 2.0f * u.v - 1.0f;
    if (a == 0 && b == 0) return {0, 0};
    float r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = (kPi / 4.0f) * (b / a);
    } else {
        r = b;
        phi = (kPi / 2.0f) - (kPi / 4.0f) * (a / b);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}

// Malley's method: project the uniform disk up to the hemisphere.
Vec3 sampleCosineHemisphere(Sample2 u) {
    Sample2 d = sampleConcentricDisk(u);
    float z = std::sqrt(std::max(0.0f, 1.0f - d.u * d.u - d.v * d.v));
    return {d.u, d.v, z};
}

// cosθ uniform in [cosMax, 1] gives equal solid angle per unit of u. sinθ comes from
// 1 − cosθ = u·(1 − cosMax) (exact in float for cosMax ≥ 0.5), as √((1 − cosθ)(1 + cosθ)):
// from a rounded cosθ it would take only a few hundred distinct values in a 0.5° cone, one of
// them exactly 0, and a spot aimed at the camera would put 1 in ~600 of its light paths
// exactly through the pinhole.
Vec3 sampleUniformCone(Sample2 u, float cosMax) {
    float oneMinusCos = u.u * (1.0f - cosMax);
    float cosTheta = 1.0f - oneMinusCos;
    float sinTheta = std::sqrt(std::max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
    float phi = 2.0f * kPi * u.v;
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

// Square-root parametrisation (Turk 1990): b0 = 1 − √u, b1 = v·√u.
Sample2 sampleUniformTriangle(Sample2 u) {
    float su = std::sqrt(u.u);
    return {1.0f - su, u.v * su};
}

}  // namespace brume
