// Emissive media against exact answers:
//   - Medium::emitted, the estimate of ∫ T·e along a piece, against its closed form in a
//     homogeneous medium and against 1D quadrature in grids (emission and density grids,
//     constant emission in a grid medium);
//   - the glowing furnace (walls of albedo 0.5 emitting 0.5 around a medium whose emission
//     equals its absorption: radiance exactly 1), homogeneous, coloured, bounded and with one
//     grid for scattering, absorption and emission, for pt in every --connect mode, bdpt in
//     every mode and auto;
//   - an absorbing, emitting sphere seen from inside with black walls:
//     L = e/σa·(1 − exp(−σa·d)).
// Statistical checks: fixed seeds, per-pixel or per-block standard errors, the z bound stated
// with each; medians and maxima too.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
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

// ∫_{t0}^{t1} T(t0, t)·e(t) dt by the midpoint rule on n steps, T from the same rule over the
// extinction σt·density (the grids are trilinear: smooth within a voxel, 0.1 m here, so 20000
// steps over a few metres resolve them).
Spectrum quadrature(const Medium& m, const Ray& ray, float t0, float t1, int n = 20000) {
    const double h = (double(t1) - t0) / n;
    const Spectrum st = m.sigmaT();
    double tau[3] = {0, 0, 0}, sum[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
        const Vec3 x = ray.o + ray.d * float(t0 + (i + 0.5) * h);
        const double rho = m.densityAt(x);
        const Spectrum e = m.emissionAt(x);
        for (int c = 0; c < 3; ++c) {
            // T at the step's midpoint: the depth up to its start plus half its own.
            const double half = 0.5 * h * st[c] * rho;
            sum[c] += e[c] * std::exp(-(tau[c] + half)) * h;
            tau[c] += 2 * half;
        }
    }
    return Spectrum(float(sum[0]), float(sum[1]), float(sum[2]));
}

struct EmittedStats {
    double mean[3] = {0, 0, 0}, se[3] = {0, 0, 0}, max[3] = {0, 0, 0}, median[3] = {0, 0, 0};
};

// n estimates of the same piece: each from a ray origin moved back along the ray by a
// different amount (its own hash, so its own random numbers), the piece unchanged.
EmittedStats estimateEmitted(const Medium& m, Vec3 o, Vec3 d, float length, int n) {
    std::vector<double> v[3];
    for (int k = 0; k < n; ++k) {
        const float back = 0.001f * float(k + 1);
        const Spectrum e = m.emitted(Ray{o - d * back, d}, back, back + length, 0.5f);
        for (int c = 0; c < 3; ++c) v[c].push_back(e[c]);
    }
    EmittedStats s;
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sum2 = 0;
        for (double x : v[c]) sum += x, sum2 += x * x;
        s.mean[c] = sum / n;
        s.se[c] = std::sqrt(std::max(0.0, sum2 / n - s.mean[c] * s.mean[c]) / (n - 1));
        std::sort(v[c].begin(), v[c].end());
        s.max[c] = v[c].back();
        s.median[c] = v[c][size_t(n / 2)];
    }
    return s;
}

constexpr double kZ = 4.5;  // 32 batches (31 degrees of freedom): a correct block misses it with p ~ 1e-4
constexpr int kBatches = 32;

double furnaceZ(const Scene& scene, Integrator& integrator, int spp, uint64_t seed, std::string* where) {
    auto px = estimateFilm(scene, integrator, 8, 8, spp, kBatches, seed, 2);
    return worstZ(px, 4, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, where);
}

BdptIntegrator makeBdpt(ConnectMode mode, bool efficiencyAware = false) {
    BdptOptions o{-1, MisHeuristic::Power};
    o.connect = mode;
    o.efficiencyAware = efficiencyAware;
    return BdptIntegrator(o);
}

}  // namespace

TEST_CASE("emitted: closed form in a homogeneous medium", "[emission]") {
    Medium m;
    m.sigmaS = Spectrum(0.3f, 0.0f, 0.1f);
    m.sigmaA = Spectrum(0.2f, 0.0f, 0.4f);
    m.emission = Spectrum(0.5f, 0.25f, 0.0f);
    const Ray ray{Vec3(0.0f), Vec3(0, 0, -1)};
    for (float len : {0.0f, 0.1f, 2.0f, 30.0f}) {
        const Spectrum e = m.emitted(ray, 1.0f, 1.0f + len, 0.5f);
        CHECK(e.x == Approx(0.5 / 0.5 * (1 - std::exp(-0.5 * len))).epsilon(1e-5).margin(1e-7));
        CHECK(e.y == Approx(0.25 * len).epsilon(1e-5).margin(1e-7));  // no extinction: e·ℓ
        CHECK(e.z == 0.0f);
        const Spectrum q = quadrature(m, ray, 1.0f, 1.0f + len, 2000);
        CHECK(e.x == Approx(q.x).epsilon(1e-4).margin(1e-7));
    }
    // An unbounded piece: e/σt where there is extinction.
    m.emission.y = 0;
    CHECK(m.emitted(ray, 0.0f, kInfinity, 0.5f).x == Approx(1.0f));
    // A medium that does not emit gives exactly 0.
    m.emission = Spectrum(0.0f);
    CHECK(isBlack(m.emitted(ray, 0.0f, 5.0f, 0.5f)));
}

TEST_CASE("emitted: grid estimates match 1D quadrature", "[emission][oracle]") {
    // The glowing grid furnace's medium: density, scattering, absorption and emission all
    // from furnace_grid.vdb (strongly varying, with empty regions and a dense blob), placed by
    // a moved and turned node. Variants: the emission grid in a homogeneous medium, and
    // constant emission in the grid medium (over a piece reaching beyond the grid's box,
    // whose stretches outside it have constant T).
    auto scene = loadTestScene("furnace_glowing_grid.gltf");
    const Medium& grid = *scene->medium(0);
    REQUIRE(grid.heterogeneous());
    REQUIRE(grid.emissionGrid.grid == grid.density.grid);  // one grid, loaded once
    Medium homogeneous = grid;
    homogeneous.density = GridPlacement{};
    homogeneous.sigmaS = Spectrum(0.4f, 0.8f, 0.1f);
    homogeneous.sigmaA = Spectrum(0.1f);
    Medium constant = grid;
    constant.emissionGrid = GridPlacement{};
    constant.emission = Spectrum(0.3f, 0.2f, 0.1f);
    struct Case {
        const char* name;
        const Medium* medium;
        Vec3 o, d;
        float length;
    } cases[] = {
        {"grid, through the blob", &grid, Vec3(-1.5f, 0.3f, -1.0f), normalize(Vec3(1, 0, 0.05f)), 3.2f},
        {"grid, diagonal", &grid, Vec3(-1.0f, -1.0f, 1.0f), normalize(Vec3(1, 1, -1)), 3.4f},
        {"emission grid in a homogeneous medium", &homogeneous, Vec3(-1.5f, 0.3f, -1.0f), normalize(Vec3(1, 0, 0.05f)), 3.2f},
        {"constant emission in a grid medium", &constant, Vec3(-3.5f, 0.2f, -0.9f), normalize(Vec3(1, 0.02f, 0)), 7.0f},
    };
    for (const Case& c : cases) {
        const Spectrum ref = quadrature(*c.medium, Ray{c.o, c.d}, 0.0f, c.length);
        const EmittedStats s = estimateEmitted(*c.medium, c.o, c.d, c.length, 4000);
        for (int ch = 0; ch < 3; ++ch) {
            INFO(c.name << " channel " << ch << ": " << s.mean[ch] << " ± " << s.se[ch] << " vs " << ref[ch] << ", median "
                        << s.median[ch] << ", max " << s.max[ch]);
            REQUIRE(ref[ch] > 0);
            CHECK(std::abs(s.mean[ch] - ref[ch]) < kZ * s.se[ch] + 1e-4 * ref[ch]);
            CHECK(s.se[ch] < 0.02 * ref[ch]);  // one estimate's spread: under 1.3 × the value
            CHECK(s.max[ch] < 8 * ref[ch]);    // no heavy tail
            CHECK(s.median[ch] > 0.25 * ref[ch]);
        }
    }
}

TEST_CASE("emitting sphere seen from inside: L = e/sigma_a (1 - exp(-sigma_a d))", "[emission][oracle]") {
    // Black walls (the furnace sphere, radius 2, tessellated: 1.996 to 2 m from the centre),
    // an absorbing coloured medium emitting e. Both tracers gather the piece to the wall in
    // closed form, so every sample of a pixel centre gives the same value: checked to 1e-4.
    auto scene = loadTestScene("emitting_sphere.gltf");
    const Spectrum e(0.3f, 0.5f, 0.2f), sigmaA(0.2f, 0.6f, 1.4f);
    const int W = 8, H = 8;
    PathTracer pt(PathTracerOptions{-1, true, ConnectMode::Mis});
    BdptIntegrator bdpt = makeBdpt(ConnectMode::Mis);
    for (const Integrator* integrator : {static_cast<const Integrator*>(&pt), static_cast<const Integrator*>(&bdpt)}) {
        auto px = estimatePixels(*scene, *integrator, W, H, 4, 3);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const float d = scene->intersect(scene->camera().generateRay(x + 0.5f, y + 0.5f, W, H)).t;
                for (int c = 0; c < 3; ++c) {
                    const double expected = e[c] / sigmaA[c] * (1 - std::exp(-double(sigmaA[c]) * d));
                    INFO("pixel (" << x << "," << y << ") channel " << c);
                    CHECK(px[size_t(y) * W + x].mean(c) == Approx(expected).epsilon(1e-4));
                }
            }
    }
}

TEST_CASE("glowing furnace: pt in every connect mode gives 1", "[emission][pt][oracle]") {
    // Per-pixel z over 8 × 8 pixel centres, 3 channels, against the Bonferroni bound.
    for (const char* file : {"furnace_glowing.gltf", "furnace_glowing_bounded.gltf", "furnace_glowing_chromatic.gltf",
                             "furnace_glowing_grid.gltf"}) {
        auto scene = loadTestScene(file);
        for (ConnectMode mode : kConnectModes) {
            PathTracer pt(PathTracerOptions{-1, true, mode});
            const int W = 8, H = 8;
            auto px = estimatePixels(*scene, pt, W, H, 256, 5);
            double worst = 0;
            std::vector<double> means;
            for (const PixelEstimate& e : px)
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, std::abs(e.mean(c) - 1) / std::max(e.stderror(c), 1e-9));
                    means.push_back(e.mean(c));
                }
            std::sort(means.begin(), means.end());
            INFO(file << " pt --connect " << connectModeName(mode) << ": worst z " << worst << ", median pixel "
                      << means[means.size() / 2] << ", largest " << means.back());
            CHECK(worst < zBound(3 * W * H));
            CHECK(std::abs(means[means.size() / 2] - 1) < 0.02);
            CHECK(means.back() < 1.2);
        }
    }
}

TEST_CASE("glowing furnace: bdpt in every connect mode and auto give 1", "[emission][bdpt][oracle][sanitizer-skip]") {
    // 2 × 2 blocks of an 8 × 8 image from 32 independent renders (light-tracing splats
    // included), |z| < 4.5.
    for (const char* file : {"furnace_glowing.gltf", "furnace_glowing_chromatic.gltf", "furnace_glowing_grid.gltf"}) {
        auto scene = loadTestScene(file);
        for (ConnectMode mode : kConnectModes) {
            BdptIntegrator bdpt = makeBdpt(mode);
            std::string where;
            const double z = furnaceZ(*scene, bdpt, 8, 11, &where);
            INFO(file << " bdpt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
            CHECK(z < kZ);
        }
        BdptIntegrator automatic = makeBdpt(ConnectMode::Mis, true);
        std::string where;
        const double z = furnaceZ(*scene, automatic, 8, 12, &where);
        INFO(file << " auto: worst " << where << " (z = " << z << ")");
        CHECK(z < kZ);
    }
}
