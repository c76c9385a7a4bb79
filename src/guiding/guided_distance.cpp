#include "brume/guiding/guided_distance.h"

#include <algorithm>
#include <cmath>

namespace brume {

namespace {

constexpr float kShares[] = {0.25f, 0.5f};
constexpr double kGuidingCost = 0.1;

// ∫_a^b e^(−σt) dt (b may be infinite).
double integralOfT(double sigma, double a, double b) {
    return std::exp(-sigma * a) * -std::expm1(-sigma * (b - a)) / sigma;
}

}  // namespace

GuidedDistance GuidedDistance::on(const GuidingField* field, Vec3 o, Vec3 d, float len, float sigmaT, float forcedShare) {
    GuidedDistance g;
    if (!field || !(sigmaT > 0) || !(len > 0)) return g;
    GuidingField::Interval leaves[kMaxIntervals - 2];
    const int count = field->along(o, d, len, leaves, kMaxIntervals - 2);
    if (count <= 0) return g;  // outside the tree, or more leaves than the table holds
    g.sigmaT_ = sigmaT;
    g.len_ = len;
    const double sigma = sigmaT;
    // The intervals tile [0, len]: the leaves, with the parts before and after the tree.
    // known: the cell learned S there (−1 in s_ marks the rest until the mean is known).
    double m2[kMaxIntervals], w[kMaxIntervals];
    auto push = [&](float a, float b, const GuidingCell* cell) {
        if (!(b > a)) return;
        const int k = g.n_++;
        g.bound_[k] = a;
        g.bound_[k + 1] = b;
        const bool known = cell && cell->inscatter >= 0;
        g.s_[k] = known ? cell->inscatter : -1.0f;
        m2[k] = known ? cell->inscatter2 : -1.0;
        w[k] = integralOfT(sigma, a, b);
    };
    float at = 0;
    for (int i = 0; i < count; ++i) {
        const float a = std::max(leaves[i].t0, at), b = std::min(leaves[i].t1, len);
        push(at, a, nullptr);
        push(a, b, leaves[i].cell);
        at = std::max(at, b);
    }
    push(at, len, nullptr);
    // The unknown intervals take the W-weighted mean of the known ones.
    double wKnown = 0, sKnown = 0, m2Known = 0;
    for (int k = 0; k < g.n_; ++k)
        if (g.s_[k] >= 0) {
            wKnown += w[k];
            sKnown += w[k] * g.s_[k];
            m2Known += w[k] * m2[k];
        }
    if (!(wKnown > 0) || !(sKnown > 0)) return GuidedDistance{};
    g.cdf_[0] = 0;
    for (int k = 0; k < g.n_; ++k) {
        if (g.s_[k] < 0) {
            g.s_[k] = float(sKnown / wKnown);
            m2[k] = m2Known / wKnown;
        }
        g.cdf_[k + 1] = g.cdf_[k] + g.s_[k] * w[k];
    }
    g.z_ = g.cdf_[g.n_];
    g.pass_ = std::isinf(len) ? 0.0 : g.transmittance(len);
    if (!(g.z_ > 0) || !std::isfinite(g.z_) || !(g.pass_ < 1)) return GuidedDistance{};

    // The share: M(β) = Σ_k W_k·M2_k / [(1 − β)σt + β c_k] (guided_distance.h).
    const double scale = (1.0 - g.pass_) / g.z_;
    auto moment = [&](double beta) {
        double m = 0;
        for (int k = 0; k < g.n_; ++k) m += w[k] * m2[k] / ((1.0 - beta) * sigma + beta * scale * g.s_[k]);
        return m;
    };
    if (forcedShare >= 0) {
        g.share_ = std::min(forcedShare, 0.9f);
    } else {
        const double m0 = moment(0.0);
        double best = (1.0 - kGuidingCost) * m0;
        for (float beta : kShares) {
            const double m = moment(beta);
            if (m < best) {
                best = m;
                g.share_ = beta;
            }
        }
    }
    if (!(g.share_ > 0)) return GuidedDistance{};
    return g;
}

int GuidedDistance::interval(float t) const {
    const int k = int(std::upper_bound(bound_ + 1, bound_ + n_, t) - (bound_ + 1));
    return std::min(k, n_ - 1);
}

double GuidedDistance::pdf(float t) const {
    const double c = (1.0 - pass_) * s_[interval(t)] / z_;
    return transmittance(t) * ((1.0 - share_) * sigmaT_ + share_ * c);
}

GuidedDistanceSample GuidedDistance::sample(float u) const {
    GuidedDistanceSample s;
    const double sigma = sigmaT_;
    double t;
    if (u < share_) {  // ∝ T·S, colliding with probability 1 − T(len)
        const double v = std::min(double(u) / share_, 1.0);
        if (v >= 1.0 - pass_) {
            t = len_;
        } else {
            const double target = v / (1.0 - pass_) * z_;
            int k = int(std::upper_bound(cdf_ + 1, cdf_ + n_, target) - (cdf_ + 1));
            while (k < n_ - 1 && !(s_[k] > 0)) ++k;  // (only a zero-width step of the sum)
            const double a = bound_[k], b = bound_[k + 1];
            const double r = std::clamp((target - cdf_[k]) / std::max(cdf_[k + 1] - cdf_[k], 1e-300), 0.0, 1.0);
            // Within [a, b] ∝ e^(−σt): invert ∫_a^t.
            t = a - std::log1p(-r * -std::expm1(-sigma * (b - a))) / sigma;
            t = std::clamp(t, a, std::nextafter(b, a));
        }
    } else {  // free flight
        const double v = std::min((double(u) - share_) / (1.0 - share_), 0x1.fffffffffffffp-1);
        t = -std::log1p(-v) / sigma;
    }
    if (!(t < len_)) {
        s.t = len_;
        s.pdf = pass_;
        return s;
    }
    s.scattered = true;
    s.t = float(t);
    if (!(s.t < len_)) s.t = std::nextafter(len_, 0.0f);
    const double c = (1.0 - pass_) * s_[interval(s.t)] / z_;
    s.pdf = transmittance(s.t) * ((1.0 - share_) * sigma + share_ * c);
    s.weight = float(1.0 / ((1.0 - share_) * sigma + share_ * c));
    return s;
}

}  // namespace brume
