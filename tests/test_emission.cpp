// Emissive media against exact answers:
//   - Medium::emitted, the estimate of ∫ T·e along a piece, against its closed form in a
//     homogeneous medium and against 1D quadrature in grids (emission and density grids,
//     constant emission in a grid medium, a blackbody temperature grid);
//   - the glowing furnace (walls of albedo 0.5 emitting 0.5 around a medium whose emission
//     equals its absorption: radiance exactly 1), homogeneous, coloured, bounded and with one
//     grid for scattering, absorption and emission, for pt in every --connect mode, bdpt in
//     every mode and auto; and with a blackbody temperature grid;
//   - an absorbing, emitting sphere seen from inside with black walls:
//     L = e/σa·(1 − exp(−σa·d));
//   - next-event estimation towards emissive media: its point sampler by chi-square, its MIS
//     weights summing to one, its point density the gathering's (the strata), and pt with it
//     against pt without it.
// Statistical checks: fixed seeds, per-pixel or per-block standard errors, the z bound stated
// with each; medians and maxima too.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brume/integrators/bdpt.h"
#include "brume/math/blackbody.h"
#include "brume/integrators/path_stats.h"
#include "brume/integrators/path_tracer.h"
#include "brume/integrators/volume_light_sampling.h"
#include "brume/scene/density_grid.h"
#include "brume/scene/volume_lights.h"
#include "support/block_z.h"
#include "support/film_estimates.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"
#include "support/test_support.h"

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

// A glowing furnace. furnace_blackbody.gltf's tint is set here to 0.4/e(2500 K), so that its
// blackbody emission (2500 K everywhere in the sphere) equals its absorption, 0.4.
std::unique_ptr<Scene> loadFurnace(const std::string& file) {
    SceneDescription desc = loadGltf(std::string(BRUME_TEST_DATA) + "/" + file);
    for (Medium& m : desc.media)
        if (m.blackbody) {
            const Spectrum e = blackbodyEmission(2500, m.blackbodyIntensity);
            m.emission = Spectrum(0.4f / e.x, 0.4f / e.y, 0.4f / e.z);
        }
    return std::make_unique<Scene>(std::move(desc));
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
    // A blackbody: the same grid read as a temperature, 400 K per unit (up to ~3500 K in the
    // blob), tinted: e = tint × blackbodyEmission(T), not linear in the grid.
    Medium blackbody = grid;
    blackbody.blackbody = true;
    blackbody.emission = Spectrum(1.0f, 0.8f, 2.0f);
    blackbody.emissionGrid.scale = 400.0f;
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
        {"blackbody grid, through the blob", &blackbody, Vec3(-1.5f, 0.3f, -1.0f), normalize(Vec3(1, 0, 0.05f)), 3.2f},
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
                             "furnace_glowing_grid.gltf", "furnace_blackbody.gltf"}) {
        auto scene = loadFurnace(file);
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
    for (const char* file : {"furnace_glowing.gltf", "furnace_glowing_chromatic.gltf", "furnace_glowing_grid.gltf",
                             "furnace_blackbody.gltf"}) {
        auto scene = loadFurnace(file);
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

TEST_CASE("volume lights: points follow the density they report (chi-square)", "[emission][chi2]") {
    // An emission grid of 20 × 12 × 9 voxels (3 × 2 × 2 bricks, some empty), placed by a
    // scaled and moved transform, in two media (one with twice the emission). Bins: each
    // brick's eight octants; expected counts from pdf × the octant's world volume.
    auto grid = std::make_shared<DensityGrid>();
    const int lo[3] = {0, 0, 0}, hi[3] = {19, 11, 8};
    grid->build(lo, hi, [](int i, int j, int k) { return i >= 8 && i < 16 && j < 8 ? 0.0f : 0.1f + 0.05f * float((i + 2 * j + 3 * k) % 7); });
    std::vector<Medium> media(2);
    for (int m = 0; m < 2; ++m) {
        media[size_t(m)].sigmaA = Spectrum(1.0f);
        media[size_t(m)].emission = Spectrum(1.0f + float(m), 0.5f, 0.25f);
        media[size_t(m)].emissionGrid.grid = grid;
        const double t[3] = {0.5 * m, -1.0, 2.0}, r[4] = {0, 0, 0, 1}, sc[3] = {0.05, 0.07, 0.04};
        media[size_t(m)].emissionGrid.indexToWorld = Mat4::fromTRS(t, r, sc);
        media[size_t(m)].emissionGrid.place(Mat4());
    }
    VolumeLights lights(media);
    REQUIRE(lights.samples(0));
    REQUIRE(lights.samples(1));
    const double octantVolume[2] = {0.05 * 0.07 * 0.04 * 64, 0.05 * 0.07 * 0.04 * 64};  // (4 voxels)³ in m³
    const size_t bricks = grid->brick.size();
    std::vector<double> observed(2 * bricks * 8, 0.0), expected(observed.size(), 0.0);
    const int n = 400000;
    Rng rng(7, 3);
    bool pdfMatches = true;
    for (int i = 0; i < n; ++i) {
        VolumeLightSample s;
        const float u = rng.next1D();
        const Vec3 u3(rng.next1D(), rng.next1D(), rng.next1D());
        REQUIRE(lights.sample(u, u3, &s));
        const Vec3 q = media[size_t(s.medium)].emissionGrid.worldToLocal.point(s.p);
        const size_t b = grid->brickAt(q);
        pdfMatches &= b == s.brick && s.pdf == lights.pdf(s.medium, b);
        const int o = (int(q.x) % 8 >= 4 ? 1 : 0) + (int(q.y) % 8 >= 4 ? 2 : 0) + (int(q.z) % 8 >= 4 ? 4 : 0);
        observed[(size_t(s.medium) * bricks + b) * 8 + size_t(o)] += 1;
    }
    CHECK(pdfMatches);
    double total = 0;
    for (int m = 0; m < 2; ++m)
        for (size_t b = 0; b < bricks; ++b)
            for (int o = 0; o < 8; ++o) {
                const double e = n * lights.pdf(m, b) * octantVolume[m];
                expected[(size_t(m) * bricks + b) * 8 + size_t(o)] = e;
                total += e;
            }
    CHECK(total == Approx(n).epsilon(1e-4));  // the densities integrate to one
    const ChiSquareResult r = chiSquareTest(observed, expected);
    INFO(r.table);
    CHECK(r.pValue > 1e-3);
    // Twice the emission, twice the share.
    double share[2] = {0, 0};
    for (size_t i = 0; i < observed.size(); ++i) share[i / (bricks * 8)] += observed[i] / n;
    CHECK(share[1] / share[0] == Approx(2.0 * (2.0 + 0.5 + 0.25) / (1.0 + 0.5 + 0.25) / 2.0 * 1.0).epsilon(0.02));
}

TEST_CASE("volume lights: next-event and gathering weights sum to one", "[emission][mis]") {
    // For a path x → y both strategies can make, w_n + w_g = 1 whatever the densities, and
    // each tends to 1 where it should (p_g grows as 1/t² close to x).
    for (double pn : {1e-3, 0.5, 6.0, 3e4})
        for (double pdir : {0.0, 0.02, 0.3, 5.0})
            for (double t : {1e-3, 0.05, 1.0, 40.0}) {
                const float wn = volumeLightWeight(true, pn, pdir, 0.2, t), wg = volumeLightWeight(false, pn, pdir, 0.2, t);
                INFO("pn " << pn << " pdir " << pdir << " t " << t);
                CHECK(wn + wg == Approx(1.0f).epsilon(1e-5));
            }
    CHECK(volumeLightWeight(false, 6.0, 0.08, 0.2, 1e-3) > 0.99f);  // next to x: the gathering
    CHECK(volumeLightWeight(true, 6.0, 0.08, 0.2, 3.0) > 0.99f);    // far from x: next-event estimation
    CHECK(volumeLightWeight(true, 6.0, 0.0, 0.2, 3.0) == 1.0f);     // a direction the walk cannot take
}

// Both renders' batch means per 2 × 2 block of an 8 × 8 image (32 batches each): the worst
// z = difference / combined standard error, and each one's summed standard errors per sample.
struct Agreement {
    double worst = 0, perSampleA = 0, perSampleB = 0;
    std::string where;
};

Agreement agreement(const Scene& scene, Integrator& a, int sppA, Integrator& b, int sppB, uint64_t seed) {
    auto x = estimateFilm(scene, a, 8, 8, sppA, kBatches, seed, 2);
    auto y = estimateFilm(scene, b, 8, 8, sppB, kBatches, seed + 1, 2);
    Agreement r;
    for (size_t i = 0; i < x.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double se = std::hypot(x[i].stderror(c), y[i].stderror(c));
            const double z = std::abs(x[i].mean(c) - y[i].mean(c)) / std::max(se, 1e-9);
            if (z > r.worst)
                r.where = "block " + std::to_string(i) + " channel " + std::to_string(c) + ": " + std::to_string(x[i].mean(c)) +
                          " ± " + std::to_string(x[i].stderror(c)) + " against " + std::to_string(y[i].mean(c)) + " ± " +
                          std::to_string(y[i].stderror(c));
            r.worst = std::max(r.worst, z);
            r.perSampleA += x[i].stderror(c) * std::sqrt(double(sppA));
            r.perSampleB += y[i].stderror(c) * std::sqrt(double(sppB));
        }
    return r;
}

TEST_CASE("volume lights: next-event estimation and the gathering agree on the point density", "[emission][mis]") {
    // The MIS weights compare p_n(y) with the gathering's p_dir/(ℓ·t²): both strategies must
    // use the same ℓ, the length of y's stratum along the ray x → y (1/8 of the ray's interval
    // in y's brick for a blackbody, the whole interval otherwise), and the same brick. From
    // the camera of glow_in_fog.gltf, next-event estimation draws y; the gathering along the
    // same ray must report, for its point in y's brick, that ℓ (and only that brick at that ℓ).
    for (bool blackbody : {false, true}) {
        SceneDescription desc = loadGltf(std::string(BRUME_TEST_DATA) + "/glow_in_fog.gltf");
        for (Medium& m : desc.media)
            if (m.emissionGrid.grid && blackbody) {
                m.blackbody = true;
                m.emission = Spectrum(1.0f);
                m.emissionGrid.scale = 500.0f;
            }
        Scene scene(std::move(desc));
        REQUIRE(!scene.volumeLights().empty());
        const Vec3 x = scene.camera().generateRay(16.0f, 12.0f, 32, 24).o;
        int checked = 0;
        for (uint64_t pass = 0; pass < 64; ++pass) {
            Sampler sampler(3, 0, pass);
            PathStats stats;
            VolumeLightConnection c;
            if (!connectVolumeLight(scene, x, Vec3(0.0f), scene.cameraMedia(), sampler, 0, stats, &c)) continue;
            const int mi = [&] {
                for (int i = 0; i < int(scene.desc().media.size()); ++i)
                    if (scene.volumeLights().samples(i)) return i;
                return -1;
            }();
            const Medium& m = *scene.medium(mi);
            const Vec3 y = x + c.wi * c.dist;
            const size_t brick = m.emissionGrid.grid->brickAt(m.emissionGrid.worldToLocal.point(y));
            std::vector<float> lengths;
            const Medium::PointWeight record = [&](float, size_t b, float length) {
                if (b == brick) lengths.push_back(length);
                return 1.0f;
            };
            // (The weight is asked for points that emit: a few estimates, so that some do.)
            size_t most = 0;
            for (float u : {0.1f, 0.3f, 0.5f, 0.7f, 0.9f}) {
                const size_t before = lengths.size();
                m.emitted(Ray{x, c.wi}, 0.0f, c.dist * 2, u, &record);
                most = std::max(most, lengths.size() - before);
            }
            INFO("blackbody " << blackbody << " pass " << pass << ": stratum " << c.stratumLength);
            REQUIRE(!lengths.empty());
            for (float l : lengths) CHECK(l == Approx(c.stratumLength).epsilon(1e-5));
            CHECK(most <= size_t(m.emissionStrata()));
            ++checked;
        }
        CHECK(checked > 20);
    }
}

TEST_CASE("volume lights: pt with them matches pt without them, and bdpt with them matches pt", "[emission][oracle]") {
    // A glowing grid in fog seen from outside it (glow_in_fog.gltf): every camera vertex in the
    // fog or on the floor samples the grid. z < 4.5 per block, and the volume lights must lower
    // the spread of a sample. Without them the corners, which see the glow only when a
    // phase-sampled ray hits it, are heavy-tailed: at 16 samples a batch one of them was a
    // quarter of its value (0.00052 ± 0.00019, against 0.0019 at 2^18 samples), so those
    // renders take four times the samples (a third of the time each).
    auto scene = loadTestScene("glow_in_fog.gltf");
    REQUIRE(!scene->volumeLights().empty());
    PathTracerOptions on{-1, true, ConnectMode::Mis}, off = on;
    off.volumeLights = false;
    PathTracer ptOn(on), ptOff(off);
    const Agreement p = agreement(*scene, ptOn, 16, ptOff, 64, 21);
    INFO("pt: worst z " << p.worst << " at " << p.where << "; per sample: on " << p.perSampleA << ", off " << p.perSampleB);
    CHECK(p.worst < kZ);
    CHECK(p.perSampleA < p.perSampleB);
    // bdpt's volume lights against pt's: both sharp where the other strategies are
    // heavy-tailed. (Gathering without its weight, counting those paths twice, gives z = 5.2
    // here; at 8 samples a batch bdpt's spread hid it, z = 3.1.)
    BdptOptions b{-1, MisHeuristic::Power};
    b.connect = ConnectMode::Mis;
    BdptIntegrator bdpt(b);
    const Agreement a = agreement(*scene, bdpt, 32, ptOn, 16, 23);
    INFO("bdpt against pt: worst z " << a.worst << " at " << a.where);
    CHECK(a.worst < kZ);
}

TEST_CASE("glowing media at --max-depth: pt with volume lights and bdpt gathering agree", "[emission][bdpt][oracle]") {
    // The two tracers reach a glowing grid by different strategies (pt: next-event estimation
    // and the weighted gathering; bdpt: the camera walk's gathering alone) and cut paths at
    // --max-depth by different rules (pt stops its walk, bdpt passes through media past the
    // last event). At depths 0, 1 and 2 each 2 × 2 block of an 8 × 8 image must agree:
    // z = difference / combined standard error < 4.5 (32 batches each). Two scenes: the glow
    // behind an invisible boundary, and the grid furnace, which has none (there bdpt would pass
    // through media at the last event if the glow did not forbid it, and lose the emission
    // the rays from a last medium vertex gather: z = 11.7 at depth 1, 5.9 at depth 2).
    for (const char* file : {"glow_in_fog.gltf", "furnace_glowing_grid.gltf"})
    for (int depth : {0, 1, 2}) {
        auto scene = loadTestScene(file);
        PathTracer pt(PathTracerOptions{depth, true, ConnectMode::Mis});
        BdptOptions o{depth, MisHeuristic::Power};
        o.connect = ConnectMode::Mis;
        auto a = estimateFilm(*scene, pt, 8, 8, 16, kBatches, 31, 2);
        auto b = estimateFilm(*scene, BdptIntegrator(o), 8, 8, 16, kBatches, 32, 2);
        double worst = 0;
        for (size_t i = 0; i < a.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const double se = std::hypot(a[i].stderror(c), b[i].stderror(c));
                worst = std::max(worst, std::abs(a[i].mean(c) - b[i].mean(c)) / std::max(se, 1e-9));
            }
        INFO(file << " --max-depth " << depth << ": worst z " << worst);
        CHECK(worst < kZ);
    }
}
