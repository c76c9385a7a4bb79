#include "brume/sampling/ggx.h"

namespace brume {

float ggxD(Vec3 h, float alpha) {
    if (h.z <= 0) return 0.0f;
    float a2 = alpha * alpha;
    float c2 = h.z * h.z;
    float denom = (a2 - 1.0f) * c2 + 1.0f;
    return a2 / (kPi * denom * denom);
}

float ggxG1(Vec3 w, float alpha) {
    float c2 = w.z * w.z;
    if (c2 <= 0) return 0.0f;
    float tan2 = std::max(0.0f, 1.0f - c2) / c2;
    return 2.0f / (1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}

Vec3 sampleGgxNormal(float alpha, Sample2 u) {
    float a2 = alpha * alpha;
    float cos2 = (1.0f - u.u) / (1.0f + (a2 - 1.0f) * u.u);
    float cosTheta = std::sqrt(std::max(0.0f, cos2));
    float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cos2));
    float phi = 2.0f * kPi * u.v;
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

}  // namespace brume
