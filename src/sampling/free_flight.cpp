#include "brume/sampling/free_flight.h"

#include <limits>

namespace brume {

float sampleFreeFlight(float sigmaT, float uDistance) {
    if (sigmaT <= 0) return std::numeric_limits<float>::infinity();
    return -std::log1p(-uDistance) / sigmaT;
}

int pickChannel(Spectrum w, float u) {
    float acc = 0;
    int last = 0;
    for (int c = 0; c < 3; ++c) {
        if (!(w[c] > 0)) continue;  // never a channel of weight 0, even at rounding's edge
        last = c;
        acc += w[c];
        if (u < acc) return c;
    }
    return last;
}

double freeFlightPdfScatter(float sigmaT, float t) {
    return sigmaT > 0 ? double(sigmaT) * std::exp(-double(sigmaT) * t) : 0.0;
}

double freeFlightPdfPass(float sigmaT, float t) { return sigmaT > 0 ? std::exp(-double(sigmaT) * t) : 1.0; }

}  // namespace brume
