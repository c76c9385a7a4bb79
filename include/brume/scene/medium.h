// A participating medium, and the one interface through which every integrator, strategy and
// shadow ray uses it (docs/architecture.md, "a medium query"). Every query is along a ray
// o + t·d over a piece [t0, t1] that lies in this medium, so that a medium whose coefficients
// vary in space can answer the same questions:
//   sampleDistance  free flight over the piece: a collision or a pass, its throughput weight
//                   and the densities of both walk directions (the MIS weights need both);
//   transit         transmittance over the piece and the same two densities, for points that
//                   were joined rather than sampled;
//   sigmaSAt, g     scattering coefficient and phase function at a point.
// Today's media are homogeneous (coefficients in 1/m, Henyey–Greenstein anisotropy g): the
// closed forms of sampling/free_flight.h, one exp for grey media. A heterogeneous medium
// would answer sampleDistance by delta tracking against a majorant and transit by ratio
// tracking (the densities then being those of the tracking's own events); per-channel
// (spectral) MIS would carry a density per colour channel where `double` stands now.
#pragma once
#include <string>
#include "brume/math/ray.h"
#include "brume/sampling/sampler.h"

namespace brume {

// The outcome of free flight over a piece [t0, t1] of a ray.
struct MediumSample {
    bool scattered = false;  // a collision at t (< t1); otherwise the flight passed t1
    float t = 0;
    Spectrum weight{1.0f};   // T·σs / p_scatter, or T / P_pass
    // Free-flight densities: fwd, of this flight's outcome (scattering density at t, or the
    // probability of passing t1); rev, of a walk in the opposite direction stopping at t0
    // (its scattering density there if t0 is a medium point, else its pass probability).
    double fwd = 1, rev = 1;
};

// Transmittance over a piece and the densities of the two walks that would cross it, each
// stopping at its far end if that end is a medium point (scattering density) or passing it.
struct MediumTransit {
    Spectrum T{1.0f};
    double fwd = 1, rev = 1;  // walk t0 → t1, walk t1 → t0
};

struct Medium {
    std::string name;
    Spectrum sigmaS;  // scattering
    Spectrum sigmaA;  // absorption
    float g = 0;      // HG anisotropy, (−1, 1)
    Spectrum sigmaT() const { return sigmaS + sigmaA; }
    // One extinction for all channels: distance sampling needs no channel choice.
    bool grey() const {
        Spectrum st = sigmaT();
        return st.x == st.y && st.y == st.z;
    }

    // Free flight from t0 along the ray, stopping at a collision before t1 or passing t1
    // (t1 = +∞ allowed). uDistance picks the distance, uChannel the colour channel whose
    // extinction drives it (ignored in grey media: callers need not draw it). startIsPoint: t0 is a medium vertex.
    MediumSample sampleDistance(const Ray& ray, float t0, float t1, float uDistance, float uChannel,
                                bool startIsPoint) const;
    MediumTransit transit(const Ray& ray, float t0, float t1, bool startIsPoint, bool endIsPoint) const;
    Spectrum transmittance(const Ray& ray, float t0, float t1) const;
    Spectrum sigmaSAt(Vec3 p) const { return sigmaS; }
};

}  // namespace brume
