#include "brume/sampling/hg_angle.h"

#include <algorithm>
#include <cmath>

namespace brume {

namespace {

// w² and 1 − w² of the half angle, w = sin(θ/2) or cos(θ/2) (mirrored).
double w2Of(const HgAngle& p, HalfAngle h) { return p.mirror ? h.cos2 : h.sin2; }
double oneMinusW2Of(const HgAngle& p, HalfAngle h) { return p.mirror ? h.sin2 : h.cos2; }

double sOf(const HgAngle& p, double w2) { return p.rootK * std::sqrt(w2) / std::sqrt(p.c * p.c + p.k * w2); }

}  // namespace

// With s = Δ − t = −x and r = sqrt(D² + x²): cos θ = s / r, and
//   1 − cos θ = (r − s)/r = D² / (r (r + s)),   1 + cos θ = (r + s)/r = D² / (r (r − s)),
// each used where it has no cancellation.
HalfAngle halfAngleAt(double x, double D) {
    if (std::isinf(x)) return x > 0 ? HalfAngle{1, 0} : HalfAngle{0, 1};
    const double s = -x, r = std::hypot(D, x);
    if (!(r > 0)) return HalfAngle{0.5, 0.5};
    const double oneMinus = s > 0 ? D * D / (r * (r + s)) : (r - s) / r;
    const double onePlus = s < 0 ? D * D / (r * (r - s)) : (r + s) / r;
    return HalfAngle{0.5 * oneMinus, 0.5 * onePlus};
}

// cos θ = cos²(θ/2) − sin²(θ/2), sin θ = 2 sin(θ/2) cos(θ/2).
double offsetAt(HalfAngle h, double D) {
    const double sinTheta = 2.0 * std::sqrt(h.sin2 * h.cos2);
    const double cosTheta = h.cos2 - h.sin2;
    if (!(sinTheta > 0)) return cosTheta > 0 ? -INFINITY : INFINITY;
    return -D * cosTheta / sinTheta;
}

HgAngle makeHgAngle(double g, HalfAngle end0, HalfAngle end1) {
    HgAngle p;
    const double ag = std::min(std::abs(g), 0.9999);
    // Below kPlainBelow plain equi-angular (α = 1), as at g = 0: there HG varies by at most
    // ((1 + |g|)/(1 − |g|))³ ≈ 2.5 over a ray, and the phase part's share of u, sampled as a
    // second turn of t, costs more of the Sobol numbers' stratification than it gives (hg_angle.h).
    if (!(ag >= kPlainBelow)) return p;
    p.alpha = std::max(1.0 - ag, 0.1);
    p.mirror = g < 0;
    p.c = 1.0 - ag;
    p.k = 4.0 * ag;
    p.rootK = std::sqrt(p.k);
    double s0 = sOf(p, w2Of(p, end0)), s1 = sOf(p, w2Of(p, end1));
    p.sLo = std::min(s0, s1);
    p.sHi = std::max(s0, s1);
    if (!(p.sHi - p.sLo > 1e-12)) p.alpha = 1;  // no span left: plain equi-angular
    return p;
}

// Density in w (h within the span): dS/dw / (sHi − sLo) = √k c² (c² + k w²)^(−3/2) / (sHi − sLo); per unit θ times
// dw/dθ = sqrt(1 − w²)/2.
double hgAnglePhasePdf(const HgAngle& p, HalfAngle h) {
    if (p.alpha >= 1) return 0;
    const double w2 = w2Of(p, h);
    const double q = p.c * p.c + p.k * w2;
    return p.rootK * p.c * p.c / (q * std::sqrt(q)) / (p.sHi - p.sLo) * 0.5 * std::sqrt(oneMinusW2Of(p, h));
}

double hgAnglePhaseCdf(const HgAngle& p, HalfAngle h) {
    if (p.alpha >= 1) return 0;
    return std::clamp((sOf(p, w2Of(p, h)) - p.sLo) / (p.sHi - p.sLo), 0.0, 1.0);
}

// S uniform in [sLo, sHi]; w² = c² S² / (k (1 − S²)), and, with k + c² = (1 + |g|)²,
// 1 − w² = (k − (1 + |g|)² S²) / (k (1 − S²)).
HalfAngle sampleHgAnglePhase(const HgAngle& p, double xi) {
    const double S = std::min(p.sLo + xi * (p.sHi - p.sLo), p.sHi);
    const double oneMinusS2 = (1.0 - S) * (1.0 + S);
    const double w2 = std::min(1.0, p.c * p.c * S * S / (p.k * oneMinusS2));
    const double onePlusG = 2.0 - p.c;
    const double rest = std::max(0.0, (p.k - onePlusG * onePlusG * S * S) / (p.k * oneMinusS2));
    return p.mirror ? HalfAngle{rest, w2} : HalfAngle{w2, rest};
}

}  // namespace brume
