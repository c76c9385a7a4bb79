// Henyey–Greenstein phase function. cosTheta is the cosine between the incoming and the
// outgoing propagation directions; g > 0 scatters forward. For a path traced from the
// camera along d that continues along w, light travels −w then −d, so cosTheta = dot(d, w).
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

// p(cosθ) = (1−g²) / (4π (1+g²−2g cosθ)^1.5), normalised over the sphere.
inline float hgPhase(float cosTheta, float g) {
    // 1 + g² − 2gμ written as (1−g)² + 2g(1−μ): no cancellation near the peak for g → 1.
    float denom = (1.0f - g) * (1.0f - g) + 2.0f * g * (1.0f - cosTheta);
    return kInv4Pi * (1.0f - g * g) / (denom * std::sqrt(denom));
}

// Samples w with dot(d, w) distributed as HG around d. pdf = hgPhase(dot(d, w), g).
Vec3 sampleHG(Vec3 d, float g, Sample2 u);

}  // namespace brume
