// Free-flight (density) sampling in a homogeneous medium, one colour channel at a time: the
// closed forms behind Medium (scene/medium.h), which is what integrators call. A coloured
// medium samples with one channel's extinction and weighs the channels' densities
// (docs/path-tracer.md, "coloured media").
#pragma once
#include "brume/math/vec3.h"

namespace brume {

// exp(−σt·t) per channel; σt = 0 over an infinite distance gives 1, not NaN.
inline Spectrum transmittanceOver(Spectrum sigmaT, float t) {
    auto tr = [t](float s) { return s > 0 ? std::exp(-s * t) : 1.0f; };
    if (sigmaT.x == sigmaT.y && sigmaT.y == sigmaT.z) return Spectrum(tr(sigmaT.x));  // grey: one exp
    return {tr(sigmaT.x), tr(sigmaT.y), tr(sigmaT.z)};
}

// t ~ σt·exp(−σt·t) from uDistance; +∞ if σt = 0.
float sampleFreeFlight(float sigmaT, float uDistance);

// The channel c with probability weights[c] (non-negative, summing to 1) from u in [0, 1).
int pickChannel(Spectrum weights, float u);

// Channel weights in proportion to the throughput β (uniform if β is black): Kutz et al.'s
// history-aware choice, under which Σ_c β_c cannot grow at a collision in a medium whose
// albedo is at most 1 (docs/path-tracer.md, "coloured media").
inline Spectrum throughputChannels(Spectrum beta) {
    const float sum = beta.x + beta.y + beta.z;
    return sum > 0 ? beta / sum : Spectrum(1.0f / 3.0f);
}

// Density of scattering at t, σt·exp(−σt·t), and of flying past t, exp(−σt·t). In double:
// MIS weights multiply these over long edges, where float would underflow.
double freeFlightPdfScatter(float sigmaT, float t);
double freeFlightPdfPass(float sigmaT, float t);

}  // namespace brume
