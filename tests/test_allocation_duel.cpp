// The planner's duel (allocation_duel.h): the spread between batches of passes measures the
// variance of a batch mean, for independent passes exactly and for stratified ones as the
// stratification makes it; and its state survives a save and load.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "brume/integrators/allocation_duel.h"
#include "brume/sampling/sampler.h"

using namespace brume;

namespace {

constexpr int kValues = 3 * 4000;

// Pass `index` of a contender whose every value is uniform on [0, 1) (variance 1/12), drawn
// independently, or from one Owen-scrambled Sobol sequence per value (indexed by the pass),
// whose mean over an aligned batch of n passes has variance (1/12)/n³.
std::vector<float> pass(int index, SamplerKind kind, uint64_t seed) {
    std::vector<float> v(kValues);
    for (int i = 0; i < kValues; ++i) v[size_t(i)] = Sampler(seed, uint64_t(i), uint64_t(index), kind).get1D(0);
    return v;
}

}  // namespace

TEST_CASE("duel: batch spreads measure the variance of batch means", "[auto][duel]") {
    const std::vector<float> weights(kValues, 1.0f);
    AllocationDuel duel;
    for (int i = 0; i < AllocationDuel::kPasses; ++i) duel.addPass(0, i, pass(i, SamplerKind::Independent, 3), weights);
    for (int i = 0; i < AllocationDuel::kPasses; ++i) duel.addPass(1, i, pass(i, SamplerKind::Sobol, 3), weights);
    for (int level = 0; level < AllocationDuel::kLevels; ++level) {
        // Independent: Σ over values of (1/12)/2^level, estimated from kPasses/2^(level+1)
        // pairs per value, as the median of kGroups group sums: relative standard error about
        // 1.25·√(2·kGroups/(pairs · kValues)) (the median's, below 10 %), bound 5σ.
        const int n = 1 << level, pairs = AllocationDuel::kPasses / (2 * n);
        const double rse = 1.25 * std::sqrt(2.0 * AllocationDuel::kGroups / (pairs * kValues));
        const double expected = kValues / 12.0 / n, se = expected * rse;
        INFO("batch of " << n << ": independent " << duel.variance(0, level) << ", expected " << expected << " ± " << se
                         << "; Sobol " << duel.variance(1, level) << ", expected " << 1.75 * expected / (n * n));
        CHECK(std::abs(duel.variance(0, level) - expected) < 5 * se);
        // Stratified: a uniform's mean over an aligned batch of n Owen-scrambled Sobol points
        // has variance (1/12)/n³, and a pair of sibling batches overestimates it by
        // V(n) − 2·V(2n) (allocation_duel.h): 1.75·(1/12)/n³, the bound's extreme.
        const double sobol = 1.75 * kValues / 12.0 / (n * n * n);
        CHECK(std::abs(duel.variance(1, level) - sobol) < 5 * sobol * rse);
    }
    CHECK(duel.mean(0) == Approx(kValues * 0.5).epsilon(0.01));
    // One firefly (a value 10⁴ in one pass) moves the sum but not the median of the groups.
    AllocationDuel firefly;
    for (int i = 0; i < AllocationDuel::kPasses; ++i) {
        std::vector<float> v = pass(i, SamplerKind::Independent, 3);
        if (i == 5) v[17] = 1e4f;
        firefly.addPass(0, i, v, weights);
    }
    CHECK(firefly.variance(0, 2) < 1.2 * duel.variance(0, 2));
    CHECK(duel.mean(1) == Approx(kValues * 0.5).epsilon(0.01));
}

TEST_CASE("duel: state survives a save and load midway, to the same numbers", "[auto][duel]") {
    const std::vector<float> weights(kValues, 0.5f);
    AllocationDuel straight, first;
    for (int i = 0; i < AllocationDuel::kPasses; ++i) straight.addPass(0, i, pass(i, SamplerKind::Sobol, 7), weights);
    for (int i = 0; i < 3; ++i) first.addPass(0, i, pass(i, SamplerKind::Sobol, 7), weights);
    std::string state;
    first.save(state);
    AllocationDuel second;
    StateReader reader{state};
    second.load(reader, kValues);
    CHECK(reader.at == state.size());
    for (int i = 3; i < AllocationDuel::kPasses; ++i) second.addPass(0, i, pass(i, SamplerKind::Sobol, 7), weights);
    for (int level = 0; level < AllocationDuel::kLevels; ++level) CHECK(second.variance(0, level) == straight.variance(0, level));
    AllocationDuel bad;
    const std::string truncated = state.substr(0, state.size() - 1);
    StateReader cut{truncated};
    CHECK_THROWS_AS(bad.load(cut, kValues), std::runtime_error);
}
