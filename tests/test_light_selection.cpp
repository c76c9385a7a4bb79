// Picks by where a connection starts (light_selection.h): the picks are distributions that
// sampling follows, keep power's floor, steer towards the near light, and fall back to power
// bit for bit; and the path tracer and the bidirectional tracer (whose light connection picks
// so) stay unbiased with them, against quadrature of single scattering from six lights of four
// kinds in every --connect mode.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_selection.h"
#include "support/block_z.h"
#include "support/film_estimates.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

// many_lights.gltf (tests/data/make_test_scenes.py): lights 0 and 1 the points (near, and
// bright far off), 2 the spot, 3 the sphere below the view, 4 and 5 the quad's halves.
const Vec3 kNear(0.3f, 0.2f, -1.5f), kFar(-12.0f, -0.5f, -20.0f), kSpot(0.0f, 1.5f, -3.0f), kLow(0.0f, -1.5f, -3.0f);

struct Segment {
    Vec3 o, d;
    float tEnd;
};

std::vector<Vec3> testPoints() {
    std::vector<Vec3> p;
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 5; ++j) p.push_back(Vec3(-2.0f + 0.7f * i, -1.0f + 0.6f * j, -0.5f - 1.1f * i - 0.3f * j));
    p.push_back(kNear + Vec3(0.01f, 0, 0));
    p.push_back(kFar);  // on the light: the smallest distance
    return p;
}

std::vector<Segment> testSegments() {
    std::vector<Segment> s;
    for (const Vec3& p : testPoints()) {
        s.push_back(Segment{Vec3(0.0f), normalize(p + Vec3(0, 0, -0.1f)), length(p)});
        s.push_back(Segment{p, normalize(Vec3(0.3f, -0.2f, -1.0f)), kInfinity});
    }
    s.push_back(Segment{kFar + Vec3(0, 0.01f, 2), Vec3(0, 0, -1), 4.0f});  // passes 1 cm from "bright"
    return s;
}

// Every light drawn from n stratified numbers, against pmf: counts within one of n·pmf, and the
// pmf each draw returns the one asked for.
template <class Sample, class Pmf>
void requireSamplingFollows(int lights, Sample sample, Pmf pmf) {
    const int n = 20000;
    std::vector<int> count(size_t(lights), 0);
    for (int k = 0; k < n; ++k) {
        float p = -1;
        const int i = sample((k + 0.5f) / n, &p);
        REQUIRE(i >= 0);
        REQUIRE(i < lights);
        REQUIRE(p == pmf(i));
        ++count[size_t(i)];
    }
    for (int i = 0; i < lights; ++i) CHECK(std::abs(count[size_t(i)] - n * double(pmf(i))) <= 1.5);
}

}  // namespace

TEST_CASE("light selection: picks are distributions that sampling follows, over power's floor", "[light_selection]") {
    auto scene = loadTestScene("many_lights.gltf");
    const LightSelection& sel = scene->lightSelection();
    const int n = int(scene->lights().size());
    REQUIRE(n == 6);
    REQUIRE(sel.spatial());
    const auto& power = scene->lightDistribution();
    for (const Vec3& x : testPoints()) {
        double sum = 0;
        for (int i = 0; i < n; ++i) {
            sum += sel.pmfAt(x, i);
            CHECK(sel.pmfAt(x, i) >= 0.1f * power.pmf(i) * (1 - 1e-5f));
        }
        CHECK(sum == Approx(1.0).epsilon(1e-5));
        CHECK(sel.pmfAt(x, 4) == sel.pmfAt(x, 5));  // a rectangle's halves: one pick
        requireSamplingFollows(n, [&](float u, float* p) { return sel.sampleAt(x, u, p); },
                               [&](int i) { return sel.pmfAt(x, i); });
    }
    for (const Segment& s : testSegments()) {
        double sum = 0;
        for (int i = 0; i < n; ++i) {
            sum += sel.pmfAlong(s.o, s.d, s.tEnd, i);
            CHECK(sel.pmfAlong(s.o, s.d, s.tEnd, i) >= 0.1f * power.pmf(i) * (1 - 1e-5f));
        }
        CHECK(sum == Approx(1.0).epsilon(1e-5));
        // Along a segment planar emitters keep power's pick (light_selection.h).
        CHECK(sel.pmfAlong(s.o, s.d, s.tEnd, 4) == Approx(power.pmf(4)).epsilon(1e-5));
        requireSamplingFollows(n, [&](float u, float* p) { return sel.sampleAlong(s.o, s.d, s.tEnd, u, p); },
                               [&](int i) { return sel.pmfAlong(s.o, s.d, s.tEnd, i); });
    }
}

TEST_CASE("light selection: the near light gets the pick, weights as the header derives them", "[light_selection]") {
    auto scene = loadTestScene("many_lights.gltf");
    const LightSelection& sel = scene->lightSelection();
    const auto& power = scene->lightDistribution();
    // 1 cm from "near": its weight I/r² = 10/1e-4 dwarfs the others'.
    CHECK(sel.pmfAt(kNear + Vec3(0.01f, 0, 0), 0) > 0.1f * power.pmf(0) + 0.89f);
    // A segment passing 1 cm from "bright" gives it nearly all the point-like lights' steered
    // share (0.9 of their power's).
    const Segment s{kFar + Vec3(0, 0.01f, 2), Vec3(0, 0, -1), 4.0f};
    const double pointLike = power.pmf(0) + power.pmf(1) + power.pmf(2) + power.pmf(3);
    CHECK(sel.pmfAlong(s.o, s.d, s.tEnd, 1) > 0.1 * power.pmf(1) + 0.89 * pointLike);
    // The weights themselves: I/r² at a point; the spot's cone (outside it: 0); I·Δθ/D along a
    // segment (here the segment's middle passes "near" at D = 0.5: Δθ = 2·atan(1/0.5)).
    const Vec3 x(0.3f, 0.2f, -3.5f);
    const auto wAt = sel.weightsAt(x);
    CHECK(wAt[0] == Approx(10.0 / 4.0).epsilon(1e-5));
    CHECK(wAt[2] == 0.0f);  // below the spot but 63° off its axis
    const auto wAlong = sel.weightsAlong(kNear + Vec3(0.5f, 0, 1), Vec3(0, 0, -1), 2.0f);
    CHECK(wAlong[0] == Approx(10.0 * 2.0 * std::atan(2.0) / 0.5).epsilon(1e-4));
    CHECK(wAlong[4] == 0.0f);
}

TEST_CASE("light selection: power's picks, bit for bit, where it does not apply", "[light_selection]") {
    for (const char* file : {"single_near.gltf", "furnace_ambient.gltf"}) {  // one light; 2208 triangles
        auto scene = loadTestScene(file);
        const LightSelection& sel = scene->lightSelection();
        CHECK_FALSE(sel.spatial());
        const auto& power = scene->lightDistribution();
        for (int i = 0; i < std::min(3, power.size()); ++i) {
            CHECK(sel.pmfAt(Vec3(0.1f, 0.2f, -1), i) == power.pmf(i));
            CHECK(sel.pmfAlong(Vec3(0.0f), Vec3(0, 0, -1), 3.0f, i) == power.pmf(i));
        }
        for (float u : {0.0f, 0.3f, 0.77f, 0.999f}) {
            float a, b;
            CHECK(sel.sampleAt(Vec3(0.5f), u, &a) == power.sample(u, &b));
            CHECK(a == b);
        }
    }
}

// The quadrature oracle: the sum of each light's single scattering (no light shadows another
// here: make_test_scenes.py, many_lights). Every connect mode makes its picks by position
// (A, C and D along the camera ray, B's weight from the segment before the light it hits),
// and each technique's weight reads the others' picks, so a pick density that differs from
// the one sampled shows here as a bias.
namespace {

// Single scattering along the camera ray d from the six lights: the sum of each light's
// quadrature. The point-like lights' part (with n steps) and the extended lights' (out of view:
// smooth over the image) apart, for block averages that sample them on grids of their own.
double pointLikeReference(Vec3 d, int n = 20000) {
    static const Light spot = singleSpotLight();
    const Vec3 s{float(kSigmaS)}, a{float(kSigmaT - kSigmaS)};
    return double(singleScatterReference(d, kNear, Vec3(10.0f), s, a, kG, nullptr, n).x) +
           double(singleScatterReference(d, kFar, Vec3(1000.0f), s, a, kG, nullptr, n).x) +
           double(singleScatterReference(d, kSpot, Vec3(30.0f), s, a, kG, &spot, n).x);
}
double extendedReference(Vec3 d) {
    return sphereReference(d, kLow, 0.4, 10.0) + quadReference(d, Vec3(0, 2, -3), Vec3(0.5f, 0, 0), Vec3(0, 0, 0.5f), Vec3(0, -1, 0), 40.0);
}
double manyLightsReference(Vec3 d) { return pointLikeReference(d) + extendedReference(d); }

}  // namespace

TEST_CASE("single scattering from six lights matches quadrature with picks by position", "[oracle][pt][light_selection][sanitizer-skip]") {
    const int W = 8, H = 8;
    auto scene = loadTestScene("many_lights.gltf");
    std::vector<double> ref(size_t(W * H));
    for (int i = 0; i < W * H; ++i) ref[size_t(i)] = manyLightsReference(referenceCameraDirection(i % W, i / W, W, H, kYfov));
    const double bound = zBound(W * H);
    for (ConnectMode mode : kConnectModes) {
        PathTracer pt(PathTracerOptions{1, true, mode});
        const auto px = estimatePixels(*scene, pt, W, H, 16384, 23);
        double worst = 0, worstScaled = 0;
        int worstI = 0;
        for (size_t i = 0; i < px.size(); ++i) {
            const double se = px[i].stderror(0);
            const double z = std::abs(px[i].mean(0) - ref[i]) / se;
            if (z > worst) worst = z, worstI = int(i);
            worstScaled = std::max(worstScaled, std::abs(px[i].mean(0) - 1.03 * ref[i]) / se);
        }
        INFO(connectModeName(mode) << ": worst pixel " << worstI % W << "," << worstI / W << ": "
                                   << px[size_t(worstI)].mean(0) << " ± " << px[size_t(worstI)].stderror(0) << " vs "
                                   << ref[size_t(worstI)] << " (z = " << worst << ", bound " << bound << ")");
        CHECK(worst < bound);
        CHECK(worstScaled > bound);  // the power to see a 3% error
    }
}

// The bidirectional tracer's light connection picks by where it starts (light_numbers.h),
// its light subpaths by power: the weights must carry the ratio of the two (bdpt_mis.cpp); and
// with the three point-like lights alone (many_points.gltf) single scattering is split between
// the path tracer, which picks along the camera ray, and light tracing, which picks by power
// (one_event_split.h). Estimates of 2x2 blocks from 32 independent renders (light tracing
// splats anywhere in a pixel), against the quadrature averaged over a 16x16 grid of film
// positions per block (4x4 for the lights out of view); blocks holding a point-like light in
// view (a 1/angle peak) are skipped.
TEST_CASE("bdpt: single scattering from six lights matches quadrature with the light connection's picks by position",
          "[oracle][bdpt][light_selection][sanitizer-skip]") {
    const int W = 8, B = 2, S = 16, SE = 4, blocks = W / B;
    for (bool extended : {true, false}) {
        const char* file = extended ? "many_lights.gltf" : "many_points.gltf";
        auto scene = loadTestScene(file);
        std::vector<bool> skip(size_t(blocks * blocks), false);
        for (Vec3 p : {kNear, kFar, kSpot}) {
            CameraConnection cc;
            if (connectToCamera(scene->camera(), p, W, W, &cc)) skip[size_t(int(cc.fy) / B) * blocks + int(cc.fx) / B] = true;
        }
        std::vector<double> ref(skip.size(), 0.0);
        for (size_t i = 0; i < ref.size(); ++i) {
            const int bx = int(i) % blocks, by = int(i) / blocks;
            auto at = [&](int j, int k, int n) {
                return referenceCameraDirection(bx * B + (k + 0.5) * B / n, by * B + (j + 0.5) * B / n, W, W, kYfov);
            };
            double points = 0, others = 0;
            for (int j = 0; j < S; ++j)
                for (int k = 0; k < S; ++k) points += pointLikeReference(at(j, k, S), 2000);
            for (int j = 0; extended && j < SE; ++j)
                for (int k = 0; k < SE; ++k) others += extendedReference(at(j, k, SE));
            ref[i] = points / (S * S) + others / (SE * SE);
        }
        for (ConnectMode mode : {ConnectMode::Density, ConnectMode::Mis}) {
            BdptOptions o{1, MisHeuristic::Power};
            o.connect = mode;
            std::string where, whereScaled;
            const auto px = estimateFilm(*scene, BdptIntegrator(o), W, W, 256, 32, 29, B);
            const double z = worstZ(px, blocks, skip, [&](int x, int y) { return Vec3(float(ref[size_t(y * blocks + x)])); }, &where);
            // The power to see an error of 3% (free flight alone, the noisier here: 6%).
            const double up = mode == ConnectMode::Density ? 1.06 : 1.03;
            const double zScaled =
                worstZ(px, blocks, skip, [&](int x, int y) { return Vec3(float(up * ref[size_t(y * blocks + x)])); }, &whereScaled);
            INFO(file << " --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z
                      << "); against the reference made " << up << "x: " << zScaled);
            CHECK(z < 4.5);  // 32 batches: test_bdpt_oracles.cpp's bound
            CHECK(zScaled > 4.5);
        }
    }
}
