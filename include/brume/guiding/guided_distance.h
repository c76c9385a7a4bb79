// Guided distances (docs/path-guiding.md, "Guided distances"): on a piece [0, len] of a
// camera-walk ray in a homogeneous grey medium (σt, σs), a collision is drawn either by free
// flight or, with probability β (the share), in proportion to T(t)·S(t), S what the field
// learned a medium vertex gathers per unit of throughput there (GuidingCell::inscatter: its
// next-event estimate plus its continuation), constant over each leaf the ray crosses.
//
// Both techniques collide with the same probability 1 − T(len) and pass the piece otherwise,
// so a pass keeps the weight T/P = 1 of free flight. A collision at t in the interval k has the
// one-sample mixture density
//     p(t) = T(t)·[(1 − β)·σt + β·c_k],   c_k = (1 − T(len))·S_k / Z,   Z = Σ_j S_j·W_j,
// W_j = ∫_j T(t) dt, and the weight T·σs / p = σs / [(1 − β)·σt + β·c_k] ≤ albedo / (1 − β).
// With S the same everywhere c_k = σt: the guided technique is free flight.
//
// The share is chosen per piece from what the cells learned, by the second moment each β
// predicts for the vertex's contribution X (M2_k: the cell's mean X²):
//     M(β) = Σ_k W_k·M2_k / [(1 − β)·σt + β·c_k]      (times σs², the same for every β)
// among {0, 1/4, 1/2}; β > 0 only where it lowers M(0) by a tenth (a guided piece costs a
// walk down the tree). Leaves without enough medium records, and the parts of the ray
// outside the tree, take the W-weighted mean of the known cells' S and M2.
#pragma once
#include "brume/guiding/guiding_field.h"

namespace brume {

struct GuidedDistanceSample {
    bool scattered = false;
    float t = 0;        // within the piece (len when it passes)
    double pdf = 0;     // p(t), or the pass probability T(len)
    float weight = 1;   // T·σs / p per unit σs (multiply by σs), or 1 for a pass
};

class GuidedDistance {
public:
    static constexpr int kMaxIntervals = 32;
    // forcedShare ≥ 0: that share wherever the field knows the piece (tests).
    static GuidedDistance on(const GuidingField* field, Vec3 o, Vec3 d, float len, float sigmaT, float forcedShare = -1);

    float share() const { return share_; }
    double pdf(float t) const;  // the mixture's collision density at t ∈ [0, len)
    // One number: u < β chooses the guided technique, each technique reads u rescaled.
    GuidedDistanceSample sample(float u) const;

private:
    int interval(float t) const;
    double transmittance(double t) const { return std::exp(-double(sigmaT_) * t); }

    float share_ = 0, sigmaT_ = 0, len_ = 0;
    double pass_ = 1;    // T(len)
    double z_ = 0;       // Σ S_k W_k
    int n_ = 0;
    float bound_[kMaxIntervals + 1];   // interval k is [bound_k, bound_k+1]
    float s_[kMaxIntervals];           // S_k
    double cdf_[kMaxIntervals + 1];    // Σ_{j<k} S_j W_j
};

}  // namespace brume
