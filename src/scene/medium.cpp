#include "brume/scene/medium.h"

#include "brume/sampling/free_flight.h"

namespace brume {

// Homogeneous: every quantity depends on the piece's length ℓ = t1 − t0 only, and the
// densities are symmetric (a walk either way sees the same σt over the same length). In a
// grey medium one exponential e = exp(−σt·ℓ) gives them all: T = P_pass = e, p_scatter = σt·e,
// and the weights are σs/σt (a collision) and 1 (a pass).
namespace {

bool isGrey(Spectrum s) { return s.x == s.y && s.y == s.z; }

}  // namespace

MediumSample Medium::sampleDistance(const Ray& ray, float t0, float t1, float uDistance, float uChannel,
                                    bool startIsPoint) const {
    const Spectrum st = sigmaT();
    const float len = t1 - t0;
    MediumSample ms;
    float t = sampleFreeFlight(st, uDistance, uChannel);
    ms.scattered = t < len;
    if (!ms.scattered) {
        t = len;
        if (std::isinf(len)) {  // flew to infinity through the medium: nothing arrives
            ms.t = t1;
            ms.weight = Spectrum(0.0f);
            ms.fwd = ms.rev = 0;
            return ms;
        }
    }
    ms.t = t0 + t;
    if (isGrey(st)) {
        const double e = std::exp(-double(st.x) * t), p = double(st.x) * e;
        if (ms.scattered) {
            ms.weight = sigmaS / st.x;
            ms.fwd = p;
            ms.rev = startIsPoint ? p : e;
        } else {
            ms.weight = Spectrum(1.0f);
            ms.fwd = e;
            ms.rev = startIsPoint ? p : e;
        }
        return ms;
    }
    const double pScatter = freeFlightPdfScatter(st, t), pPass = freeFlightPdfPass(st, t);
    if (ms.scattered) {
        ms.weight = transmittanceOver(st, t) * sigmaS / float(pScatter);
        ms.fwd = pScatter;
        ms.rev = startIsPoint ? pScatter : pPass;
    } else {
        ms.weight = transmittanceOver(st, t) / float(pPass);
        ms.fwd = pPass;
        ms.rev = startIsPoint ? pScatter : pPass;
    }
    return ms;
}

MediumTransit Medium::transit(const Ray& ray, float t0, float t1, bool startIsPoint, bool endIsPoint) const {
    const Spectrum st = sigmaT();
    const float len = t1 - t0;
    MediumTransit tr;
    double pass, scatter;
    if (isGrey(st)) {
        pass = st.x > 0 ? std::exp(-double(st.x) * len) : 1.0;
        scatter = double(st.x) * pass;
        tr.T = Spectrum(float(pass));
    } else {
        tr.T = transmittanceOver(st, len);
        pass = freeFlightPdfPass(st, len);
        scatter = freeFlightPdfScatter(st, len);
    }
    tr.fwd = endIsPoint ? scatter : pass;
    tr.rev = startIsPoint ? scatter : pass;
    return tr;
}

Spectrum Medium::transmittance(const Ray& ray, float t0, float t1) const { return transmittanceOver(sigmaT(), t1 - t0); }

}  // namespace brume
