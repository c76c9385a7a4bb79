// Free-flight (density) sampling in a homogeneous medium with RGB extinction σt: the closed
// forms behind Medium (scene/medium.h), which is what integrators call.
// One channel c is picked uniformly and t ~ σt_c·exp(−σt_c·t); the density of the sample
// is the average over channels (one-sample MIS with the balance heuristic across channels),
// so no channel's weight blows up when another channel is much denser.
#pragma once
#include "brume/math/vec3.h"

namespace brume {

// exp(−σt·t) per channel; σt = 0 over an infinite distance gives 1, not NaN.
inline Spectrum transmittanceOver(Spectrum sigmaT, float t) {
    auto tr = [t](float s) { return s > 0 ? std::exp(-s * t) : 1.0f; };
    if (sigmaT.x == sigmaT.y && sigmaT.y == sigmaT.z) return Spectrum(tr(sigmaT.x));  // grey: one exp
    return {tr(sigmaT.x), tr(sigmaT.y), tr(sigmaT.z)};
}

// uChannel in [0,1) picks the channel (thirds: red, green, blue; not read for a grey medium),
// uDistance the distance. Returns +∞ if the chosen channel has σt = 0.
float sampleFreeFlight(Spectrum sigmaT, float uDistance, float uChannel);

// Density of scattering at t: avg_c σt_c·exp(−σt_c·t). In double: MIS weights multiply these
// over long edges, where float would underflow.
double freeFlightPdfScatter(Spectrum sigmaT, float t);

// Probability of flying past t: avg_c exp(−σt_c·t).
double freeFlightPdfPass(Spectrum sigmaT, float t);

}  // namespace brume
