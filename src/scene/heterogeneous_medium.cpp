// A medium with a density grid: σ(x) = coefficient × ρ(x), ρ = grid value × scale (trilinear,
// 0 outside the grid). Every query walks the grid's majorant bricks along the ray
// (DensityGrid::forEachMajorant): within a piece [ta, tb] of majorant density m̄ the channel
// extinctions are bounded by μ̄ = kmax·m̄, kmax = the largest extinction coefficient.
//
// Free flight: spectral tracking (Kutz et al. 2017), which in grey media is delta tracking.
// Tentative collisions are drawn with rate μ̄; at one of density ρ the collision is real with
// probability P = Σ_c w_c·k_c·ρ/μ̄ (w: channel weights, below) and each channel's
// weight is multiplied by
//     real:  ks_c·ρ / (μ̄·P)          null:  (μ̄ − k_c·ρ) / (μ̄·(1 − P)),
// which keeps E[weight] = T_c·σs_c per unit length at a real collision and T_c on passing
// (the null-collision integral formulation of Galtier et al. 2013). Grey: P = ρ/m̄, the weights
// are the albedo and 1, as in delta tracking.
// Transmittance: ratio tracking (Novák et al. 2014), T_c = Π (1 − k_c·ρ_i/μ̄) over the
// tentative collisions; unbiased, never negative since k_c·ρ ≤ μ̄.
//
// Densities for MIS (docs/mis.md, "heterogeneous media"): the true free-flight density
// σt(x)·T(x) has no closed form, so every strategy uses the same deterministic stand-in,
//     scatter at x:  k̄·ρ(x)·exp(−k̄·τ̃),   pass:  exp(−k̄·τ̃),   τ̃ = ∫ ρ̃ dt over the piece,
// ρ̃ the mean density of each brick crossed, k̄ the mean of the channels' extinction
// coefficients: the homogeneous formula with a coarse optical depth. It is grey, the same in
// every channel: tracking draws its tentative distances with one rate for all channels, and
// which channel weighs the real/null choice (the caller's `channels`) then changes only the
// throughput weights, never a density, so MIS over strategies and channels (bdpt's hero
// channel) sees no channel ratio from a grid medium. (Per-channel stand-ins k_c·ρ·exp(−k_c·τ̃)
// made the bidirectional tracer's channel weights favour whichever channel the stand-ins
// favoured while its throughput followed the tracking's null weights: the coloured grid
// furnace had a heavy tail, worst pixels 0.83 at 2048 spp.) It is zero exactly where free
// flight cannot collide (ρ = 0), symmetric in the walk's direction, and additive over pieces,
// so the weights of every strategy still sum to one; its quality only affects the variance. (The majorant's optical depth was the first choice: in
// the strongly varying test furnace it made the stand-in far too small where bricks mix thick
// and thin, which moved MIS weight to the wrong strategies: pt at 256 spp on 8×8 pixels had
// pixel spreads 0.054–0.076 and worst pixels 1.14–1.37 with equi-angular connections, against
// 0.017–0.022 and 1.04–1.07 with the brick means.)
//
// Random numbers: the first tentative distance uses the caller's uDistance (so the sampler's
// stratification carries over); the rest, and ratio tracking's, come from a PCG stream seeded
// by a hash of the query's bits: deterministic whatever the thread count.
#include <cmath>
#include <cstring>
#include <limits>

#include "brume/sampling/sampler.h"
#include "brume/scene/density_grid.h"
#include "brume/scene/grid_tracking.h"
#include "brume/scene/medium.h"

namespace brume {

namespace {

using grid::advance;
using grid::hashQuery;
using grid::LocalRay;
using grid::sampleExp;
using grid::toLocal;

// The (grey) stand-in densities of a piece [t0, t1] whose brick-mean optical depth (grid units)
// is tau: fwd, of a walk from t0 stopping at t1 (scattering there if t1 is a medium point, else
// passing); rev, of the walk the other way.
void standIns(const DensityGrid& grid, const LocalRay& lr, Spectrum k, double tau, float t0, float t1,
              bool startIsPoint, bool endIsPoint, Channels* fwd, Channels* rev) {
    const double kbar = (double(k.x) + k.y + k.z) / 3;
    const double pass = std::exp(-kbar * tau);
    *fwd = Channels(endIsPoint ? kbar * grid.lookup(lr.q0 + lr.dq * t1) * pass : pass);
    *rev = Channels(startIsPoint ? kbar * grid.lookup(lr.q0 + lr.dq * t0) * pass : pass);
}

}  // namespace

float Medium::densityAt(Vec3 p) const {
    if (!heterogeneous()) return 1.0f;
    return density.grid->lookup(density.worldToLocal.point(p)) * density.scale;
}

MediumSample Medium::trackDistance(const Ray& ray, float t0, float t1, float uDistance, Spectrum channels,
                                   bool startIsPoint) const {
    const DensityGrid& grid = *density.grid;
    const LocalRay lr = toLocal(density, ray);
    const Spectrum k = sigmaT() * density.scale, ks = sigmaS * density.scale;
    const float kmax = std::max(k.x, std::max(k.y, k.z));
    const bool grey = this->grey();
    // The channel weights of the real/null choice: the caller's, the path throughput's in both
    // tracers (Kutz et al.'s history-aware choice: Σ_c β_c cannot grow at an event, so no
    // channel's weight compounds along the path). One-hot weights (a throughput with two black
    // channels) are mixed half and half with uniform ones, since with P = σt_h/μ̄ a tight
    // majorant (ρ → m̄) would drive the other channels' null weights (μ̄ − σt_c)/(μ̄ − σt_h)
    // without bound. Any choice keeps the weights unbiased for what was sampled, and enters no
    // density (the stand-ins are grey).
    const bool oneHot = std::max(channels.x, std::max(channels.y, channels.z)) >= 1.0f;
    const Spectrum w = oneHot ? (channels + Spectrum(1.0f / 3.0f)) * 0.5f : channels;
    Rng rng(hashQuery(ray, t0, t1, uDistance), 0x5eed);
    float u = uDistance;
    MediumSample ms;
    Spectrum W(1.0f);
    double tau = 0;  // ∫ ρ̃ dt so far (grid units; × k_c gives the stand-in's optical depth)
    float tHit = t1;
    bool real = false;
    if (kmax > 0) {
        grid.forEachMajorant(lr.q0, lr.dq, t0, t1, [&](float ta, float tb, float m, float mean) {
            if (m <= 0) return true;
            const float mu = kmax * m;
            float t = ta;
            for (;;) {
                const float s = sampleExp(mu, u);
                u = rng.next1D();
                if (!(t + s < tb)) {
                    tau += double(mean) * (tb - t);
                    return true;
                }
                tau += double(mean) * s;
                t = advance(t, s);
                const float rho = grid.lookup(lr.q0 + lr.dq * t);
                const float P = grey ? rho / m : (w.x * k.x + w.y * k.y + w.z * k.z) * rho / mu;
                const float uReal = rng.next1D();
                if (uReal < P) {
                    for (int c = 0; c < 3; ++c) W[c] *= grey ? ks[c] / k[c] : ks[c] * rho / (mu * P);
                    tHit = t;
                    real = true;
                    return false;
                }
                if (!grey)
                    for (int c = 0; c < 3; ++c) W[c] *= (mu - k[c] * rho) / (mu * (1 - P));
            }
        });
    }
    ms.scattered = real;
    ms.t = tHit;
    if (!real && std::isinf(t1)) {  // flew to infinity: nothing arrives (as in homogeneous media)
        ms.weight = Spectrum(0.0f);
        ms.fwd = ms.rev = Channels(0.0);
        ms.pdf = 0;
        return ms;
    }
    ms.weight = W;
    standIns(grid, lr, k, tau, t0, tHit, startIsPoint, real, &ms.fwd, &ms.rev);
    ms.pdf = ms.fwd[0];  // grey stand-ins: every mixture of channels gives the same
    return ms;
}

MediumTransit Medium::ratioTrack(const Ray& ray, float t0, float t1, bool startIsPoint, bool endIsPoint) const {
    const DensityGrid& grid = *density.grid;
    const LocalRay lr = toLocal(density, ray);
    const Spectrum k = sigmaT() * density.scale;
    const float kmax = std::max(k.x, std::max(k.y, k.z));
    MediumTransit tr;
    double tau = 0;
    // (An unbounded piece ends where the ray leaves the grid: the density is 0 beyond.)
    if (kmax > 0) {
        Rng rng(hashQuery(ray, t0, t1, 0.5f), 0x7a7);
        Spectrum T(1.0f);
        grid.forEachMajorant(lr.q0, lr.dq, t0, t1, [&](float ta, float tb, float m, float mean) {
            tau += double(mean) * (tb - ta);  // the whole piece, also once T is 0 (the stand-in needs it)
            if (m <= 0 || isBlack(T)) return true;
            const float mu = kmax * m;
            for (float t = ta;;) {
                t = advance(t, sampleExp(mu, rng.next1D()));
                if (!(t < tb)) return true;
                ++tr.steps;
                const float rho = grid.lookup(lr.q0 + lr.dq * t);
                for (int c = 0; c < 3; ++c) T[c] *= 1 - k[c] * rho / mu;
                // Russian roulette once every channel is below 1/16: kept with probability 1/2
                // and doubled, else 0 (E[T] unchanged). In a dense medium each tentative
                // collision then ends the estimate with probability about 1/2, so a ray's work
                // stays bounded whatever the density (without it T shrinks to 0 only through
                // the subnormals, after as many steps as the piece's optical depth).
                if (maxComponent(T) < 1.0f / 16) {
                    if (isBlack(T) || rng.next1D() < 0.5f) {
                        T = Spectrum(0.0f);
                        return true;  // (the pieces after still add to the stand-in's depth)
                    }
                    T *= 2.0f;
                }
            }
        });
        tr.T = T;
    }
    standIns(grid, lr, k, tau, t0, t1, startIsPoint, endIsPoint, &tr.fwd, &tr.rev);
    return tr;
}

}  // namespace brume
