// Random numbers by place (sampler.h, sample_dimensions.h): a decision's number depends on
// (seed, pixel, pass, dimension) only, numbers of different passes, pixels and dimensions are
// independent, the dimension table has no overlaps, and a bidirectional sample's light
// subpath does not depend on its camera subpath.
#include <catch2/catch.hpp>

#include <cmath>
#include <set>
#include <vector>

#include "brume/integrators/bdpt_subpaths.h"
#include "brume/integrators/sample_dimensions.h"
#include "brume/sampling/sampler.h"
#include "support/pixel_estimates.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

TEST_CASE("sampler: a number is a function of its place, whatever was asked before", "[sampler]") {
    Sampler a(5, 77, 3), b(5, 77, 3);
    float first = a.get1D(dim::walkVertex(dim::Side::Light, 2) + dim::kDistance);
    for (uint32_t d = 0; d < 100; ++d) b.get1D(d);
    CHECK(b.get1D(dim::walkVertex(dim::Side::Light, 2) + dim::kDistance) == first);
    CHECK(a.get1D(9, 1) != a.get1D(9, 0));  // a repeat is another number
    CHECK(Sampler(5, 77, 4).get1D(9) != a.get1D(9));
    CHECK(Sampler(5, 78, 3).get1D(9) != a.get1D(9));
    CHECK(Sampler(6, 77, 3).get1D(9) != a.get1D(9));
}

TEST_CASE("sampler: numbers of neighbouring passes, pixels and dimensions are uncorrelated", "[sampler]") {
    // Pearson correlation over n pairs; independent uniforms give |r| ~ 1/√n. (Keys that
    // differed only in PCG's increment once gave r ≈ 0.3 between passes.)
    const int n = 20000;
    auto corr = [&](auto pair) { return pearsonCorrelation(n, pair); };
    const double bound = 5.0 / std::sqrt(double(n));
    auto passes = [](int i) { return std::pair<double, double>(Sampler(1, i / 16, 0).get1D(i % 16), Sampler(1, i / 16, 1).get1D(i % 16)); };
    auto pixels = [](int i) { return std::pair<double, double>(Sampler(1, i, 2).get1D(3), Sampler(1, i + 1, 2).get1D(3)); };
    auto dims = [](int i) { return std::pair<double, double>(Sampler(1, i, 2).get1D(3), Sampler(1, i, 2).get1D(4)); };
    auto repeats = [](int i) { return std::pair<double, double>(Sampler(1, i, 2).get1D(3, 1), Sampler(1, i, 2).get1D(3, 2)); };
    CHECK(std::abs(corr(passes)) < bound);
    CHECK(std::abs(corr(pixels)) < bound);
    CHECK(std::abs(corr(dims)) < bound);
    CHECK(std::abs(corr(repeats)) < bound);
    // And uniform: 16 bins, chi-square with 15 degrees of freedom below its 1e-4 quantile (≈ 46).
    std::vector<int> bins(16, 0);
    for (int i = 0; i < n; ++i) ++bins[int(Sampler(2, i, 0).get1D(dim::kFilmJitter) * 16)];
    double chi2 = 0;
    for (int b : bins) chi2 += (b - n / 16.0) * (b - n / 16.0) / (n / 16.0);
    CHECK(chi2 < 46.0);
}

TEST_CASE("sample dimensions: every place has a block of its own", "[sampler]") {
    std::set<uint32_t> used;
    auto claim = [&](uint32_t base, const char* what, int a, int b) {
        for (uint32_t f = 0; f < dim::kBlock; ++f) {
            INFO(what << " " << a << " " << b << " field " << f);
            REQUIRE(used.insert(base + f).second);
        }
    };
    claim(dim::kFilmJitter, "film", 0, 0);
    claim(dim::kLightStart, "light start", 0, 0);
    for (int k = 0; k < 64; ++k) {
        claim(dim::walkVertex(dim::Side::Camera, k), "camera vertex", k, 0);
        claim(dim::walkVertex(dim::Side::Light, k), "light vertex", k, 0);
        claim(dim::equiAngularSegment(k), "pt equi-angular segment", k, 0);
        for (int t = 0; t < 64; ++t) claim(dim::connection(k, t), "connection", k, t);
    }
    // The largest places still fit below the next region.
    CHECK(dim::walkVertex(dim::Side::Light, dim::kMaxPlace - 1) + dim::kBlock <= dim::connection(0, 0));
    CHECK(dim::connection(dim::kMaxPlace, dim::kMaxPlace) + dim::kBlock <= dim::equiAngularSegment(0));
}

TEST_CASE("bdpt: the light subpath does not depend on the camera subpath", "[sampler][bdpt]") {
    // Sequential draws would hand the light walk whatever numbers the camera walk left.
    auto scene = loadTestScene("quad_light_fog.gltf");
    std::vector<PathVertex> camera(kMaxSubpathVertices), alone(kMaxSubpathVertices), after(kMaxSubpathVertices);
    int compared = 0;
    for (int pixel = 0; pixel < 64; ++pixel) {
        Sampler sampler(11, uint64_t(pixel), 0);
        PathStats stats;
        int nAlone = traceLightSubpath(*scene, 1000, 0, sampler, alone.data(), stats);
        int nCamera = traceCameraSubpath(*scene, float(pixel % 8) + 0.5f, float(pixel / 8) + 0.5f, 8, 8, 1000, 1 << 30, 1 << 30, 0, sampler,
                                         camera.data(), stats);
        int nAfter = traceLightSubpath(*scene, 1000, 0, sampler, after.data(), stats);
        REQUIRE(nAfter == nAlone);
        for (int i = 0; i < nAlone; ++i) {
            REQUIRE(after[i].p.x == alone[i].p.x);
            REQUIRE(after[i].p.y == alone[i].p.y);
            REQUIRE(after[i].p.z == alone[i].p.z);
        }
        compared += nAlone > 2 && nCamera > 2;
    }
    CHECK(compared > 10);
}
