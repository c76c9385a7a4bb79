#include "brume/sampling/free_flight.h"

#include <limits>

namespace brume {

float sampleFreeFlight(Spectrum sigmaT, float uDistance, float uChannel) {
    float s = sigmaT[std::min(2, int(uChannel * 3.0f))];
    if (s <= 0) return std::numeric_limits<float>::infinity();
    return -std::log1p(-uDistance) / s;
}

namespace {
// A grey medium (the common case) needs one exponential instead of three.
bool grey(Spectrum sigmaT) { return sigmaT[0] == sigmaT[1] && sigmaT[1] == sigmaT[2]; }
}  // namespace

double freeFlightPdfScatter(Spectrum sigmaT, float t) {
    if (grey(sigmaT)) return sigmaT[0] > 0 ? double(sigmaT[0]) * std::exp(-double(sigmaT[0]) * t) : 0.0;
    double sum = 0;
    for (int c = 0; c < 3; ++c)
        if (sigmaT[c] > 0) sum += double(sigmaT[c]) * std::exp(-double(sigmaT[c]) * t);
    return sum / 3.0;
}

double freeFlightPdfPass(Spectrum sigmaT, float t) {
    if (grey(sigmaT)) return sigmaT[0] > 0 ? std::exp(-double(sigmaT[0]) * t) : 1.0;
    double sum = 0;
    for (int c = 0; c < 3; ++c) sum += sigmaT[c] > 0 ? std::exp(-double(sigmaT[c]) * t) : 1.0;
    return sum / 3.0;
}

}  // namespace brume
