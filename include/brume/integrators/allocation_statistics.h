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
#pragma once
#include <vector>

#include "brume/integrators/bdpt_mis.h"
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
// recomputed for five settings that give every candidate's weights (they are left with the
// last one's).
void accumulateMoments(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight,
                       MisSettings pilot, const std::vector<BdptAllocation>& candidates,
                       const std::vector<WeightRecord>& records, const PixelWeights& weights, int ownX, int ownY,
                       double* sums);

}  // namespace brume
