// The statistics behind the efficiency-aware tracer (allocation_planner.h): from the samples
// of the pilot allocation, the second moment each candidate allocation would have.
//
// A multi-sample MIS estimator whose strategies k are made n_k times per sample (n_k may be a
// probability), with weights w_k, has per-sample second moment
//   M(n) = Σ_k ∫ w_k(x)² f(x)² / (n_k p_k(x)) dx
// (Veach 1997, §9.2; for the balance heuristic it is ∫ f² / Σ_k n_k p_k, which Grittmann et
// al. 2022 use to compare allocations). The pilot makes every strategy any candidate makes,
// from the same subpaths and numbers, so its sample x of strategy t (made n_t times) is one
// the candidate's strategy t would draw. M(n') is estimated two ways (docs/mis.md):
//   alone:    Σ over the pilot's samples of (f/p_t)² · w'_t² / (n_t n'_t), f/p_t the sample's
//             unweighted contribution and w'_t the candidate's weight for it (the render's
//             heuristic, the candidate's counts): unbiased whatever densities the weights
//             use, but blind to rare large values that the pilot's other strategies carry;
//   combined: through the pilot's own weights, each sample an estimate of ∫ G with
//             G(x) = Σ_τ w'_τ² f² / (n'_τ p_τ) = f² T'_{2β−1} / (p_t T'_β²) (T below): sees
//             those values where other strategies find them often, but reads the densities
//             the weights use (a light connection that samples an area light by solid angle
//             is weighted by its area density: ea-only allocations 1.2–1.45× too noisy).
// A candidate that leaves some pilot sample with no strategy (Σ n'_k p_k = 0) gets an
// infinite moment: it would be biased, and is never chosen.
//
// The variance of a pixel in one pass is Σ over the samples that reach it (its own, and
// others' light-tracing splats) of E[g²] − E[g]², g = Σ_r e_r the sample's weighted
// contributions e_r to it. E[Σ_r e_r²] is M above; the products of two contributions of one
// sample, C = E[Σ_{r≠r'} e_r·e_r'], are taken from the pilot's sample as each candidate would
// weight them (one it leaves out counts 0, a general connection made with another
// probability by the ratio). Without C the estimate missed what sharing a mean costs: where
// the free-flight and equi-angular variants of one connection split a nearly exact integral,
// or where a free-flight vertex and the emitter hit behind it are two outcomes of one walk (on
// a lamp in thin fog it rated the ea-only allocation 1.33× noisier than with both variants; it
// was 0.86× as noisy). E[g]² is the square of the part of the pixel's value its own sample
// carries (a splat's part in one pixel is negligible); that part differs between candidates
// that split the light differently between a pixel's own sample and light tracing, so each
// candidate's own part is summed per recording pixel too (ownParts, allocation_planner.h).
// So V_candidate − V_pilot = (M + C − Σ E[g_own]²)_candidate − (the same)_pilot.
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

// Adds to moments.candidate[g][j] and moments.combined[g][j] (g: the group of (ownX, ownY)), for
// every candidate j, its M + C over
// `records` (above; M alone and combined), each contribution weighted by w_c of the pixel it
// lands in; and to own[3j + c], if given, the
// candidate's weighted contributions to the sample's own pixel (ownX, ownY), channel c. The
// sample's subpaths get their MIS sums recomputed for seven settings that give every
// candidate's weights (they are left with the last one's).
void accumulateMoments(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight,
                       MisSettings pilot, const std::vector<BdptAllocation>& candidates,
                       const std::vector<WeightRecord>& records, const PixelWeights& weights, int ownX, int ownY,
                       AllocationMoments& moments, float* own = nullptr);

}  // namespace brume
