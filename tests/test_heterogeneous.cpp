// Heterogeneous media (density grids) against exact answers, for pt and bdpt in every
// --connect mode:
//   the heterogeneous furnace: walls emitting 1 with albedo 0 around a non-absorbing medium of
//     strongly varying density (furnace_field in tests/data/make_test_scenes.py: waves from 0
//     to 4 /m cut to zero on one side of a plane, a blob of 8 /m): radiance exactly 1; ambient,
//     bounded by a moved and turned mesh (the grid moves with it), and coloured;
//   an absorbing ramp: density linear in x and y inside a box in front of a backdrop of
//     radiance 1; trilinear interpolation reproduces a linear field exactly, so the optical
//     depth along a ray is length × density at its midpoint and L = exp(−τ);
//   single scattering from a point light in a density gradient, against 1D quadrature (the
//     optical depths again in closed form).
// Per-pixel (or per-block) z tests, |z| < 4.5: a correct estimate misses with probability
// ~1e-5 per comparison (~3e-4 over the blocks of a case with batch means of 31 degrees of
// freedom), and the seeds are fixed. Medians and maxima too, where a heavy tail could hide.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "support/block_z.h"
#include "support/film_estimates.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr double kZ = 4.5;

BdptIntegrator makeBdpt(int maxDepth, ConnectMode mode) {
    BdptOptions o{maxDepth, MisHeuristic::Power};
    o.connect = mode;
    return BdptIntegrator(o);
}

// Median and maximum over pixels of the per-pixel means divided by the reference.
void checkSpread(const std::vector<PixelEstimate>& px, int wide, const std::function<Vec3(int, int)>& ref,
                 const std::string& what, double medianTol, double maxRatio) {
    for (int c = 0; c < 3; ++c) {
        std::vector<double> r;
        for (size_t i = 0; i < px.size(); ++i) r.push_back(px[i].mean(c) / ref(int(i) % wide, int(i) / wide)[c]);
        std::sort(r.begin(), r.end());
        const double median = 0.5 * (r[(r.size() - 1) / 2] + r[r.size() / 2]);
        INFO(what << " channel " << "RGB"[c] << ": median " << median << ", max " << r.back());
        std::printf("[%s] channel %c: median %.4f, min %.4f, max %.4f\n", what.c_str(), "RGB"[c], median, r.front(),
                    r.back());
        CHECK(std::abs(median - 1) < medianTol);
        CHECK(r.back() < maxRatio);
    }
}

// The ramp's optical depth along camera direction d (absorption 1 per unit density): the ray
// crosses the box from z = −1 to z = −3 (every camera ray does, make_test_scenes.py asserts
// the view), so τ = length × ρ(midpoint).
double rampTau(Vec3 d) {
    const double az = -double(d.z), t1 = 1 / az, t2 = 3 / az, tm = 0.5 * (t1 + t2);
    const double rho = 0.6 + 0.25 * d.x * tm + 0.1 * d.y * tm;
    return (t2 - t1) * rho;
}

// Single scattering in the gradient box [−2.5, 2.5] × [−2, 2] × [−6, −0.5], density
// ρ(y) = 1 + 0.35·y, σs = 0.2 ρ, σt = 0.25 ρ, g = 0.3, point light I = 10 at c. The camera
// ray is in the medium for z ∈ [−6, −0.5]; the light's segment lies in the (convex) box.
// Along a segment of length ℓ between heights y0 and y1 the optical depth is 0.25·ℓ·ρ((y0+y1)/2).
double gradientSingleScatter(Vec3 d) {
    const Vec3 c(0.3f, 0.2f, -3.0f);
    auto rho = [](double y) { return 1.0 + 0.35 * y; };
    const double dx = d.x, dy = d.y, dz = d.z;
    const double tIn = 0.5 / -dz, tOut = 6.0 / -dz;
    const double delta = c.x * dx + c.y * dy + c.z * dz;
    const double px = c.x - delta * dx, py = c.y - delta * dy, pz = c.z - delta * dz;
    const double D = std::sqrt(px * px + py * py + pz * pz);
    const double a = std::atan2(tIn - delta, D), b = std::atan2(tOut - delta, D);
    auto f = [&](double phi) {
        const double t = delta + D * std::tan(phi);
        const double xx = t * dx, xy = t * dy, xz = t * dz;
        const double lx = c.x - xx, ly = c.y - xy, lz = c.z - xz;
        const double r = std::sqrt(lx * lx + ly * ly + lz * lz);
        const double cosTheta = (dx * lx + dy * ly + dz * lz) / r;
        const double tauCam = 0.25 * (t - tIn) * rho(0.5 * (tIn * dy + xy));
        const double tauLight = 0.25 * r * rho(0.5 * (xy + c.y));
        // σs·T·p·I/r², with dt = r²/D dφ.
        return 0.2 * rho(xy) * std::exp(-tauCam - tauLight) * phaseHG(cosTheta, 0.3) * 10.0 / D;
    };
    const int n = 4000;
    double h = (b - a) / n, sum = f(a) + f(b);
    for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 ? 4 : 2);
    return sum * h / 3;
}

// A block's reference: the average over a 4 × 4 grid of film positions per pixel.
template <class F>
Vec3 pixelAverage(int x0, int y0, int block, int W, double yfov, F f) {
    double sum = 0;
    const int S = 4;
    for (int y = 0; y < block; ++y)
        for (int x = 0; x < block; ++x)
            for (int j = 0; j < S; ++j)
                for (int k = 0; k < S; ++k)
                    sum += f(referenceCameraDirection(x0 + x + (k + 0.5) / S, y0 + y + (j + 0.5) / S, W, W, yfov));
    return Vec3(float(sum / (S * S * block * block)));
}

}  // namespace

TEST_CASE("heterogeneous furnace: pt in every connect mode, every pixel is 1", "[heterogeneous][pt][oracle]") {
    for (const char* file : {"furnace_grid_ambient.gltf", "furnace_grid_bounded.gltf"}) {
        auto scene = loadTestScene(file);
        for (ConnectMode mode : kConnectModes) {
            PathTracer pt(PathTracerOptions{-1, true, mode});
            const int W = 8;
            auto px = estimatePixels(*scene, pt, W, W, 256, 7);
            std::string where;
            double z = worstZ(px, W, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, &where);
            INFO(file << " pt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
            CHECK(z < kZ);
            checkSpread(px, W, [](int, int) { return Vec3(1.0f); }, std::string(file) + " pt", 0.03, 1.3);
        }
    }
}

TEST_CASE("heterogeneous furnace: bdpt in every connect mode, every pixel is 1", "[heterogeneous][bdpt][oracle]") {
    for (const char* file : {"furnace_grid_ambient.gltf", "furnace_grid_bounded.gltf"}) {
        auto scene = loadTestScene(file);
        for (ConnectMode mode : kConnectModes) {
            BdptIntegrator bdpt = makeBdpt(-1, mode);
            auto px = estimateFilm(*scene, bdpt, 8, 8, 8, 32, 7, 2);
            std::string where;
            double z = worstZ(px, 4, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, &where);
            INFO(file << " bdpt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
            CHECK(z < kZ);
            checkSpread(px, 4, [](int, int) { return Vec3(1.0f); }, std::string(file) + " bdpt", 0.05, 1.3);
        }
    }
}

// Coloured: extinction (0.5, 1, 2) per unit density, spectral tracking with the path
// throughput's channel weights in both tracers (grey stand-in densities keep that choice out
// of bdpt's weights: heterogeneous_medium.cpp). Null and real collisions multiply the
// channels' weights by factors either side of 1, so batch means of 64 spp are
// skewed. 32 batches were too few: the batch-mean standard error moves with the
// rare large values, and seed 10 of 20 failed at z = 5.1–5.2 in a high-variance corner
// (pt and bdpt alike; unbiased, checked at 32768 spp with two seeds: errors uncorrelated
// between seeds). 128 batches (8192 spp) passed on 20 seeds. Median within 2 %; worst
// pixel: 1.37 was the largest a correct render reached at 2048 spp (pt, red), so 1.6. The
// seed is 9, or BRUME_TEST_SEED where set: the test must pass on any seed, and is run on 20 of them when
// tracking or the weights change (docs/results.md). [heavy]: left out of the sanitizer run
// (the grey furnaces run the same tracking code there).
TEST_CASE("heterogeneous coloured furnace: every channel of every pixel is 1", "[heterogeneous][chromatic][oracle][heavy]") {
    auto scene = loadTestScene("furnace_grid_chromatic.gltf");
    const char* seedText = std::getenv("BRUME_TEST_SEED");
    const uint64_t seed = seedText ? std::strtoull(seedText, nullptr, 10) : 9;
    INFO("seed " << seed);
    const int kBatches = 128;
    for (ConnectMode mode : kConnectModes) {
        PathTracer pt(PathTracerOptions{-1, true, mode});
        auto px = estimateFilm(*scene, pt, 8, 8, 64, kBatches, seed);
        std::string where;
        double z = worstZ(px, 8, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, &where);
        INFO("pt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        std::printf("[coloured furnace, seed %llu] pt --connect %s: worst %s, z = %.2f\n", (unsigned long long)seed,
                    connectModeName(mode), where.c_str(), z);
        CHECK(z < kZ);
        checkSpread(px, 8, [](int, int) { return Vec3(1.0f); }, "coloured pt " + std::string(connectModeName(mode)), 0.02, 1.6);
    }
    for (ConnectMode mode : {ConnectMode::Density, ConnectMode::Mis}) {
        BdptIntegrator bdpt = makeBdpt(-1, mode);
        auto px = estimateFilm(*scene, bdpt, 8, 8, 64, kBatches, seed);
        std::string where;
        double z = worstZ(px, 8, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, &where);
        INFO("bdpt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        std::printf("[coloured furnace, seed %llu] bdpt --connect %s: worst %s, z = %.2f\n", (unsigned long long)seed,
                    connectModeName(mode), where.c_str(), z);
        CHECK(z < kZ);
        checkSpread(px, 8, [](int, int) { return Vec3(1.0f); }, "coloured bdpt " + std::string(connectModeName(mode)), 0.02, 1.6);
    }
}

TEST_CASE("absorbing density ramp: L = exp(-tau) with tau in closed form", "[heterogeneous][oracle]") {
    auto scene = loadTestScene("absorbing_ramp.gltf");
    const int W = 8;
    auto ref = [&](int x, int y) { return pixelAverage(x, y, 1, W, 0.6, [](Vec3 d) { return std::exp(-rampTau(d)); }); };
    // The test can fail: the reference with the ramp's slope dropped is far off.
    CHECK(std::abs(std::exp(-rampTau(referenceCameraDirection(0, 0, W, W, 0.6))) - std::exp(-2.0 * 0.6)) > 0.01);
    for (ConnectMode mode : kConnectModes) {
        PathTracer pt(PathTracerOptions{-1, true, mode});
        auto px = estimatePixels(*scene, pt, W, W, 512, 3);
        std::string where;
        double z = worstZ(px, W, std::vector<bool>(px.size(), false), ref, &where);
        INFO("pt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        CHECK(z < kZ);
    }
    for (ConnectMode mode : {ConnectMode::Density, ConnectMode::Mis}) {
        BdptIntegrator bdpt = makeBdpt(-1, mode);
        auto px = estimateFilm(*scene, bdpt, W, W, 16, 32, 3, 2);
        std::string where;
        double z = worstZ(px, W / 2, std::vector<bool>(px.size(), false),
                          [&](int bx, int by) {
                              return pixelAverage(2 * bx, 2 * by, 2, W, 0.6, [](Vec3 d) { return std::exp(-rampTau(d)); });
                          },
                          &where);
        INFO("bdpt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        CHECK(z < kZ);
    }
}

TEST_CASE("single scattering in a density gradient matches 1D quadrature", "[heterogeneous][oracle]") {
    auto scene = loadTestScene("single_gradient.gltf");
    const int W = 10;
    auto ref = [&](int x, int y) { return pixelAverage(x, y, 1, W, 0.6, gradientSingleScatter); };
    // Against the homogeneous answer (density 1 everywhere in the box) the gradient matters.
    {
        Vec3 d = referenceCameraDirection(5, 2, W, W, 0.6);
        CHECK(std::abs(gradientSingleScatter(d) - singleScatterReference(d, Vec3(0.3f, 0.2f, -3.0f), Vec3(10.0f),
                                                                          Vec3(0.2f), Vec3(0.05f), 0.3, nullptr)[0]) >
              0.02 * gradientSingleScatter(d));
    }
    // The pixel (6, 3) holds the light, where the integral diverges: skipped, with its block.
    std::vector<bool> skipPixel(size_t(W * W), false), skipBlock(size_t(W * W / 4), false);
    skipPixel[3 * W + 6] = true;
    skipBlock[1 * (W / 2) + 3] = true;
    for (ConnectMode mode : kConnectModes) {
        PathTracer pt(PathTracerOptions{1, true, mode});
        auto px = estimatePixels(*scene, pt, W, W, 256, 5);
        std::string where;
        double z = worstZ(px, W, skipPixel, ref, &where);
        INFO("pt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        CHECK(z < kZ);
    }
    for (ConnectMode mode : kConnectModes) {
        BdptIntegrator bdpt = makeBdpt(1, mode);
        auto px = estimateFilm(*scene, bdpt, W, W, 8, 32, 5, 2);
        std::string where;
        double z = worstZ(px, W / 2, skipBlock,
                          [&](int bx, int by) { return pixelAverage(2 * bx, 2 * by, 2, W, 0.6, gradientSingleScatter); },
                          &where);
        INFO("bdpt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        CHECK(z < kZ);
    }
}
