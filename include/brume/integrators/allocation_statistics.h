// The statistics behind the efficiency-aware tracer (allocation_planner.h): from the samples
// of the pilot allocation, the second moment each candidate allocation would have.
//
// For the balance heuristic, a multi-sample MIS estimator whose strategies k are made n_k
// times per sample (n_k may be a probability) has per-sample second moment
//   M(n) = ∫ f(x)² / Σ_k n_k p_k(x) dx
// (Veach 1997, §9.2; Grittmann et al. 2022 use it to compare allocations). The pilot samples
// x from strategy t with expected count n_t, so for any candidate n'
//   E[ Σ over the pilot's samples (f/p_t)² · u_t(n) · u_t(n') ] = M(n'),   u_t(n) = p_t / Σ_k n_k p_k,
// where f/p_t is the sample's unweighted contribution and u_t the weight per unit count that
// misWeight gives as perCount. A candidate that leaves some pilot sample with no strategy
// (Σ n'_k p_k = 0) gets an infinite moment: it would be biased, and is never chosen.
//
// The variance of a pixel is E[(Σ_r e_r)²] − (its mean)², the sum over a sample's weighted
// contributions e_r to it. The mean is every unbiased candidate's; E[Σ_r e_r²] is M above;
// the products of two contributions of one sample, C = E[Σ_{r≠r'} e_r·e_r'], are taken from
// the pilot's sample as each candidate would weight them (every candidate makes its
// strategies from the same subpaths and numbers; one it leaves out counts 0, a general
// connection made with another probability by the ratio). So V_candidate − V_pilot =
// (M + C)_candidate − (M + C)_pilot. Without C the estimate missed what sharing a mean costs:
// where the free-flight and equi-angular variants of one connection split a nearly exact
// integral, or where a free-flight vertex and the emitter hit behind it are two outcomes of
// one walk (on a lamp in thin fog it rated the ea-only allocation 1.33× noisier than with both
// variants; it was 0.86× as noisy).
#pragma once
#include <vector>

#include "brume/integrators/bdpt_mis.h"
#include "brume/integrators/path_stats.h"
#include "brume/integrators/path_vertex.h"

namespace brume {

struct BdptAllocation;

// One weighted contribution of a sample, with what its weight needs to be recomputed.
struct WeightRecord {
    int s = 0, t = 0;
    StrategyJoin join;
    Spectrum value;      // unweighted, for one sample of the strategy
    int x = -1, y = -1;  // the pixel it lands in (−1: the sample's own)
    bool moved = false;  // `vertex` is its equi-angular vertex, standing in for camera[t−1]
    PathVertex vertex;   // (t ≥ 2) or light[s−1] (t = 1)
    bool hasLightVertex = false;  // s = 1: `lightVertex` is the sampled light vertex y0
    PathVertex lightVertex;
    // A free-flight light or camera connection at a medium vertex that its equi-angular
    // variant (on) could have made: an ea-only allocation would not make it.
    bool replaceable = false;
};

// Per pixel and channel, the weight 1 / (I² + ε) that turns squared error into relative
// squared error (I: a smooth estimate of the pixel's value).
struct PixelWeights {
    int width = 0, height = 0;
    const float* w = nullptr;  // 3 per pixel, row-major
    const float* at(int x, int y) const { return w + 3 * (size_t(y) * size_t(width) + size_t(x)); }
};

// Adds to sums[j], for every candidate j, Σ over `records` of Σ_c w_c · value_c² · u(pilot) · u(candidate j)
// (balance heuristic, the allocations' counts). The sample's subpaths get their MIS sums
// recomputed for seven settings that give every candidate's weights (they are left with the
// last one's).
void accumulateMoments(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight,
                       MisSettings pilot, const std::vector<BdptAllocation>& candidates,
                       const std::vector<WeightRecord>& records, const PixelWeights& weights, int ownX, int ownY,
                       AllocationMoments& moments);

}  // namespace brume
