// auto's partial pilot pass (AllocationPlanner::partialAt, BdptOptions::partialPilot): in full
// transport the pilot's collecting pass renders the camera side at its recording pixels alone
// (every pixel still traces its light subpath, whose camera connections reach only the
// recording pixels), and the image always leaves that pass out. Checked: what the pass traces,
// the image against the furnace's closed form, the image's arithmetic, and the same bits for
// any thread count and through a stop at every pilot pass.
#include <catch2/catch.hpp>

#include <cmath>
#include <algorithm>
#include <atomic>
#include <cstring>
#include <string>
#include <vector>

#include "brume/integrators/allocation_planner.h"
#include "brume/integrators/bdpt.h"
#include "brume/render/renderer.h"
#include "support/block_z.h"
#include "support/pixel_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr int kDecided = AllocationPlanner::kMaxLastDecisionPass + 1;

BdptOptions partialOptions(bool partial = true, int plannedPasses = 0) {
    BdptOptions o{-1, MisHeuristic::Power};
    o.connect = ConnectMode::Mis;
    o.efficiencyAware = true;
    o.plannedPasses = plannedPasses;
    o.partialPilot = partial;
    return o;
}

RenderOptions passes(int W, int H, int spp, int threads = 2, uint64_t seed = 5) {
    RenderOptions o;
    o.width = W;
    o.height = H;
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    return o;
}

// The image of a whole render, and the choice.
struct Rendered {
    std::vector<float> image;
    std::string chosen;
};

Rendered renderPartial(const Scene& scene, int W, int H, int spp, int threads) {
    BdptIntegrator integrator(partialOptions());
    Film film(W, H);
    render(scene, integrator, passes(W, H, spp, threads), film);
    return Rendered{finalImage(film, integrator, SamplerKind::Sobol),
                    integrator.planner()->decided() ? integrator.planner()->chosen().name() : "undecided"};
}

}  // namespace

// Each pilot pass against the same pass of a whole pilot (the same seed): the camera walk
// at a quarter of the pixels, the light subpaths at every pixel (their rays in RenderStats::rays,
// their counts apart from the recording pixels', which are what RenderStats::counts holds).
TEST_CASE("auto's partial pilot passes trace the camera side at the recording pixels alone", "[auto][allocation]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    const int W = 40, H = 30;
    auto pilotPasses = [&](bool partial, int planned, RenderStats* two, int* partialPasses) {
        BdptIntegrator integrator(partialOptions(partial, planned));
        Film film(W, H);
        for (int pass = 0; pass < 2; ++pass) two[pass] = render(*scene, integrator, passes(W, H, 1), film);
        *partialPasses = integrator.leftOut().partialPasses;
    };
    RenderStats whole[2];
    int none = -1;
    pilotPasses(false, 0, whole, &none);
    CHECK(none == 0);
    struct Case {
        int planned;
        bool expectPartial;
    };
    for (const Case& k : {Case{0, true}, Case{64, true}, Case{8, false}}) {
        RenderStats two[2];
        int partialPasses = -1;
        pilotPasses(true, k.planned, two, &partialPasses);
        CHECK(partialPasses == (k.expectPartial ? 2 : 0));
        for (int pass = 0; pass < 2; ++pass) {
            const double camera = double(two[pass].counts.bdpt.cameraWalkRays) / double(whole[pass].counts.bdpt.cameraWalkRays);
            const double light = double(two[pass].counts.bdpt.lightWalkRays) / double(whole[pass].counts.bdpt.lightWalkRays);
            const double rays = double(two[pass].rays) / double(whole[pass].rays);
            INFO("planned " << k.planned << ", pass " << pass << ": camera walk rays " << camera << "x the whole pass's, "
                            << "light walk rays counted " << light << "x, all rays " << rays << "x");
            if (k.expectPartial) {
                CHECK(camera == Approx(0.25).margin(0.05));  // (every second pixel in x and y)
                CHECK(light == Approx(0.25).margin(0.05));   // (the others' counted apart)
                CHECK(rays > light + 0.1);                   // (every pixel traces its light subpath)
                CHECK(rays < 0.9);
            } else {
                CHECK(camera == 1.0);
                CHECK(rays == 1.0);
            }
        }
    }
}

// The furnace (every pixel 1): whole renders from a fresh tracer each, so every batch has its
// own partial pass, taken through the image as a user gets it (finalImage). The film's plain
// mean, with the partial pass in, is not the image: at pixels that do not record, the pass
// holds only the light subpaths' splats.
TEST_CASE("auto's partial pilot: the image of the furnace is 1 in every pixel", "[auto][oracle]") {
    auto scene = loadTestScene("furnace_albedo.gltf");
    const int W = 8, H = 8, B = 4, batches = 32;
    std::vector<PixelEstimate> px(size_t((W / B) * (H / B)));
    for (int b = 0; b < batches; ++b) {
        BdptIntegrator integrator(partialOptions());
        Film film(W, H);
        render(*scene, integrator, passes(W, H, kDecided, 2, 7000 + uint64_t(b)), film);
        REQUIRE(integrator.leftOut().partialPasses == 2);
        const std::vector<float> image = finalImage(film, integrator, SamplerKind::Sobol);
        for (int by = 0; by < H / B; ++by)
            for (int bx = 0; bx < W / B; ++bx) {
                PixelEstimate& e = px[size_t(by * (W / B) + bx)];
                for (int c = 0; c < 3; ++c) {
                    double v = 0;
                    for (int y = by * B; y < (by + 1) * B; ++y)
                        for (int x = bx * B; x < (bx + 1) * B; ++x) v += image[3 * size_t(y * W + x) + size_t(c)];
                    v /= B * B;
                    e.sum[c] += v;
                    e.sum2[c] += v * v;
                }
                ++e.n;
            }
    }
    std::string where;
    const double z = worstZ(px, W / B, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, &where);
    INFO("worst " << where << " (z = " << z << ")");
    CHECK(z < 4.5);
}

// image · (N − p − k) = all · N − partial − (the other left-out sums where they are left out):
// p = 1 after the first pass, 2 after the pilot.
TEST_CASE("auto's image leaves its partial pilot pass out always", "[auto]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    const int W = 24, H = 16;
    BdptIntegrator integrator(partialOptions());
    Film film(W, H);
    int done = 0;
    for (int spp : {1, 2, 3, kDecided, 60}) {
        render(*scene, integrator, passes(W, H, spp - done), film);
        done = spp;
        const Integrator::LeftOutPasses out = integrator.leftOut();
        const int p = std::min(spp, 2);
        REQUIRE(out.partialPasses == p);
        REQUIRE(out.partialSums);
        const std::vector<float> all = film.rgb(), image = finalImage(film, integrator, SamplerKind::Sobol);
        if (spp == p) {  // (nothing else: the film's mean, partial as it is)
            CHECK(image == all);
            continue;
        }
        const int others = spp - p - out.passes;
        const bool group = out.passes > 0 && out.sums && others > 0 &&
                           (out.always || out.noise > 2.0 + double(out.passes) / others || others >= kLeftOutRatio * out.passes);
        INFO(spp << " passes, " << out.passes << " more left out: " << (group ? "yes" : "no"));
        double worst = 0;
        for (size_t i = 0; i < all.size(); ++i) {
            double left = fromFixed((*out.partialSums)[i]);
            if (group) left += fromFixed((*out.sums)[i]);
            const double expect = (double(all[i]) * spp - left) / (spp - p - (group ? out.passes : 0));
            worst = std::max(worst, std::abs(image[i] - expect) / (std::abs(expect) + 1e-3));
        }
        CHECK(worst < 1e-5);
    }
}

TEST_CASE("auto's partial pilot: the same bits for any thread count and through a stop", "[auto]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    const int W = 40, H = 30, spp = kDecided + 2;
    const Rendered one = renderPartial(*scene, W, H, spp, 1);
    const Rendered two = renderPartial(*scene, W, H, spp, 2);
    CHECK(one.chosen != "undecided");
    CHECK(one.chosen == two.chosen);
    CHECK(std::memcmp(one.image.data(), two.image.data(), one.image.size() * sizeof(float)) == 0);
    for (int stop : {1, 2, 3, kDecided}) {  // (in the pilot, after it, after the duel)
        Film film(W, H);
        std::string state;
        {
            BdptIntegrator first(partialOptions());
            render(*scene, first, passes(W, H, stop), film);
            state = first.saveState();
        }
        BdptIntegrator second(partialOptions());
        second.loadState(state);
        render(*scene, second, passes(W, H, spp - stop), film);
        INFO("stopped after pass " << stop);
        CHECK(second.planner()->chosen().name() == two.chosen);
        const std::vector<float> image = finalImage(film, second, SamplerKind::Sobol);
        CHECK(std::memcmp(image.data(), two.image.data(), image.size() * sizeof(float)) == 0);
    }
}

// Under a time budget that the first pass already spends, the render goes on to the first
// pass the image keeps (renderer.cpp), rather than end with an image of partial passes alone.
TEST_CASE("auto's partial pilot: a spent time budget still ends with a whole pass", "[auto]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    const int W = 24, H = 16;
    BdptIntegrator integrator(partialOptions());
    Film film(W, H);
    RenderOptions o = passes(W, H, 1);
    o.timeBudget = 1e-9;
    const RenderStats stats = render(*scene, integrator, o, film);
    CHECK(stats.passes == 3);
    CHECK(integrator.leftOut().partialPasses == 2);
    // The image is the one whole pass.
    const std::vector<float> all = film.rgb(), image = finalImage(film, integrator, SamplerKind::Sobol);
    double worst = 0;
    for (size_t i = 0; i < all.size(); ++i) {
        const double expect = double(all[i]) * 3 - fromFixed((*integrator.leftOut().partialSums)[i]);
        worst = std::max(worst, std::abs(image[i] - expect) / (std::abs(expect) + 1e-3));
    }
    CHECK(worst < 1e-5);
}

// The state of a tracer that has rendered nothing (what mpirun's ranks start from) and of one
// stopped in its partial pilot load; a foreign count of partial passes does not.
TEST_CASE("auto's partial pilot: states before and within the pilot load, malformed ones do not", "[auto]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    {
        BdptIntegrator fresh(partialOptions()), other(partialOptions());
        CHECK_NOTHROW(other.loadState(fresh.saveState()));
    }
    BdptIntegrator a(partialOptions());
    Film film(16, 16);
    render(*scene, a, passes(16, 16, 1), film);
    const std::string state = a.saveState();
    BdptIntegrator b(partialOptions());
    CHECK_NOTHROW(b.loadState(state));
    // Without partial passes, a state that has them is foreign.
    BdptIntegrator whole(partialOptions(false));
    CHECK_THROWS_AS(whole.loadState(state), std::runtime_error);
}

// A cancel (Ctrl-C) after the first partial pass, with the pass in flight to be dropped: the
// render still goes on to the first whole pass, and no further (renderer.cpp).
TEST_CASE("auto's partial pilot: a cancel within it ends at the first whole pass", "[auto]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    const int W = 24, H = 16;
    BdptIntegrator integrator(partialOptions());
    Film film(W, H);
    render(*scene, integrator, passes(W, H, 1), film);
    std::atomic<bool> cancel{true};
    RenderControl control;
    control.cancel = &cancel;
    control.dropInFlight = true;
    const RenderStats stats = render(*scene, integrator, passes(W, H, 100), film, control);
    CHECK(stats.passes == 2);
    CHECK(film.passes() == 3);
    CHECK(integrator.leftOut().partialPasses == 2);
    // Cancelled before any pass of a new render: nothing.
    BdptIntegrator fresh(partialOptions());
    Film empty(W, H);
    CHECK(render(*scene, fresh, passes(W, H, 100), empty, control).passes == 0);
}
