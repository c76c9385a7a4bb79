// The Henyey–Greenstein phase per unit scattering *angle*: the phase part of product sampling
// along a ray towards a point (equi-angular × phase, docs/path-tracer.md "Product sampling").
//
// On the ray o + t·d passing a point c (closest approach at t = Δ, distance D), equi-angular
// sampling's angle u = atan((t − Δ)/D) and the scattering angle θ at x(t), between d and the
// direction from x(t) to c, are related by θ = u + π/2 (cos θ = (Δ − t)/r = −sin u). The 1/r²
// falloff is uniform in u, so what is left to sample is HG(cos θ) dθ on [θa, θb]: per unit
// angle, not per solid angle, so HG's own inverse does not apply; its integral is elliptic.
//
// With w = sin(θ/2) (g ≥ 0; for g < 0, HG(cos θ; g) = HG(cos θ'; |g|) with θ' = π − θ, and
// w = cos(θ/2)):
//   1 + g² − 2g cos θ = c² + k w²  (c = 1 − |g|, k = 4|g|),   dθ = 2 dw / sqrt(1 − w²),
// so HG dθ ∝ (c² + k w²)^(−3/2) · 2/sqrt(1 − w²) dw. Without the last factor (≥ 1, and 1 at the
// forward peak) the density has a closed-form cdf:
//   ∫ (c² + k w²)^(−3/2) dw = S(w) / (c²√k),   S(w) = √k w / sqrt(c² + k w²) ∈ [0, 1),
// inverted by w = c S / (√k sqrt(1 − S²)). Per unit θ this "phase part" is ∝ HG · cos(θ'/2):
// exact at the forward peak, too thin towards θ' = π, where HG is smallest. A defensive
// mixture with uniform-in-angle sampling (plain equi-angular), weight α = max(1 − |g|, 0.1),
// bounds target / proposal everywhere (variance within 1.5× of the ideal on every span tried,
// where plain equi-angular is up to 160× off at g = 0.99); g = 0 gives α = 1, plain equi-angular.
// So does |g| < kPlainBelow: at g = 0.1 (single scattering, pt, relative variance from seed
// pairs) plain equi-angular had 1/2.4–1/6.6 of the product's in the fog room at 16–200 spp,
// 1/1.5–1/1.6 on the thin lamp made g = 0.1 and 1/1.02–1/1.08 on the doorway made g = 0.1; at
// g = 0.2 the fog room still 1/1.3–1/1.6 and the thin lamp even; at 0.3 the product 1.4–1.6×
// better on both (docs/results.md). The phase part's share of u is sampled as a second turn
// of t (equiangular.cpp), which Sobol numbers stratify poorly when it is small.
#pragma once

namespace brume {

constexpr double kPlainBelow = 0.15;

// A scattering angle by its half-angle squares: sin²(θ/2) = (1 − cos θ)/2, cos²(θ/2) = (1 + cos θ)/2,
// each computed without cancellation (both are needed near θ = 0 and θ = π).
struct HalfAngle {
    double sin2 = 0, cos2 = 1;
};

// The scattering angle at x(t) towards c, from x = t − Δ and D (+∞ allowed for x).
HalfAngle halfAngleAt(double x, double D);

// x = t − Δ of the point whose scattering angle is h: x = −D cos θ / sin θ.
double offsetAt(HalfAngle h, double D);

// The phase part on the angle span between two ends (in any order).
struct HgAngle {
    double alpha = 1;      // weight of the uniform-in-angle part; 1: no phase part
    bool mirror = false;   // g < 0: w = cos(θ/2)
    double c = 1, k = 0, rootK = 0;
    double sLo = 0, sHi = 0;  // S at the span's ends, sLo < sHi
};

// |g| is clamped to 0.9999 (a proposal only: any deterministic choice keeps densities exact).
// Falls back to α = 1 when the phase part's span is empty to rounding.
HgAngle makeHgAngle(double g, HalfAngle end0, HalfAngle end1);

// The phase part's density per unit θ at h (h within the span), its cdf in S, and its
// sample for ξ ∈ [0, 1).
double hgAnglePhasePdf(const HgAngle& p, HalfAngle h);
double hgAnglePhaseCdf(const HgAngle& p, HalfAngle h);
HalfAngle sampleHgAnglePhase(const HgAngle& p, double xi);

}  // namespace brume
