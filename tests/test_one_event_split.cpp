// The one-event split of the bidirectional tracer in single scattering (one_event_split.h):
// where it applies; its camera family's weight W_C and its limits; and the light side's
// re-computation of the density the path tracer placed x with, which W_C reads on both sides
// (if the two differed, W_C + W_L would not be 1 on the path, and the image would be biased).
// The image itself against quadrature: test_bdpt_oracles.cpp.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/film/film.h"
#include "brume/integrators/bdpt.h"
#include "brume/integrators/connection_shares.h"
#include "brume/integrators/direct_light_tracing.h"
#include "brume/integrators/equiangular_segment.h"
#include "brume/integrators/one_event_split.h"
#include "brume/integrators/path_stats.h"
#include "brume/render/renderer.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/camera_importance.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr int kW = 16, kH = 16;

OneEventSplit splitFor(ConnectMode mode, double q, double kappa) {
    OneEventSplit s;
    s.mode = mode;
    s.width = kW;
    s.height = kH;
    s.q = q;
    s.kappa = kappa;
    return s;
}

}  // namespace

TEST_CASE("one-event split: where it applies", "[bdpt][mis]") {
    CHECK(oneEventSplitApplies(*loadTestScene("single_near.gltf")));          // point light, grey fog
    CHECK(oneEventSplitApplies(*loadTestScene("single_spot.gltf")));          // spot light
    CHECK(oneEventSplitApplies(*loadTestScene("sphere_light_fog.gltf")));     // sphere light
    CHECK_FALSE(oneEventSplitApplies(*loadTestScene("single_chromatic.gltf")));  // coloured fog
    CHECK_FALSE(oneEventSplitApplies(*loadTestScene("quad_light_fog.gltf")));    // an area light
    CHECK_FALSE(oneEventSplitApplies(*loadTestScene("bdpt_quad_fogbox.gltf")));  // bounded fog
    // And a render takes it only in single scattering.
    auto scene = loadTestScene("single_near.gltf");
    for (int depth : {1, 2}) {
        BdptIntegrator bdpt(BdptOptions{depth, MisHeuristic::Power});
        bdpt.beginPass(*scene, 0);
        CHECK(bdpt.splitsOneEvent() == (depth == 1));
    }
}

// At a few points of the fog of single_near: W_C in [0, 1]; 1 without light tracing (q = 0)
// and as κ → 0; → 0 as κ → ∞; falling as κ grows; the closed form at one point.
TEST_CASE("one-event split: the camera family's weight", "[bdpt][mis]") {
    auto scene = loadTestScene("single_near.gltf");
    const Light& light = scene->lights()[0];
    const Medium& m = *scene->medium(scene->cameraMedia().current());
    const Vec3 c = scene->camera().position;
    for (ConnectMode mode : {ConnectMode::Density, ConnectMode::Mis}) {
        for (float fx : {2.5f, 8.0f, 13.5f}) {
            const Ray r = scene->camera().generateRay(fx, 7.5f, kW, kH);
            for (float t : {0.5f, 2.0f, 4.0f}) {
                const Vec3 x = r.o + r.d * t;
                const double p = 0.3;
                CHECK(splitFor(mode, 0, 1).cameraWeight(*scene, x, m, 0, light.position, p) == 1.0f);
                float last = 1.0f;
                for (double kappa : {1e-9, 0.01, 1.0, 100.0, 1e9}) {
                    const float w = splitFor(mode, 1, kappa).cameraWeight(*scene, x, m, 0, light.position, p);
                    INFO("fx " << fx << ", t " << t << ", kappa " << kappa << ": W_C " << w);
                    CHECK(w >= 0.0f);
                    CHECK(w <= last);
                    last = w;
                    if (kappa == 1e-9) CHECK(w > 0.999f);
                    if (kappa == 1e9) CHECK(w < 0.001f);
                }
            }
        }
        // The closed form, --connect density: p_C = pdfDir/|x − c|² · p, p_L = q·κ·p_e/|x − y|² · σt·e^(−σt s).
        const Ray r = scene->camera().generateRay(8.0f, 7.5f, kW, kH);
        const Vec3 x = r.o + r.d * 2.0f;
        const double sc = length(x - c), sl = length(x - light.position), st = m.sigmaT().x;
        const double pC = cameraPdfDir(scene->camera(), r.d, kW, kH) / (sc * sc) * 0.3;
        double pL = 0.5 * 0.25 / (4 * M_PI) / (sl * sl) * st * std::exp(-st * sl);
        if (mode == ConnectMode::Density) {
            const double expected = pC * pC / (pC * pC + pL * pL);
            CHECK(splitFor(mode, 0.5, 0.25).cameraWeight(*scene, x, m, 0, light.position, 0.3) ==
                  Approx(expected).epsilon(1e-4));
        }
    }
}

// The light side's π_C against the path tracer's: the camera ray through a film position, its
// segment to the first surface, x placed on it equi-angularly (product in anisotropic fog)
// towards the light as the path tracer places it; cameraDensity(x) must give that density.
TEST_CASE("one-event split: the light side finds the path tracer's density of x", "[bdpt][mis]") {
    for (const char* file : {"single_near.gltf", "single_spot.gltf", "single_forward.gltf", "single_behind.gltf"}) {
        auto scene = loadTestScene(file);
        const Light& light = scene->lights()[0];
        const Medium& m = *scene->medium(scene->cameraMedia().current());
        for (ConnectMode mode : {ConnectMode::EquiAngular, ConnectMode::Mis}) {
            const OneEventSplit split = splitFor(mode, 1, 1);
            PathStats stats;
            int compared = 0;
            double worst = 0;
            for (int i = 0; i < 200; ++i) {
                Sampler s(5, uint64_t(i), 0, SamplerKind::Independent);
                const Sample2 film = s.next2D();
                const Ray r = scene->camera().generateRay(film.u * kW, film.v * kH, kW, kH);
                const SurfaceHit hit = scene->intersect(Ray{r.o, r.d});
                EquiAngular ea;
                if (!equiAngularTowards(light, light.position, MediumSegment{r.o, r.d, hit.valid() ? hit.t : kInfinity, &m},
                                        connectAnisotropy(mode, m.g), &ea))
                    continue;
                const float t = sampleEquiAngular(ea, s.next1D());
                const double p = equiAngularPdf(ea, t);
                if (!(p > 0)) continue;
                const double found = split.cameraDensity(*scene, r.o + r.d * t, m, light, stats);
                worst = std::max(worst, std::abs(found / p - 1));
                ++compared;
            }
            INFO(file << " --connect " << connectModeName(mode) << ": " << compared << " points, worst relative difference "
                      << worst);
            CHECK(compared > 100);
            CHECK(worst < 2e-3);
        }
    }
}

// The fixed tracer's camera family in the split is the path tracer, which learns how often to
// make its connections in media (connection_shares.h) as `pt` does, from 8 passes of the
// render's Sobol numbers: light tracing's 4 learning passes (independent numbers) come first,
// so its shares are decided after pass 4 + 8 − 1 and not before; the same for 1 and 2 threads.
TEST_CASE("one-event split: the fixed tracer's path tracer learns its connection shares", "[bdpt][mis]") {
    auto scene = loadTestScene("sphere_light_fog.gltf");
    const int learnedAfter = DirectLightTracing::kPasses + ConnectionShares::kLearningPasses;
    std::vector<Spectrum> image[2];
    for (int threads : {1, 2})
        for (int spp : {learnedAfter - 1, learnedAfter}) {
            BdptOptions o{1, MisHeuristic::Power};
            o.connect = ConnectMode::Mis;
            o.learnShares = true;  // (the command's default)
            BdptIntegrator bdpt(o);
            Film film(kW, kH);
            RenderOptions ro;
            ro.width = kW;
            ro.height = kH;
            ro.spp = spp;
            ro.seed = 3;
            ro.threads = threads;
            render(*scene, bdpt, ro, film);
            REQUIRE(bdpt.splitsOneEvent());
            REQUIRE(bdpt.connectionShares());
            INFO(spp << " passes, " << threads << " threads");
            CHECK(bdpt.connectionShares()->learning() == (spp < learnedAfter));
            if (spp < learnedAfter) continue;
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) image[threads - 1].push_back(film.pixel(x, y));
        }
    bool same = image[0].size() == image[1].size();
    for (size_t i = 0; same && i < image[0].size(); ++i)
        same = image[0][i].x == image[1][i].x && image[0][i].y == image[1][i].y && image[0][i].z == image[1][i].z;
    CHECK(same);
}
