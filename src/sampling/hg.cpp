#include "brume/sampling/hg.h"

#include "brume/math/frame.h"

namespace brume {

// Inverting the cdf of p(μ) = (1−g²)/(2(1+g²−2gμ)^1.5) over μ ∈ [−1, 1]:
//   μ = (1 + g² − ((1−g²)/(1 − g + 2gξ))²) / (2g);  ξ = 0 → μ = −1, ξ = 1 → μ = 1.
Vec3 sampleHG(Vec3 d, float g, Sample2 u) {
    float cosTheta;
    if (std::abs(g) < 1e-3f) {
        cosTheta = 1.0f - 2.0f * u.u;
    } else {
        float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u.u);
        cosTheta = (1.0f + g * g - s * s) / (2.0f * g);
        cosTheta = std::min(1.0f, std::max(-1.0f, cosTheta));
    }
    float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    float phi = 2.0f * kPi * u.v;
    return Frame(d).toWorld(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
}

}  // namespace brume
