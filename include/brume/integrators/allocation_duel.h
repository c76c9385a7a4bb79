// The planner's duel (allocation_planner.h): two allocations render whole passes in turn with
// the sampler the render uses, and the spread between batches of their passes measures the
// error each would have with that sampler, which no re-weighting of independent pilot
// samples can see (Owen-scrambled Sobol gave the path tracer 34× and the bidirectional tracer
// 3.9× at 64 spp on one lamp in fog).
//
// Why batches measure it. The sequence index of a pixel's numbers is the pass (sampler.h),
// shuffled by an Owen scramble, which keeps aligned blocks: the passes of an aligned batch of
// n = 2^k passes are a randomised net, and their mean is distributed as a render of n passes,
// with variance V(n). Two consecutive batches a, b that halve an aligned batch of 2n give
//   E[(a − b)²] / 2 = V(n) − Cov(a, b),   Cov(a, b) = 2·V(2n) − V(n) ≤ 0,
// from V(2n) = (2·V(n) + 2·Cov) / 4. So the estimate is V(n) + (V(n) − 2·V(2n)): exact for
// independent numbers (V(2n) = V(n)/2) and at most 1.75·V(n) for the fastest rate a
// scrambled net reaches, n^−3. It is an overestimate by the same bounded factor for both
// contenders, and their ratio is what the planner needs.
//
// Per pixel and channel the squared differences are weighted as the pilot's (1/(Ī² + ε):
// relative errors), at three batch sizes (1, 2 and 4 passes; from 4, 2 and 1 pairs of the
// 8 passes), whose ratios show how fast each contender's error falls.
//
// Heavy tails: a sum over pixels of so few pairs is at the mercy of one firefly (a shaded
// lamp over glass, single scattering: one pixel made a contender look 2.6× worse in one seed
// and the other 2.1× worse in the next). So the pixels are dealt into kGroups interleaved
// groups and the estimate is the median of the groups' sums times kGroups (median of means):
// a firefly moves one group.
//
// Cost: each contender's passes count their own work (PathStats::counts, path_stats.h), from which
// sample_cost.h gives the cost of one of its passes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "brume/integrators/integrator.h"
#include "brume/integrators/state_bytes.h"

namespace brume {

class AllocationDuel {
public:
    static constexpr int kLevels = 3;                 // batches of 1, 2 and 4 passes
    static constexpr int kPasses = 2 << (kLevels - 1);  // per contender: one pair of the largest batches
    static constexpr int kGroups = 9;                    // pixel groups of the median of means

    // The index-th pass (0 … kPasses − 1) of contender c (0 or 1): its image and the pixel
    // weights (3 values per pixel each). Passes come in order.
    void addPass(int c, int index, const std::vector<float>& image, const std::vector<float>& weights);
    int passes(int c) const { return passes_[c]; }
    // The weighted relative variance of the mean of 2^level passes of contender c, summed
    // over pixels and channels (see above: an overestimate by a factor of 1 to 1.75; the
    // median of the pixel groups' sums, times kGroups).
    double variance(int c, int level) const;
    // The counters of contender c's passes so far, and their samples.
    void addWork(int c, const PathStats& totals, double samples);
    // The cost of one pass of contender c, counted (sample_cost.h; the path tracer's or the
    // bidirectional tracer's weights); 0 before its first pass.
    double cost(int c, bool pathTracer) const;
    // Σ w·L over its passes, per pass: its weighted mean brightness.
    double mean(int c) const { return passes_[c] > 0 ? mean_[c] / passes_[c] : 0.0; }

    void save(std::string& out) const;
    void load(StateReader& reader, size_t values);  // std::runtime_error if malformed

private:
    std::vector<float> first_[kLevels];  // the first batch of the current pair, per level (sums)
    double squares_[2][kLevels][kGroups] = {};  // Σ w·(a − b)² over the pairs so far, per pixel group
    double mean_[2] = {};
    PathCounts counts_[2];
    double samples_[2] = {};
    int passes_[2] = {0, 0};
};

}  // namespace brume
