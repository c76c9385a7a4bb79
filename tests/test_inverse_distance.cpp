// The film position drawn ∝ 1/|x − c| in a pixel holding a light's image (inverse_distance.h),
// and the pixels that take it (light_pixels.h).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "brume/sampling/inverse_distance.h"
#include "brume/sampling/sampler.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

// ∫ over [cx, x] × [cy, y] of dA/|p − c|, signed by the orientation (a rectangle with c at a
// corner: a·asinh(b/a) + b·asinh(a/b)); the mass of any axis-aligned rectangle follows by
// inclusion and exclusion of its corners. Independent of the sampler's triangles and edges.
double cornerMass(double cx, double cy, double x, double y) {
    const double a = std::abs(x - cx), b = std::abs(y - cy);
    if (a == 0 || b == 0) return 0.0;
    const double m = a * std::asinh(b / a) + b * std::asinh(a / b);
    return ((x > cx) == (y > cy)) ? m : -m;
}

double rectangleMass(double cx, double cy, double x0, double y0, double x1, double y1) {
    return cornerMass(cx, cy, x1, y1) - cornerMass(cx, cy, x0, y1) - cornerMass(cx, cy, x1, y0) + cornerMass(cx, cy, x0, y0);
}

const double kCentres[][2] = {{0.5, 0.5},  {0.13, 0.71}, {0.0, 0.4},   {1.0, 1.0},  {0.999, 0.002},  // inside or on it
                              {1.3, 0.5},  {-0.2, 1.4},  {0.5, -0.01}, {1.9, 1.9},  {-0.001, 0.37},  // outside
                              {2.0, 0.0},  {-1.0, 0.5}};

}  // namespace

TEST_CASE("the inverse-distance norm is the square's mass of 1/|x - c|", "[sampling]") {
    for (const auto& c : kCentres) {
        INFO("c = (" << c[0] << ", " << c[1] << ")");
        const double z = rectangleMass(c[0], c[1], 0, 0, 1, 1);
        CHECK(inverseDistanceNorm(float(c[0]), float(c[1])) == Approx(z).epsilon(1e-5));
    }
}

TEST_CASE("points drawn by inverse distance follow their density (chi-square)", "[sampling][chi2]") {
    constexpr int kBins = 12, kSamples = 200000;
    for (const auto& c : kCentres) {
        const float cx = float(c[0]), cy = float(c[1]);
        INFO("c = (" << cx << ", " << cy << ")");
        std::vector<double> observed(kBins * kBins, 0.0), expected(kBins * kBins, 0.0);
        const double z = rectangleMass(cx, cy, 0, 0, 1, 1);
        for (int j = 0; j < kBins; ++j)
            for (int i = 0; i < kBins; ++i)
                expected[size_t(j * kBins + i)] =
                    kSamples * rectangleMass(cx, cy, double(i) / kBins, double(j) / kBins, double(i + 1) / kBins, double(j + 1) / kBins) / z;
        Rng rng(uint64_t(1000 + 7000 * double(cx) + 1000 * double(cy) + 10000), 1);
        double meanWeight = 0, worst = 0;
        for (int n = 0; n < kSamples; ++n) {
            const InverseDistanceSample s = sampleInverseDistance(cx, cy, Sample2{rng.next1D(), rng.next1D()});
            REQUIRE(s.x >= 0.0f);
            REQUIRE(s.x <= 1.0f);
            REQUIRE(s.y >= 0.0f);
            REQUIRE(s.y <= 1.0f);
            const int i = std::min(int(s.x * kBins), kBins - 1), j = std::min(int(s.y * kBins), kBins - 1);
            observed[size_t(j * kBins + i)] += 1;
            meanWeight += s.weight;
            // The weight is 1/p = Z·|x − c|, so the pdf function agrees with it.
            const float pdf = inverseDistancePdf(cx, cy, s.x, s.y);
            if (s.weight > 1e-3f) worst = std::max(worst, std::abs(double(pdf) * s.weight - 1.0));
        }
        const ChiSquareResult r = chiSquareTest(observed, expected);
        INFO(r.table);
        CHECK(r.pValue > 1e-4);
        CHECK(worst < 1e-3);
        // E[1/p] is the square's area.
        CHECK(meanWeight / kSamples == Approx(1.0).epsilon(0.02));
    }
}

TEST_CASE("weighted by inverse distance, 1/|x - c| over the square is integrated with no variance", "[sampling]") {
    // f = 1/|x − c| times its weight Z·|x − c| is Z for every point: the singularity the
    // camera ray meets beside a point light, cancelled.
    for (const auto& c : kCentres) {
        const float cx = float(c[0]), cy = float(c[1]);
        const double z = rectangleMass(cx, cy, 0, 0, 1, 1);
        Rng rng(17, 2);
        for (int n = 0; n < 1000; ++n) {
            const InverseDistanceSample s = sampleInverseDistance(cx, cy, Sample2{rng.next1D(), rng.next1D()});
            const double r = std::hypot(double(s.x) - cx, double(s.y) - cy);
            if (r < 1e-4) continue;
            INFO("c = (" << cx << ", " << cy << "), sample " << n);
            CHECK(s.weight / r == Approx(z).epsilon(1e-3));
        }
    }
}
