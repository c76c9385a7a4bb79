// Film accumulation and the renderer's scheduling, with fake integrators on an empty scene:
// averaging over passes, the (seed, pixel, pass) sample streams, identical images for any
// thread count (splats included), dropped non-finite samples, time budgets, cancellation,
// abandoned passes and films restored between passes.
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <thread>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "brume/film/film.h"
#include "brume/render/renderer.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/scene.h"

using namespace brume;

namespace {

// The first value the integrator draws, in every channel: checks the sample streams.
struct FirstDrawIntegrator : Integrator {
    Spectrum sample(const Scene&, float, float, int, int, Sampler& sampler, PathStats& stats) const override {
        stats.rays += 2;
        return Spectrum(sampler.next1D());
    }
};

// The film position itself: checks the jitter and the pixel convention.
struct PositionIntegrator : Integrator {
    Spectrum sample(const Scene&, float fx, float fy, int, int, Sampler&, PathStats&) const override {
        return Spectrum(fx, fy, 0.0f);
    }
};

// NaN at pixel (0,0), +inf at pixel (1,0), 1 elsewhere.
struct NonFiniteIntegrator : Integrator {
    Spectrum sample(const Scene&, float fx, float fy, int, int, Sampler&, PathStats&) const override {
        if (fy < 1 && fx < 1) return Spectrum(std::numeric_limits<float>::quiet_NaN());
        if (fy < 1 && fx < 2) return Spectrum(0.0f, std::numeric_limits<float>::infinity(), 0.0f);
        return Spectrum(1.0f);
    }
};

// Three splats per sample at random pixels (some outside the image), plus a random value.
struct SplattingFake : SplattingIntegrator {
    Spectrum sampleWithSplats(const Scene&, float, float, int width, int height, Sampler& sampler, PathStats&,
                              SplatList& splats) const override {
        for (int i = 0; i < 3; ++i) {
            float x = sampler.next1D() * float(width + 4) - 2.0f;
            float y = sampler.next1D() * float(height + 4) - 2.0f;
            splats.splat(x, y, Spectrum(sampler.next1D(), 0.25f, 1e-3f * sampler.next1D()), width, height);
        }
        return Spectrum(sampler.next1D(), 0.0f, 0.0f);
    }
};

struct ThrowingIntegrator : Integrator {
    Spectrum sample(const Scene&, float fx, float fy, int, int, Sampler&, PathStats&) const override {
        if (fx > 20 && fy > 10) throw std::runtime_error("integrator failure");
        return Spectrum(1.0f);
    }
};

const Scene& emptyScene() {
    static Scene scene{SceneDescription{}};
    return scene;
}

RenderOptions options(int w, int h, int spp, int threads, uint64_t seed = 7) {
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.threads = threads;
    o.seed = seed;
    return o;
}

std::vector<float> renderImage(Integrator& integrator, const RenderOptions& o, RenderStats* stats = nullptr) {
    Film film(o.width, o.height);
    RenderStats s = render(emptyScene(), integrator, o, film);
    if (stats) *stats = s;
    return film.rgb();
}

}  // namespace

TEST_CASE("film: pixel is the mean over completed passes", "[film]") {
    Film film(3, 2);
    CHECK(film.passes() == 0);
    CHECK(film.pixel(2, 1).x == 0.0f);
    film.add(2, 1, Spectrum(1.0f, 2.0f, 3.0f));
    film.completePass();
    film.add(2, 1, Spectrum(3.0f, 0.0f, 0.5f));
    film.add(0, 0, Spectrum(4.0f));
    film.completePass();
    CHECK(film.passes() == 2);
    Spectrum p = film.pixel(2, 1);
    CHECK(p.x == 2.0f);
    CHECK(p.y == 1.0f);
    CHECK(p.z == 1.75f);
    CHECK(film.pixel(0, 0).y == 2.0f);
    CHECK(film.pixel(1, 0).y == 0.0f);

    std::vector<float> rgb = film.rgb();
    REQUIRE(rgb.size() == 18);
    CHECK(rgb[3 * (1 * 3 + 2) + 0] == 2.0f);  // row-major, top row first
    CHECK(rgb[3 * (1 * 3 + 2) + 2] == 1.75f);
    CHECK(rgb[0] == 2.0f);

    film.clear();
    CHECK(film.passes() == 0);
    film.completePass();
    CHECK(film.pixel(2, 1).x == 0.0f);
}

TEST_CASE("film: splats are divided by the passes and skip positions outside", "[film]") {
    Film film(4, 4);
    SplatList list;
    list.splat(1.5f, 2.9f, Spectrum(6.0f), 4, 4);
    list.splat(1.0f, 2.0f, Spectrum(2.0f), 4, 4);
    list.splat(-0.5f, 1.0f, Spectrum(100.0f), 4, 4);  // outside
    list.splat(4.0f, 1.0f, Spectrum(100.0f), 4, 4);   // outside
    list.splat(0.0f, 0.0f, Spectrum(std::numeric_limits<float>::quiet_NaN()), 4, 4);
    CHECK(list.records().size() == 2);
    CHECK(list.nonFinite() == 1);
    CHECK_FALSE(film.hasSplats());
    film.mergeSplats(list);
    CHECK(film.hasSplats());
    film.add(1, 2, Spectrum(4.0f));
    film.completePass();
    film.completePass();
    CHECK(film.pixel(1, 2).x == 6.0f);  // (6 + 2 + 4) / 2
    CHECK(film.pixel(0, 1).x == 0.0f);
    list.clear();
    CHECK(list.records().empty());
    CHECK(list.nonFinite() == 0);
}

TEST_CASE("film: bad sizes are rejected", "[film]") {
    CHECK_THROWS_AS(Film(0, 4), std::invalid_argument);
    CHECK_THROWS_AS(Film(4, -1), std::invalid_argument);
}

TEST_CASE("renderer: each sample uses Sampler(seed, y*width+x, pass), jitter at its own dimension", "[renderer]") {
    const int w = 21, h = 18, spp = 3;
    FirstDrawIntegrator integrator;
    RenderStats stats;
    std::vector<float> img = renderImage(integrator, options(w, h, spp, 2, 1234), &stats);
    CHECK(stats.passes == spp);
    CHECK(stats.samples == uint64_t(w * h * spp));
    CHECK(stats.rays == 2 * stats.samples);
    CHECK(stats.nonFinite == 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0;
            for (int pass = 0; pass < spp; ++pass) {
                // The jitter reads dimension kFilmJitter, not the sequential stream.
                Sampler s(1234, uint64_t(y) * w + x, pass);
                sum += s.next1D();
            }
            REQUIRE(img[3 * (y * w + x)] == float(sum * (1.0 / spp)));
        }
}

TEST_CASE("renderer: film positions are jittered inside their pixel, top-left origin", "[renderer]") {
    const int w = 19, h = 17, spp = 4;
    PositionIntegrator integrator;
    std::vector<float> img = renderImage(integrator, options(w, h, spp, 2));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float fx = img[3 * (y * w + x)], fy = img[3 * (y * w + x) + 1];
            REQUIRE(fx >= float(x));
            REQUIRE(fx < float(x + 1));
            REQUIRE(fy >= float(y));
            REQUIRE(fy < float(y + 1));
        }
    // The jitter is not always the pixel centre.
    CHECK(img[0] != 0.5f);
}

TEST_CASE("renderer: the same seed gives the same image for any thread count", "[renderer]") {
    const int w = 45, h = 37;  // not a multiple of the tile size
    FirstDrawIntegrator integrator;
    std::vector<float> one = renderImage(integrator, options(w, h, 3, 1));
    for (int threads : {2, 3, 8}) {
        INFO("threads " << threads);
        CHECK(renderImage(integrator, options(w, h, 3, threads)) == one);
    }
    CHECK(renderImage(integrator, options(w, h, 3, 0)) == one);  // hardware threads
    CHECK(renderImage(integrator, options(w, h, 3, 1, 8)) != one);  // another seed
}

TEST_CASE("renderer: splats are merged identically for any thread count", "[renderer]") {
    const int w = 40, h = 35, spp = 3;
    SplattingFake integrator;
    RenderStats stats;
    std::vector<float> one = renderImage(integrator, options(w, h, spp, 1), &stats);
    for (int threads : {2, 5}) {
        INFO("threads " << threads);
        CHECK(renderImage(integrator, options(w, h, spp, threads)) == one);
    }
    // Green: every in-image splat adds 0.25 / spp; about 3·w·h·(w·h)/((w+4)(h+4)) per pass.
    double green = 0;
    for (int i = 0; i < w * h; ++i) green += one[3 * i + 1];
    double splatsPerPass = green / 0.25;
    double expected = 3.0 * w * h * (double(w * h) / ((w + 4) * (h + 4)));
    CHECK(splatsPerPass == Approx(expected).epsilon(0.05));
}

TEST_CASE("renderer: non-finite samples are dropped and counted", "[renderer]") {
    const int w = 8, h = 4, spp = 5;
    NonFiniteIntegrator integrator;
    RenderStats stats;
    std::vector<float> img = renderImage(integrator, options(w, h, spp, 2), &stats);
    CHECK(stats.nonFinite == 2 * spp);
    CHECK(stats.samples == uint64_t(w * h * spp));
    for (float v : img) CHECK(std::isfinite(v));
    CHECK(img[0] == 0.0f);
    CHECK(img[3 + 1] == 0.0f);
    CHECK(img[3 * 2] == 1.0f);
}

TEST_CASE("renderer: more passes on the same film continue the sequence", "[renderer]") {
    const int w = 20, h = 20;
    FirstDrawIntegrator integrator;
    std::vector<float> four = renderImage(integrator, options(w, h, 4, 2));
    Film film(w, h);
    render(emptyScene(), integrator, options(w, h, 2, 1), film);
    render(emptyScene(), integrator, options(w, h, 2, 2), film);
    CHECK(film.passes() == 4);
    std::vector<float> twice = film.rgb();
    for (size_t i = 0; i < four.size(); ++i) REQUIRE(twice[i] == Approx(four[i]).margin(1e-6));
}

TEST_CASE("renderer: a time budget renders whole passes, at least one", "[renderer]") {
    FirstDrawIntegrator integrator;
    RenderOptions o = options(16, 16, 1, 2);
    o.spp = 0;  // ignored with a budget
    o.timeBudget = 0.05;
    Film film(16, 16);
    RenderStats stats = render(emptyScene(), integrator, o, film);
    CHECK(stats.passes >= 1);
    CHECK(film.passes() == stats.passes);
    CHECK(stats.samples == uint64_t(256) * stats.passes);
    CHECK(stats.seconds >= 0.05);
    CHECK(stats.seconds < 5.0);

    o.timeBudget = 1e-9;
    Film film2(16, 16);
    CHECK(render(emptyScene(), integrator, o, film2).passes == 1);
}

// Passes of a steady pace (4 ms each, in endPass), with `leftOut` passes the image leaves out
// always (as auto's pilot and duel).
struct PacedIntegrator : Integrator {
    int leftOutPasses = 0;
    std::vector<FixedSum> sums = std::vector<FixedSum>(size_t(16 * 16 * 3));
    Spectrum sample(const Scene&, float, float, int, int, Sampler& sampler, PathStats&) const override {
        return Spectrum(sampler.next1D());
    }
    void endPass(const Scene&, const PassSummary&) override { std::this_thread::sleep_for(std::chrono::milliseconds(4)); }
    LeftOutPasses leftOut() const override {
        LeftOutPasses out;
        out.passes = leftOutPasses;
        out.sums = leftOutPasses > 0 ? &sums : nullptr;
        out.always = true;
        return out;
    }
};

TEST_CASE("renderer: the block of Sobol passes a time budget ends on", "[renderer]") {
    // 2^(⌊log2 n⌋ − 2): the image's passes end with their binary digits below the top three 0.
    const int n[] = {1, 3, 4, 7, 8, 15, 16, 255, 256, 319, 320, 511, 512, 1000};
    const int block[] = {1, 1, 1, 1, 2, 2, 4, 32, 64, 64, 64, 64, 128, 128};
    for (size_t i = 0; i < sizeof n / sizeof n[0]; ++i) {
        INFO(n[i]);
        CHECK(sobolBlock(n[i]) == block[i]);
    }
}

TEST_CASE("renderer: with sobolBlocks a time budget ends on a block of the image's passes", "[renderer]") {
    for (int left : {0, 3}) {
        PacedIntegrator integrator;
        integrator.leftOutPasses = left;
        RenderOptions o = options(16, 16, 1, 2);
        o.timeBudget = 0.6;  // about 150 passes: blocks of 32
        o.sobolBlocks = true;
        Film film(16, 16);
        RenderStats stats = render(emptyScene(), integrator, o, film);
        const int kept = imagePasses(film, integrator, o.sampler);
        INFO(left << " left out: " << stats.passes << " passes, " << kept << " in the image, " << stats.seconds << " s");
        CHECK(kept == stats.passes - left);
        // On a block, before the budget: the next block (32 passes, 0.13 s) would not fit.
        CHECK(kept % sobolBlock(kept) == 0);
        CHECK(stats.seconds < o.timeBudget);
        CHECK(kept >= 64);  // not stopped blocks too soon: a 4-ms pass, 0.6 s
        // Without it the budget is spent.
        o.sobolBlocks = false;
        Film whole(16, 16);
        CHECK(render(emptyScene(), integrator, o, whole).seconds >= o.timeBudget);
    }
}

TEST_CASE("renderer: cancellation stops after the current pass", "[renderer]") {
    FirstDrawIntegrator integrator;
    std::atomic<bool> cancel{true};
    Film film(16, 16);
    RenderStats stats = render(emptyScene(), integrator, options(16, 16, 50, 2), film, &cancel);
    CHECK(stats.passes == 1);
    CHECK(film.passes() == 1);
}

TEST_CASE("renderer: bad options and integrator exceptions", "[renderer]") {
    FirstDrawIntegrator integrator;
    Film film(16, 16);
    CHECK_THROWS_AS(render(emptyScene(), integrator, options(16, 15, 1, 1), film), std::invalid_argument);
    CHECK_THROWS_AS(render(emptyScene(), integrator, options(16, 16, 0, 1), film), std::invalid_argument);
    CHECK_THROWS_AS(render(emptyScene(), integrator, options(16, 16, 1, -1), film), std::invalid_argument);
    ThrowingIntegrator thrower;
    Film big(40, 40);
    CHECK_THROWS_WITH(render(emptyScene(), thrower, options(40, 40, 2, 2), big), "integrator failure");
}

namespace {

// FirstDrawIntegrator that raises `flag` when it reaches pixel (x, y) in pass `pass` (known
// from the sampler stream it is given: it compares the first draw with that of the target).
struct CancellingIntegrator : Integrator {
    std::atomic<bool>* flag;
    uint64_t seed;
    int width, x, y, pass;
    Spectrum sample(const Scene&, float fx, float fy, int, int, Sampler& sampler, PathStats&) const override {
        float v = sampler.next1D();
        if (int(fx) == x && int(fy) == y) {
            Sampler target(seed, uint64_t(y) * uint64_t(width) + uint64_t(x), uint64_t(pass));
            if (target.next1D() == v) flag->store(true);
        }
        return Spectrum(v);
    }
};

}  // namespace

TEST_CASE("film: restore puts the exact state back, splats included", "[film]") {
    Film film(3, 2);
    film.add(1, 1, Spectrum(0.1f, 0.2f, 0.3f));
    film.splat(2, 0, Spectrum(1.0f / 3.0f));
    film.completePass();
    Film copy(3, 2);
    copy.restore(film.passes(), film.sums(), film.hasSplats());
    CHECK(copy.passes() == 1);
    CHECK(copy.hasSplats());
    CHECK(copy.sums() == film.sums());
    CHECK(copy.rgb() == film.rgb());

    CHECK_THROWS_AS(copy.restore(-1, film.sums(), false), std::invalid_argument);
    CHECK_THROWS_AS(copy.restore(1, std::vector<Film::Sum>(17), false), std::invalid_argument);
    copy.restore(4, std::vector<Film::Sum>(18, toFixed(2.0f)), false);
    CHECK_FALSE(copy.hasSplats());
    CHECK(copy.pixel(0, 0).x == 0.5f);
}

// The sums are exact: any order of adding gives the same bits, where double sums would not
// (1e8 + 1 − 1e8 in one order, 1 − 1e8 + 1e8 in another).
TEST_CASE("film: sums do not depend on the order of adding", "[film]") {
    Rng rng(5, 1);
    std::vector<float> values;
    for (int i = 0; i < 2000; ++i) {
        const float mag = std::ldexp(rng.next1D(), int(rng.next1D() * 80) - 40);  // 2^-40 .. 2^40
        values.push_back(rng.next1D() < 0.2f ? -mag : mag);
    }
    values.push_back(1e-30f);  // below 2^-64: truncated to 0, the same in every order
    Film forward(1, 1), backward(1, 1), shuffled(1, 1);
    for (float v : values) forward.add(0, 0, Spectrum(v));
    for (size_t i = values.size(); i-- > 0;) backward.add(0, 0, Spectrum(values[i]));
    for (size_t k = 0; k < values.size(); ++k) shuffled.add(0, 0, Spectrum(values[(k * 7919) % values.size()]));
    CHECK(forward.sums() == backward.sums());
    CHECK(forward.sums() == shuffled.sums());
    double d1 = 0, d2 = 0;
    for (float v : values) d1 += v;
    for (size_t i = values.size(); i-- > 0;) d2 += values[i];
    INFO("double sums " << d1 << " and " << d2 << " (they may or may not differ; the exact ones may not)");
    // Conversion is exact for |v| >= 2^-40: 0.1f in and out.
    CHECK(fromFixed(toFixed(0.1f)) == double(0.1f));
    CHECK(fromFixed(toFixed(-3.5e7f)) == -3.5e7);
    CHECK(toFixed(0.0f) == 0);
}

TEST_CASE("renderer: a film restored between passes continues to the same bits", "[renderer]") {
    const int w = 37, h = 21;
    SplattingFake integrator;
    Film straight(w, h);
    render(emptyScene(), integrator, options(w, h, 5, 2), straight);

    Film first(w, h);
    render(emptyScene(), integrator, options(w, h, 2, 3), first);
    Film resumed(w, h);
    resumed.restore(first.passes(), first.sums(), first.hasSplats());
    render(emptyScene(), integrator, options(w, h, 3, 1), resumed);
    CHECK(resumed.passes() == 5);
    CHECK(resumed.sums() == straight.sums());
    CHECK(resumed.rgb() == straight.rgb());
}

TEST_CASE("renderer: dropInFlight abandons the pass in flight without a trace", "[renderer]") {
    const int w = 40, h = 40, spp = 6;  // 9 tiles
    const uint64_t seed = 7;

    SECTION("cancelled before the first pass: nothing rendered") {
        FirstDrawIntegrator integrator;
        std::atomic<bool> cancel{true};
        RenderControl control;
        control.cancel = &cancel;
        control.dropInFlight = true;
        Film film(w, h);
        RenderStats stats = render(emptyScene(), integrator, options(w, h, spp, 2, seed), film, control);
        CHECK(stats.passes == 0);
        CHECK(stats.samples == 0);
        CHECK(film.passes() == 0);
        for (Film::Sum v : film.sums()) REQUIRE(v == 0);
    }
    SECTION("cancelled in the middle of pass 2 (0-based): the film holds passes 0 and 1") {
        std::atomic<bool> cancel{false};
        CancellingIntegrator integrator;
        integrator.flag = &cancel;
        integrator.seed = seed;
        integrator.width = w;
        integrator.x = 20;  // the middle tile, so other tiles are left
        integrator.y = 20;
        integrator.pass = 2;
        RenderControl control;
        control.cancel = &cancel;
        control.dropInFlight = true;
        std::vector<int> seen;
        control.afterPass = [&](const Film& f, const RenderStats& s) {
            CHECK(f.passes() == s.passes);
            seen.push_back(f.passes());
        };
        Film film(w, h);
        RenderStats stats = render(emptyScene(), integrator, options(w, h, spp, 1, seed), film, control);
        CHECK(stats.passes == 2);
        CHECK(stats.samples == uint64_t(2 * w * h));
        CHECK(film.passes() == 2);
        CHECK(seen == std::vector<int>{1, 2});

        FirstDrawIntegrator plain;
        Film two(w, h);
        render(emptyScene(), plain, options(w, h, 2, 1, seed), two);
        CHECK(film.sums() == two.sums());
    }
    SECTION("without dropInFlight the pass in flight is finished") {
        std::atomic<bool> cancel{false};
        CancellingIntegrator integrator;
        integrator.flag = &cancel;
        integrator.seed = seed;
        integrator.width = w;
        integrator.x = 20;
        integrator.y = 20;
        integrator.pass = 2;
        Film film(w, h);
        RenderStats stats = render(emptyScene(), integrator, options(w, h, spp, 1, seed), film, &cancel);
        CHECK(stats.passes == 3);
        CHECK(film.passes() == 3);
    }
}

TEST_CASE("renderer: non-finite samples and splats of a dropped pass are not counted", "[renderer]") {
    struct Integrator2 : SplattingIntegrator {
        std::atomic<bool>* flag;
        Spectrum sampleWithSplats(const Scene&, float fx, float fy, int width, int height, Sampler&, PathStats&,
                                  SplatList& splats) const override {
            splats.splat(fx, fy, Spectrum(std::numeric_limits<float>::infinity()), width, height);
            if (int(fx) == 0 && int(fy) == 0) {
                // Pixel (0,0) is in the first tile: the third time round, cancel.
                if (++calls == 3) flag->store(true);
                return Spectrum(std::numeric_limits<float>::quiet_NaN());
            }
            return Spectrum(1.0f);
        }
        mutable std::atomic<int> calls{0};
    };
    std::atomic<bool> cancel{false};
    Integrator2 integrator;
    integrator.flag = &cancel;
    RenderControl control;
    control.cancel = &cancel;
    control.dropInFlight = true;
    const int w = 20, h = 20;
    Film film(w, h);
    RenderStats stats = render(emptyScene(), integrator, options(w, h, 5, 1), film, control);
    CHECK(stats.passes == 2);
    // Per completed pass: one NaN sample and one infinite splat per pixel.
    CHECK(stats.nonFinite == uint64_t(2 * (1 + w * h)));
    CHECK(film.pixel(0, 0).x == 0.0f);
    CHECK(film.pixel(5, 5).x == 1.0f);
}
