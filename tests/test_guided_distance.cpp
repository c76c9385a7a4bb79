// Guided distances (guided_distance.h) on a hand-made field: the leaves a ray crosses, in
// order, in both directions; the sampler follows its density (chi-square, with the pass
// probability T(len) as the outside bin), and a free-flight density in its place fails; the
// weight is T / p at every sample, so the estimate is unbiased; the share is learned: none
// where every cell learned the same, some where they differ tenfold.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/guiding/guided_distance.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

// The box [0, 4] × [−1, 1]²: x < 1 → cell 0; 1 ≤ x < 2.5 → cell 1; x ≥ 2.5 → a leaf with too
// few records (no cell).
GuidingField handMade(float s0, float s1) {
    using Node = GuidingField::Node;
    std::vector<Node> nodes{Node{1.0f, 0, 1}, Node{0, 3, 0}, Node{2.5f, 0, 3}, Node{0, 3, 1},
                            Node{0, 3, GuidingField::kNoCell}};
    std::vector<GuidingCell> cells(2);
    cells[0].inscatter = s0;
    cells[0].inscatter2 = 4 * s0 * s0;
    cells[1].inscatter = s1;
    cells[1].inscatter2 = 4 * s1 * s1;
    GuidingField f;
    f.assign(Vec3(0, -1, -1), Vec3(4, 1, 1), nodes, cells);
    return f;
}

}  // namespace

TEST_CASE("guiding field: the leaves a ray crosses, in order", "[guiding]") {
    const GuidingField f = handMade(1, 10);
    GuidingField::Interval iv[8];
    // From x = −1 along +x: [1, 2] cell 0, [2, 3.5] cell 1, [3.5, 5] no cell.
    int n = f.along(Vec3(-1, 0.1f, 0), Vec3(1, 0, 0), 10.0f, iv, 8);
    REQUIRE(n == 3);
    CHECK(iv[0].t0 == Approx(1));
    CHECK(iv[0].t1 == Approx(2));
    CHECK(iv[0].cell == &f.cells()[0]);
    CHECK(iv[1].t1 == Approx(3.5));
    CHECK(iv[1].cell == &f.cells()[1]);
    CHECK(iv[2].t1 == Approx(5));
    CHECK(iv[2].cell == nullptr);
    // Backwards from x = 3, cut at t = 2.5 (x = 0.5): the leaf without a cell, cell 1, cell 0.
    n = f.along(Vec3(3, 0.1f, 0), Vec3(-1, 0, 0), 2.5f, iv, 8);
    REQUIRE(n == 3);
    CHECK(iv[0].cell == nullptr);
    CHECK(iv[0].t1 == Approx(0.5));
    CHECK(iv[1].cell == &f.cells()[1]);
    CHECK(iv[1].t1 == Approx(2.0));
    CHECK(iv[2].cell == &f.cells()[0]);
    CHECK(iv[2].t1 == Approx(2.5));
    // Too many for the table; and a ray that misses the box.
    CHECK(f.along(Vec3(-1, 0.1f, 0), Vec3(1, 0, 0), 10.0f, iv, 2) == -1);
    CHECK(f.along(Vec3(-1, 3, 0), Vec3(1, 0, 0), 10.0f, iv, 8) == 0);
}

TEST_CASE("guided distances: the sampler follows its density, and the weight is T / p", "[guiding][chi2]") {
    const GuidingField f = handMade(1, 10);
    const float sigma = 0.5f;
    struct Case {
        Vec3 o, d;
        float len;
    };
    const double alpha = 0.01 / 4;
    for (const Case c : {Case{Vec3(-1, 0.1f, 0), Vec3(1, 0, 0), 6.0f}, Case{Vec3(3.5f, 0.2f, 0.3f), Vec3(-1, 0, 0), 3.0f},
                         Case{Vec3(-1, 0.1f, 0), Vec3(1, 0, 0), INFINITY}}) {
        for (float forced : {0.5f, 0.25f}) {
            const GuidedDistance gd = GuidedDistance::on(&f, c.o, c.d, c.len, sigma, forced);
            INFO("len " << c.len << " forced share " << forced);
            REQUIRE(gd.share() == forced);
            const double b = std::isinf(c.len) ? 30.0 : double(c.len);
            HistogramOptions opt;
            opt.outsideProbability = std::exp(-sigma * b);  // passes (or beyond 30 on an endless ray)
            double worstRatio = 0;
            long mismatches = 0;
            auto sampleFn = [&](Sample2 u) -> std::optional<double> {
                const GuidedDistanceSample s = gd.sample(u.u);
                if (!s.scattered) return std::nullopt;
                // weight · p = T: the estimate T·σs·X / p is the weight times σs·X.
                const double ratio = s.weight * s.pdf / std::exp(-double(sigma) * s.t);
                worstRatio = std::max(worstRatio, std::abs(ratio - 1));
                mismatches += std::abs(s.pdf / gd.pdf(s.t) - 1) > 1e-5;
                return double(s.t);
            };
            const HistogramResult r = intervalHistogramTest(sampleFn, [&](double t) { return gd.pdf(float(t)); }, 0.0, b,
                                                            60, 400000, opt);
            INFO(r.chi2.table);
            CHECK(r.invalid == 0);
            CHECK(r.chi2.pValue > alpha);
            CHECK(worstRatio < 1e-4);
            CHECK(mismatches == 0);
            // Power: free flight's density in its place fails.
            const HistogramResult wrong = intervalHistogramTest(
                sampleFn, [&](double t) { return sigma * std::exp(-sigma * t); }, 0.0, b, 60, 100000, opt);
            CHECK(wrong.chi2.pValue < 1e-6);
        }
    }
}

TEST_CASE("guided distances: the share is learned (none where every cell learned the same)", "[guiding]") {
    const GuidingField same = handMade(2, 2);
    CHECK(GuidedDistance::on(&same, Vec3(-1, 0.1f, 0), Vec3(1, 0, 0), 6.0f, 0.5f).share() == 0);
    const GuidingField differ = handMade(0.5f, 5);
    CHECK(GuidedDistance::on(&differ, Vec3(-1, 0.1f, 0), Vec3(1, 0, 0), 6.0f, 0.5f).share() > 0);
    // Outside the tree there is nothing to guide by.
    CHECK(GuidedDistance::on(&differ, Vec3(-1, 3, 0), Vec3(1, 0, 0), 6.0f, 0.5f).share() == 0);
}
