#include "brume/integrators/allocation_duel.h"

#include "brume/integrators/sample_cost.h"

#include <algorithm>
#include <stdexcept>

namespace brume {

void AllocationDuel::addPass(int c, int index, const std::vector<float>& image, const std::vector<float>& weights) {
    if (index == 0)
        for (std::vector<float>& f : first_) f.assign(image.size(), 0.0f);
    for (size_t i = 0; i < image.size(); ++i) mean_[c] += double(weights[i]) * double(image[i]);
    // The batch of 2^level passes that this pass completes, level by level: a first half is
    // kept; a second half is compared with it, and the two make the next level's batch.
    std::vector<float> batch = image;
    for (int level = 0; level < kLevels; ++level) {
        const int size = 1 << level;
        if ((index + 1) % size != 0) break;
        if ((index / size) % 2 == 0) {
            first_[level] = batch;
            break;
        }
        for (size_t i = 0; i < batch.size(); ++i) {
            const double d = (double(batch[i]) - double(first_[level][i])) / size;  // of the means
            squares_[c][level][(i / 3) % kGroups] += double(weights[i]) * d * d;
            batch[i] += first_[level][i];
        }
    }
    passes_[c] = index + 1;
}

void AllocationDuel::addWork(int c, const PathStats& totals, double samples) {
    counts_[c].add(totals.counts);
    samples_[c] += samples;
}

double AllocationDuel::cost(int c, bool pathTracer) const {
    if (passes_[c] == 0) return 0.0;
    const PathCounts& n = counts_[c];
    // (The bidirectional tracer's single-scattering split, one_event_split.h, counts its camera
    // family as the path tracer and its light tracing as the bidirectional tracer does.)
    const bool split = !pathTracer && n.pt.samples > 0;
    if (pathTracer || split) return (pathTracerCost(n.pt) + (split ? bidirectionalCost(n.bdpt, 0.0) : 0.0)) / passes_[c];
    return bidirectionalCost(n.bdpt, samples_[c]) / passes_[c];
}

// Pairs of 2^level-pass batches in kPasses passes: kPasses / 2^(level+1); each gives 2·V.
double AllocationDuel::variance(int c, int level) const {
    const int pairs = kPasses >> (level + 1);
    double groups[kGroups];
    std::copy(squares_[c][level], squares_[c][level] + kGroups, groups);
    std::nth_element(groups, groups + kGroups / 2, groups + kGroups);
    return groups[kGroups / 2] * kGroups / (2.0 * pairs);
}

// State: i32 passes × 2, f64 squares × 2·kLevels·kGroups, f64 mean × 2, u64 counts ×
// 2·PathCounts::kCount, f64 samples × 2, then per level (u64 n, n f32).
void AllocationDuel::save(std::string& out) const {
    for (int p : passes_) putBytes(out, int32_t(p));
    for (const auto& row : squares_)
        for (const auto& level : row)
            for (double v : level) putBytes(out, v);
    for (double m : mean_) putBytes(out, m);
    for (const PathCounts& counts : counts_) counts.forEach([&](uint64_t v) { putBytes(out, v); });
    for (double v : samples_) putBytes(out, v);
    for (const std::vector<float>& f : first_) putVector(out, f);
}

void AllocationDuel::load(StateReader& r, size_t values) {
    for (int& p : passes_) {
        p = r.get<int32_t>();
        if (p < 0 || p > kPasses) throw std::runtime_error("allocation state is malformed");
    }
    for (auto& row : squares_)
        for (auto& level : row)
            for (double& v : level) v = r.get<double>();
    for (double& m : mean_) m = r.get<double>();
    for (PathCounts& counts : counts_) counts.forEach([&](uint64_t& v) { v = r.get<uint64_t>(); });
    for (double& v : samples_) {
        v = r.get<double>();
        if (!(v >= 0)) throw std::runtime_error("allocation state is malformed");
    }
    for (std::vector<float>& f : first_) {
        f = r.getVector<float>(values);
        if (!f.empty() && f.size() != values) throw std::runtime_error("allocation state is malformed");
    }
}

}  // namespace brume
