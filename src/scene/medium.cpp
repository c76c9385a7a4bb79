#include "brume/scene/medium.h"

#include "brume/sampling/free_flight.h"

namespace brume {

// Homogeneous: every quantity depends on the piece's length ℓ = t1 − t0 only, and the
// densities are symmetric (a walk either way sees the same σt over the same length).
MediumSample Medium::sampleDistance(const Ray& ray, float t0, float t1, float uDistance, float uChannel,
                                    bool startIsPoint) const {
    const Spectrum st = sigmaT();
    MediumSample ms;
    float t = sampleFreeFlight(st, uDistance, uChannel);
    if (t < t1 - t0) {
        double p = freeFlightPdfScatter(st, t);
        ms.scattered = true;
        ms.t = t0 + t;
        ms.weight = transmittanceOver(st, t) * sigmaS / float(p);
        ms.fwd = p;
        ms.rev = startIsPoint ? p : freeFlightPdfPass(st, t);
        return ms;
    }
    float len = t1 - t0;
    ms.t = t1;
    if (std::isinf(len)) {  // flew to infinity through the medium: nothing arrives
        ms.weight = Spectrum(0.0f);
        ms.fwd = ms.rev = 0;
        return ms;
    }
    double p = freeFlightPdfPass(st, len);
    ms.weight = transmittanceOver(st, len) / float(p);
    ms.fwd = p;
    ms.rev = startIsPoint ? freeFlightPdfScatter(st, len) : p;
    return ms;
}

MediumTransit Medium::transit(const Ray& ray, float t0, float t1, bool startIsPoint, bool endIsPoint) const {
    const Spectrum st = sigmaT();
    const float len = t1 - t0;
    MediumTransit tr;
    tr.T = transmittanceOver(st, len);
    const double pass = startIsPoint && endIsPoint ? 0.0 : freeFlightPdfPass(st, len);
    const double scatter = startIsPoint || endIsPoint ? freeFlightPdfScatter(st, len) : 0.0;
    tr.fwd = endIsPoint ? scatter : pass;
    tr.rev = startIsPoint ? scatter : pass;
    return tr;
}

Spectrum Medium::transmittance(const Ray& ray, float t0, float t1) const { return transmittanceOver(sigmaT(), t1 - t0); }

}  // namespace brume
