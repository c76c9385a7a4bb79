#include "brume/scene/medium.h"

#include "brume/sampling/free_flight.h"

#include <algorithm>
#include <limits>

namespace brume {

// Homogeneous: every quantity depends on the piece's length ℓ = t1 − t0 only, and the
// densities are symmetric (a walk either way sees the same σt over the same length). In a
// grey medium one exponential e = exp(−σt·ℓ) gives them all: T = P_pass = e, p_scatter = σt·e,
// and the weights are σs/σt (a collision) and 1 (a pass), whatever the channel weights.
//
// Coloured: the distance is sampled with channel c's extinction, c drawn with probability w_c;
// the flight's density is the mixture p = Σ_c w_c·p_c (p_c: σt_c·e_c for a collision, e_c for
// a pass), and the weight is T·σs/p or T/p per channel. With w ∝ the path throughput β this
// keeps Σ_c β_c from growing in a non-absorbing medium (β'_c = β_c·f_c/p with
// Σ_c β_c·f_c = Σ_c β_c·p_c·albedo_c); with one-hot w (a hero channel) the caller weighs the
// channels at the path level instead.
MediumSample Medium::sampleDistance(const Ray& ray, float t0, float t1, float uDistance, float uChannel,
                                    Spectrum channels, bool startIsPoint) const {
    if (heterogeneous()) return trackDistance(ray, t0, t1, uDistance, channels, startIsPoint);
    const Spectrum st = sigmaT();
    const float len = t1 - t0;
    const bool grey = this->grey();
    MediumSample ms;
    const int c = grey ? 0 : pickChannel(channels, uChannel);
    float t = sampleFreeFlight(st[c], uDistance);
    ms.scattered = t < len;
    if (!ms.scattered) {
        t = len;
        if (std::isinf(len)) {  // flew to infinity through the medium: nothing arrives
            ms.t = t1;
            ms.weight = Spectrum(0.0f);
            ms.fwd = ms.rev = Channels(0.0);
            ms.pdf = 0;
            return ms;
        }
    }
    ms.t = t0 + t;
    if (grey) {
        const double e = std::exp(-double(st.x) * t), p = double(st.x) * e;
        ms.weight = ms.scattered ? sigmaS / st.x : Spectrum(1.0f);
        ms.pdf = ms.scattered ? p : e;
        ms.fwd = Channels(ms.pdf);
        ms.rev = Channels(startIsPoint ? p : e);
        return ms;
    }
    Channels scatter(0.0), pass(1.0);
    for (int k = 0; k < 3; ++k) {
        scatter[k] = freeFlightPdfScatter(st[k], t);
        pass[k] = freeFlightPdfPass(st[k], t);
    }
    ms.fwd = ms.scattered ? scatter : pass;
    ms.rev = startIsPoint ? scatter : pass;
    ms.pdf = ms.fwd.mix(channels);
    // f_k = T_k·σs_k = p_scatter,k·σs_k/σt_k, or T_k = P_pass,k; the ratio in double.
    for (int k = 0; k < 3; ++k) {
        const double f = ms.scattered ? (st[k] > 0 ? scatter[k] * sigmaS[k] / st[k] : 0.0) : pass[k];
        // (Capped to float's range: a channel far thinner than the one sampled, over a long
        // piece, can outweigh it beyond 3e38; converting that to float is undefined.)
        ms.weight[k] = ms.pdf > 0 ? float(std::min(f / ms.pdf, double(std::numeric_limits<float>::max()))) : 0.0f;
    }
    return ms;
}

MediumTransit Medium::transit(const Ray& ray, float t0, float t1, bool startIsPoint, bool endIsPoint) const {
    if (heterogeneous()) return ratioTrack(ray, t0, t1, startIsPoint, endIsPoint);
    const Spectrum st = sigmaT();
    const float len = t1 - t0;
    MediumTransit tr;
    if (grey()) {
        const double pass = st.x > 0 ? std::exp(-double(st.x) * len) : 1.0, scatter = double(st.x) * pass;
        tr.T = Spectrum(float(pass));
        tr.fwd = Channels(endIsPoint ? scatter : pass);
        tr.rev = Channels(startIsPoint ? scatter : pass);
        return tr;
    }
    tr.T = transmittanceOver(st, len);
    for (int k = 0; k < 3; ++k) {
        const double pass = freeFlightPdfPass(st[k], len), scatter = freeFlightPdfScatter(st[k], len);
        tr.fwd[k] = endIsPoint ? scatter : pass;
        tr.rev[k] = startIsPoint ? scatter : pass;
    }
    return tr;
}

Spectrum Medium::transmittance(const Ray& ray, float t0, float t1) const {
    if (heterogeneous()) return ratioTrack(ray, t0, t1, false, false).T;
    return transmittanceOver(sigmaT(), t1 - t0);
}

}  // namespace brume
