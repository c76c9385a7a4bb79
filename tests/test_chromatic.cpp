// Coloured media against exact answers: the chromatic furnace (a closed cavity of coloured
// walls emitting 1 − albedo, filled with a non-absorbing fog whose extinction differs 4× between
// channels: radiance 1 everywhere) and a purely absorbing coloured fog (radiance
// exp(−σa,c·d) for walls emitting 1 at distance d). Means, medians and maxima per channel: a
// heavy tail passes a mean test by luck, and shows in the median and the maximum.
#include <catch2/catch.hpp>

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "brume/film/film.h"
#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/render/renderer.h"
#include "brume/math/ray.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {


struct ChannelStats {
    double mean = 0, median = 0, max = 0;
};

// Per channel over the image, each pixel divided by its expected value.
std::vector<ChannelStats> relativeStats(const Film& film, const std::function<Spectrum(int, int)>& expected) {
    std::vector<ChannelStats> out(3);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> v;
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x) v.push_back(film.pixel(x, y)[c] / expected(x, y)[c]);
        std::sort(v.begin(), v.end());
        double sum = 0;
        for (double a : v) sum += a;
        out[c] = {sum / v.size(), 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]), v.back()};
    }
    return out;
}

Film renderFilm(const Scene& scene, Integrator& integrator, int width, int height, int spp, uint64_t seed) {
    Film film(width, height);
    RenderOptions o;
    o.width = width;
    o.height = height;
    o.spp = spp;
    o.seed = seed;
    o.threads = 2;
    render(scene, integrator, o, film);
    return film;
}

// The bounds: image mean within 1 %, median within 2 %, no pixel above 3 (relative).
void checkFurnace(const Film& film, const std::string& what) {
    auto st = relativeStats(film, [](int, int) { return Spectrum(1.0f); });
    for (int c = 0; c < 3; ++c) {
        INFO(what << " channel " << "RGB"[c] << ": mean " << st[c].mean << ", median " << st[c].median << ", max "
                  << st[c].max);
        std::printf("[%s] channel %c: mean %.4f, median %.4f, max %.3f\n", what.c_str(), "RGB"[c], st[c].mean,
                    st[c].median, st[c].max);
        CHECK(std::abs(st[c].mean - 1) < 0.01);
        CHECK(std::abs(st[c].median - 1) < 0.02);
        CHECK(st[c].max < 3);
    }
}

}  // namespace

TEST_CASE("chromatic furnace: pt converges in every channel, every connect mode", "[chromatic][pt][oracle]") {
    auto scene = loadTestScene("furnace_chromatic.gltf");
    for (ConnectMode mode : kConnectModes) {
        PathTracer pt(PathTracerOptions{-1, true, mode});
        checkFurnace(renderFilm(*scene, pt, 48, 32, 64, 5), std::string("pt --connect ") + connectModeName(mode));
    }
}

// The bidirectional tracer samples every distance of a sample with one hero channel and weighs
// over channels: each channel is served mostly by the third of the samples whose hero it is,
// so it needs more samples than pt here (at 32 spp the blue median is 0.90; docs/results.md).
// At 256 spp the blue median sat at 0.976–0.992 over seeds 11–13 with either sampler, at the
// edge of the bound; at 512 spp on 24 × 16 pixels it was 0.980–1.000 over seeds 5–6 (0.9799 in
// --connect density at seed 5 once the light subpaths were stratified over the image, their
// means 0.999–1.008): a median of per-pixel values is pulled low by each pixel's skew, which
// falls as 1/√spp. So the same samples as 12 × 8 pixels at 2048 spp. (General connections
// are made with probability 1/4 by default,
// which also makes a sample cheaper.) [heavy]: 100 s here; the sanitizer build leaves it out
// (it passed there when written; the weight checker and the pt cases run the same code under
// the sanitizers). Plain equi-angular is product sampling's g = 0 case and mis's part where
// g = 0; the fog here has g = −0.3, so product covers it (and each mode costs 70 s).
TEST_CASE("chromatic furnace: bdpt converges in every channel, every connect mode", "[chromatic][bdpt][oracle][heavy]") {
    auto scene = loadTestScene("furnace_chromatic.gltf");
    for (ConnectMode mode : {ConnectMode::Density, ConnectMode::Product, ConnectMode::Mis}) {
        BdptOptions opt;
        opt.connect = mode;
        BdptIntegrator bdpt(opt);
        checkFurnace(renderFilm(*scene, bdpt, 12, 8, 2048, 5), std::string("bdpt --connect ") + connectModeName(mode));
    }
}

TEST_CASE("absorbing coloured fog: radiance is exp(-sigma_a d) per channel", "[chromatic][pt][oracle]") {
    // Walls of the furnace sphere (radius 2, tessellated: the centre sees its flat faces at
    // 1.996 to 2 m) emit 1 and reflect nothing; σa = (0.1, 0.4, 1.2) /m, no scattering. Free
    // flight either reaches the wall (weight T_c / P_pass) or is absorbed (0): per-pixel z
    // tests with the samples' own standard errors.
    auto scene = loadTestScene("furnace_absorbing.gltf");
    const Spectrum sigmaA(0.1f, 0.4f, 1.2f);
    const int W = 12, H = 8;
    for (ConnectMode mode : kConnectModes) {
        PathTracer pt(PathTracerOptions{-1, true, mode});
        auto px = estimatePixels(*scene, pt, W, H, 1024, 9);
        double worst = 0, meanRatio[3] = {0, 0, 0};
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                // The distance to the wall through the pixel's centre (T varies < 0.1 % across it).
                Ray r = scene->camera().generateRay(x + 0.5f, y + 0.5f, W, H);
                const float d = scene->intersect(r).t;
                const PixelEstimate& e = px[size_t(y) * W + x];
                for (int c = 0; c < 3; ++c) {
                    const double expected = std::exp(-double(sigmaA[c]) * d);
                    meanRatio[c] += e.mean(c) / expected / (W * H);
                    worst = std::max(worst, std::abs(e.mean(c) - expected) / std::max(e.stderror(c), 1e-6));
                }
            }
        INFO("pt --connect " << connectModeName(mode) << ": worst z " << worst << ", mean ratios " << meanRatio[0]
                             << " " << meanRatio[1] << " " << meanRatio[2]);
        CHECK(worst < zBound(3 * W * H));
        for (double m : meanRatio) CHECK(std::abs(m - 1) < 0.01);
    }
}
