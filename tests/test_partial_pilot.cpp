// auto's partial pilot pass (AllocationPlanner::partialAt, BdptOptions::partialPilot): in full
// transport the pilot's collecting pass renders the camera side at its recording pixels alone
// (every pixel still traces its light subpath, whose camera connections reach only the
// recording pixels), and the image always leaves that pass out. Checked: what the pass traces,
// the image against the furnace's closed form, the image's arithmetic, and the same bits for
// any thread count and through a stop at every pilot pass.
#include <catch2/catch.hpp>

#include <cmath>
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

TEST_CASE("auto's partial pilot pass traces the camera side at the recording pixels alone", "[auto][allocation]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    const int W = 40, H = 30;
    struct Case {
        bool partial;
        int planned;
        bool expectPartial;
    };
    for (const Case& k : {Case{true, 0, true}, Case{true, 64, true}, Case{true, 8, false}, Case{false, 0, false}}) {
        BdptIntegrator integrator(partialOptions(k.partial, k.planned));
        Film film(W, H);
        const RenderStats first = render(*scene, integrator, passes(W, H, 1), film);
        const RenderStats second = render(*scene, integrator, passes(W, H, 1), film);
        const double camera = double(second.counts.bdpt.cameraWalkRays) / double(first.counts.bdpt.cameraWalkRays);
        const double light = double(second.counts.bdpt.lightWalkRays) / double(first.counts.bdpt.lightWalkRays);
        INFO("partialPilot " << k.partial << ", planned " << k.planned << ": camera walk rays " << camera
                             << "x the first pass's, light walk rays " << light << "x");
        if (k.expectPartial) {
            CHECK(camera == Approx(0.25).margin(0.05));  // (every second pixel in x and y)
        } else {
            CHECK(camera == Approx(1.0).margin(0.1));
        }
        CHECK(light == Approx(1.0).margin(0.1));  // (every pixel traces its light subpath)
        CHECK((integrator.leftOut().partialPasses == 1) == k.expectPartial);
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
        REQUIRE(integrator.leftOut().partialPasses == 1);
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

// image · (N − 1 − k) = all · N − partial − (the other left-out sums where they are left out).
TEST_CASE("auto's image leaves its partial pilot pass out always", "[auto]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    const int W = 24, H = 16;
    BdptIntegrator integrator(partialOptions());
    Film film(W, H);
    int done = 0;
    for (int spp : {2, 3, kDecided, 60}) {
        render(*scene, integrator, passes(W, H, spp - done), film);
        done = spp;
        const Integrator::LeftOutPasses out = integrator.leftOut();
        REQUIRE(out.partialPasses == 1);
        REQUIRE(out.partialSums);
        const std::vector<float> all = film.rgb(), image = finalImage(film, integrator, SamplerKind::Sobol);
        const int others = spp - 1 - out.passes;
        const bool group = out.passes > 0 && out.sums && others > 0 &&
                           (out.always || out.noise > 2.0 + double(out.passes) / others || others >= kLeftOutRatio * out.passes);
        INFO(spp << " passes, " << out.passes << " more left out: " << (group ? "yes" : "no"));
        double worst = 0;
        for (size_t i = 0; i < all.size(); ++i) {
            double left = fromFixed((*out.partialSums)[i]);
            if (group) left += fromFixed((*out.sums)[i]);
            const double expect = (double(all[i]) * spp - left) / (spp - 1 - (group ? out.passes : 0));
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
    for (int stop : {1, 2, 3, kDecided}) {
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
