// A participating medium, and the one interface through which every integrator, strategy and
// shadow ray uses it (docs/architecture.md, "a medium query"). Every query is along a ray
// o + t·d over a piece [t0, t1] that lies in this medium, so that a medium whose coefficients
// vary in space can answer the same questions:
//   sampleDistance  free flight over the piece: a collision or a pass, its throughput weight
//                   and, per colour channel, the densities of both walk directions (the MIS
//                   weights need both);
//   transit         transmittance over the piece and the same densities, for points that
//                   were joined rather than sampled;
//   sigmaSAt, g     scattering coefficient and phase function at a point.
// Homogeneous media (coefficients in 1/m, Henyey–Greenstein anisotropy g) answer in closed
// form (sampling/free_flight.h), one exp for grey media. A medium with a density grid
// (coefficients per unit density; scene/heterogeneous_medium.cpp) answers sampleDistance by
// delta (spectral) tracking against the grid's majorants and transit by ratio tracking; its
// densities are deterministic stand-ins (docs/mis.md, "heterogeneous media").
//
// Coloured media (docs/path-tracer.md, "coloured media"): the caller says with what
// probability each channel drives the distance (its `channels` weights: the path throughput
// in pt, the sample's hero channel in bdpt); the distance is sampled with that channel's
// extinction and the weight divides by the mixture Σ_c w_c·p_c. The densities come back per
// channel so that the caller can form any mixture it needs. In a grid medium the weights only
// choose real or null collisions (both tracers pass the throughput's), and the densities are
// grey stand-ins (heterogeneous_medium.cpp).
//
// Emission (docs/scene-format.md, "emission"): a medium may add radiance along a ray,
// dL/ds += e(x), e = emission × (grid value × scale, or 1 without an emission grid), whatever
// its albedo; or, for a blackbody grid, e = emission (the tint) × blackbodyEmission(grid value
// × scale kelvin) (math/blackbody.h; a constant temperature is turned into constant emission
// by the loader). `emitted` estimates what a piece sends back to its start, ∫ T(t0, t)·e(t) dt
// (scene/medium_emission.cpp): the integrators add it, times the throughput, on every piece a
// camera walk crosses.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include "brume/math/channels.h"
#include "brume/math/mat4.h"
#include "brume/math/ray.h"
#include "brume/sampling/sampler.h"

namespace brume {

// The outcome of free flight over a piece [t0, t1] of a ray.
struct MediumSample {
    bool scattered = false;  // a collision at t (< t1); otherwise the flight passed t1
    float t = 0;
    Spectrum weight{1.0f};   // T·σs / p_scatter, or T / P_pass, per channel (p, P: the mixture)
    // Free-flight densities per channel: fwd, of this flight's outcome (scattering density at
    // t, or the probability of passing t1); rev, of a walk in the opposite direction stopping
    // at t0 (its scattering density there if t0 is a medium point, else its pass probability).
    Channels fwd, rev;
    double pdf = 1;          // the mixture of fwd that was sampled: Σ_c w_c·fwd_c
};

// Transmittance over a piece and the densities of the two walks that would cross it, each
// stopping at its far end if that end is a medium point (scattering density) or passing it.
struct MediumTransit {
    Spectrum T{1.0f};
    Channels fwd, rev;  // walk t0 → t1, walk t1 → t0
    uint32_t steps = 0;  // grid media: the tentative collisions ratio tracking drew (its work)
};

struct DensityGrid;

// Where a medium's density grid sits. indexToWorld: the grid's own transform; a medium inside
// a mesh has it composed with the mesh node's (place()); worldToLocal: world → the grid's
// local voxel coordinates (DensityGrid::local), what the queries use.
struct GridPlacement {
    std::shared_ptr<const DensityGrid> grid;
    Mat4 indexToWorld;
    Mat4 worldToLocal;
    float scale = 1;  // the grid's values times scale are the density
    bool placedByNode = false;  // (loader bookkeeping: one node's transform places it)
    std::string source;         // where the grid came from, for messages: <file>: grid "<name>"
    std::string requested;      // (loader bookkeeping: the file and grid name asked for)
    // Sets worldToLocal for the grid's index space placed by `node` (identity: world space).
    void place(const Mat4& node);
};

struct Medium {
    std::string name;
    Spectrum sigmaS;  // scattering (per unit density where there is a grid)
    Spectrum sigmaA;  // absorption (likewise)
    float g = 0;      // HG anisotropy, (−1, 1)
    GridPlacement density;  // no grid: homogeneous
    Spectrum emission{0.0f};    // radiance per metre (× the emission grid where there is one)
    GridPlacement emissionGrid; // no grid: the same everywhere in the medium
    bool blackbody = false;     // the emission grid is a temperature in kelvin, emission its tint
    float blackbodyIntensity = 1;  // b in math/blackbody.h
    bool heterogeneous() const { return density.grid != nullptr; }
    // (A blackbody's channel may be negative below ~1900 K, as in Cycles: math/blackbody.h.)
    bool emissive() const { return emission.x != 0 || emission.y != 0 || emission.z != 0; }
    Spectrum sigmaT() const { return sigmaS + sigmaA; }
    // One extinction for all channels: distance sampling needs no channel choice.
    bool grey() const {
        Spectrum st = sigmaT();
        return st.x == st.y && st.y == st.z;
    }

    // Free flight from t0 along the ray, stopping at a collision before t1 or passing t1
    // (t1 = +∞ allowed). uDistance picks the distance; uChannel the channel that drives it,
    // with probabilities `channels` (non-negative, summing to 1; both ignored in grey media,
    // so callers need not draw uChannel there). startIsPoint: t0 is a medium vertex.
    MediumSample sampleDistance(const Ray& ray, float t0, float t1, float uDistance, float uChannel,
                                Spectrum channels, bool startIsPoint) const;
    MediumTransit transit(const Ray& ray, float t0, float t1, bool startIsPoint, bool endIsPoint) const;
    Spectrum transmittance(const Ray& ray, float t0, float t1) const;
    Spectrum sigmaSAt(Vec3 p) const { return heterogeneous() ? sigmaS * densityAt(p) : sigmaS; }
    // The density (grid value × scale) at a world point: 1 in homogeneous media.
    float densityAt(Vec3 p) const;
    // The emission coefficient e at a world point (0 in a medium that does not emit).
    Spectrum emissionAt(Vec3 p) const;
    // e where the emission grid's stored value is v (before its scale).
    Spectrum emissionOf(float v) const;
    // An unbiased estimate of ∫_{t0}^{t1} T(t0, t)·e(t) dt along the ray (0 if the medium does
    // not emit): in closed form in a homogeneous medium with constant emission, else from the
    // points and transmittances medium_emission.cpp describes, with random numbers from a
    // hash of the query and u (the sampler's number for it: rays along the same line, as a
    // pixel centre's, still get independent estimates).
    // weight: a factor on each point of an emission grid's estimate, w(t, brick, length): its
    // brick (DensityGrid::brickAt) and the length of its stratum, 1/emissionStrata() of the
    // ray's interval in the brick, from which the point's density is 1/length (MIS with
    // next-event estimation, integrators/volume_light_sampling.h).
    using PointWeight = std::function<float(float t, size_t brick, float length)>;
    // Points per brick along a ray in an emission grid (medium_emission.cpp): 8 for a
    // blackbody, whose T⁴ changes by orders of magnitude across a brick, else 1.
    int emissionStrata() const { return blackbody ? 8 : 1; }
    Spectrum emitted(const Ray& ray, float t0, float t1, float u, const PointWeight* weight = nullptr) const;

private:
    MediumSample trackDistance(const Ray& ray, float t0, float t1, float uDistance, Spectrum channels,
                               bool startIsPoint) const;
    MediumTransit ratioTrack(const Ray& ray, float t0, float t1, bool startIsPoint, bool endIsPoint) const;
};

// The channel weights of a sample with hero channel h (bidirectional walks): all on h.
inline Spectrum heroChannel(int h) {
    Spectrum w(0.0f);
    w[h] = 1.0f;
    return w;
}

}  // namespace brume
