// Guided survival (ADRRS, Vorba and Křivánek 2016; docs/path-guiding.md), shared by the path
// tracer and bdpt's camera walk. A walk whose expected contribution β·A (β: its throughput
// before the vertex's scattering, A: what the vertex's cell says a walk scattering there
// brings back per unit of throughput) is at least 1/kWindow of the pixel's value I goes on;
// a smaller one survives with probability kWindow·β·A / I, at least kMinSurvival (A is an
// estimate, and a walk it calls worthless may not be). Unbiased for any survival above 0.
// Grey media only, and up to kGuidedDepth events; the throughput roulette otherwise.
#pragma once
#include <algorithm>

#include "brume/math/vec3.h"

namespace brume {

constexpr float kGuidedSurvivalWindow = 3.0f, kGuidedMinSurvival = 0.05f;
constexpr int kGuidedSurvivalDepth = 32;

inline float guidedSurvival(const Spectrum& betaBefore, float adjoint, float pixelValue) {
    const float expected = (betaBefore.x + betaBefore.y + betaBefore.z) / 3.0f * adjoint;
    return std::clamp(kGuidedSurvivalWindow * expected / pixelValue, kGuidedMinSurvival, 1.0f);
}

}  // namespace brume
