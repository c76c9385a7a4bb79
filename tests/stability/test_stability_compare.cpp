// The stability table's own numbers (stability_compare.h) on made-up runs: the median of
// means fails an image 58 % too dark whose heavy tail keeps the mean's z near −1, and passes
// the same tail without the bias.
#include <catch2/catch.hpp>

#include <random>

#include "stability/stability_compare.h"

using namespace brume;
using namespace brume::test;

namespace {

// A one-block 4×4 image over 32 batches: each batch's pixels are `base`, and with
// probability `p` a batch carries a rare value that makes its mean `spike`.
StabilityRun madeUpRun(double base, double spike, double p, uint32_t seed) {
    StabilityRun run;
    run.width = run.height = run.block = 4;
    run.batches = 32;
    run.sppPerBatch = 1;
    run.blocks.resize(1);
    run.batchPixels.resize(size_t(run.batches) * 16);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int b = 0; b < run.batches; ++b) {
        const double v = (u(rng) < p ? spike : base) * (0.95 + 0.1 * u(rng));
        for (int i = 0; i < 16; ++i) run.batchPixels[size_t(b) * 16 + size_t(i)] = v;
        for (int c = 0; c < 3; ++c) run.blocks[0].sum[c] += v, run.blocks[0].sum2[c] += v * v;
        ++run.blocks[0].n;
    }
    return run;
}

}  // namespace

TEST_CASE("stability compare: the median of means fails a biased image with a heavy tail", "[stability]") {
    const std::vector<bool> unmasked(1, false);
    // The reference: mean about 1 (base 0.5, a spike of 16.5 in about 1 batch of 32).
    const StabilityRun reference = madeUpRun(0.5, 16.5, 1.0 / 32.0, 7);
    // 58 % too dark, with a tail of its own that lands in this run: its mean z stays small.
    const StabilityRun biased = madeUpRun(0.21, 16.5, 1.0 / 32.0, 8);
    const Comparison c = compareRuns(biased, reference, unmasked);
    INFO("z mean " << c.zMean << ", bias " << c.relBias << ", median of means " << c.relMedianOfMeans);
    CHECK(std::abs(c.zMean) < 5.0);  // what the mean's z alone (the suite's kZ) would let through
    CHECK(std::abs(c.relMedianOfMeans) > 0.5);  // what the median of means sees
    const StabilityRun fair = madeUpRun(0.5, 16.5, 1.0 / 32.0, 9);
    const Comparison d = compareRuns(fair, reference, unmasked);
    INFO("unbiased: z mean " << d.zMean << ", median of means " << d.relMedianOfMeans);
    CHECK(std::abs(d.relMedianOfMeans) < 0.2);
}
