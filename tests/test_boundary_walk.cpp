// The one walk through invisible medium boundaries (boundary_walk.h) and the medium interface
// behind it: an edge's transmittance and free-flight densities are the same traced from either
// end, the pieces add up to the segment, and Medium answers with its closed forms.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/visibility.h"
#include "brume/sampling/free_flight.h"
#include "support/pixel_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

double relDiff(double a, double b) { return std::abs(a - b) / std::max(std::abs(a), std::abs(b)); }

}  // namespace

TEST_CASE("boundary walk: an edge through a fog box has the same densities from either end", "[medium][boundary]") {
    // Fog box [-1, 1] × [-1, 1] × [-4.5, -2.5] behind an invisible boundary, floor at y = -1.2
    // (normal +y), camera at the origin, outside the box.
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    Rng rng(7, 1);
    ShadowTarget floor;
    int checked = 0, crossed = 0;
    for (int i = 0; i < 400; ++i) {
        // a: a medium point in the box; b: a point on the floor or the pinhole.
        Vec3 a(-0.9f + 1.8f * rng.next1D(), -0.9f + 1.8f * rng.next1D(), -4.4f + 1.8f * rng.next1D());
        const bool onFloor = i % 2 == 0;
        Vec3 b = onFloor ? Vec3(-1.4f + 2.8f * rng.next1D(), -1.2f, -4.9f + 2.8f * rng.next1D()) : Vec3(0.0f);
        SurfaceHit probe = scene->intersect(Ray{b + Vec3(0, 0.1f, 0), Vec3(0, -1, 0), 0.2f});  // the floor under b
        if (onFloor && !probe.valid()) continue;
        ShadowTarget bTarget;
        if (onFloor) bTarget.mesh = probe.mesh, bTarget.triangle = probe.triangle;
        Vec3 bNormal = onFloor ? Vec3(0, 1, 0) : Vec3(0.0f);
        Vec3 d = b - a;
        float dist = length(d);
        d /= dist;
        PathStats stats;
        Connection ab = connectPoints(*scene, leaving(a, Vec3(0.0f), d, dist, onFloor, bTarget), scene->mediaAt(a), true,
                                      false, stats);
        ShadowTarget none;
        Connection ba = connectPoints(*scene, leaving(b, bNormal, -d, dist, false, none), scene->mediaAt(b + bNormal * 1e-3f),
                                      false, true, stats);
        INFO("a (" << a.x << ", " << a.y << ", " << a.z << ") b (" << b.x << ", " << b.y << ", " << b.z << ")");
        REQUIRE(isBlack(ab.T) == isBlack(ba.T));
        if (isBlack(ab.T)) continue;  // blocked by the floor's edge or the light
        ++checked;
        crossed += ab.crossed;
        CHECK(ab.crossed == ba.crossed);
        CHECK(relDiff(ab.T.x, ba.T.x) < 1e-5);
        // The walk a → b stops at b exactly as the walk b → a passes it, and back.
        for (int c = 0; c < 3; ++c) {
            CHECK(relDiff(ab.freeFlightToB[c], ba.freeFlightToA[c]) < 1e-5);
            CHECK(relDiff(ab.freeFlightToA[c], ba.freeFlightToB[c]) < 1e-5);
        }
    }
    CHECK(checked > 100);
    CHECK(crossed > 100);
}

TEST_CASE("boundary walk: pieces cover the segment exactly, one medium each", "[medium][boundary]") {
    auto scene = loadTestScene("bdpt_quad_fogbox.gltf");
    // From the pinhole straight through the box: vacuum, fog over z in [-4.5, -2.5], vacuum.
    const Vec3 d(0, 0, -1);
    PathStats stats;
    BoundaryWalk walk(*scene, leaving(Vec3(0.0f), Vec3(0.0f), d, 6.0f), scene->cameraMedia(), stats);
    BoundaryPiece piece;
    std::vector<BoundaryPiece> pieces;
    while (walk.next(&piece)) pieces.push_back(piece);
    REQUIRE(pieces.size() == 3);
    CHECK(pieces[0].t0 == 0.0f);
    CHECK(pieces[0].medium == nullptr);
    CHECK(pieces[0].t1 == Approx(2.5f).epsilon(1e-6));
    CHECK(pieces[1].t0 == pieces[0].t1);
    CHECK(pieces[1].medium != nullptr);
    CHECK(pieces[1].t1 == Approx(4.5f).epsilon(1e-6));
    CHECK(pieces[2].t0 == pieces[1].t1);
    CHECK(pieces[2].medium == nullptr);
    CHECK(pieces[2].t1 == 6.0f);
    CHECK(walk.crossed());
}

TEST_CASE("medium: a homogeneous medium answers with its closed forms", "[medium]") {
    Medium m;
    m.sigmaS = Spectrum(0.4f, 0.8f, 1.2f);
    m.sigmaA = Spectrum(0.1f);
    const Spectrum st = m.sigmaT();  // 0.5, 0.9, 1.3
    const Ray ray{Vec3(1, 2, 3), Vec3(0, 0, 1)};
    // Only the piece's length counts: [2, 2.75] as [0, 0.75]; densities per channel.
    MediumTransit tr = m.transit(ray, 2.0f, 2.75f, true, false);
    CHECK(tr.T.y == Approx(std::exp(-0.9 * 0.75)));
    for (int c = 0; c < 3; ++c) {
        CHECK(tr.fwd[c] == Approx(freeFlightPdfPass(st[c], 0.75f)));     // passes the end
        CHECK(tr.rev[c] == Approx(freeFlightPdfScatter(st[c], 0.75f)));  // the reverse walk stops at the start
    }
    CHECK(m.transmittance(ray, 2.0f, 2.75f).z == Approx(std::exp(-1.3 * 0.75)));
    // Channel weights w: the density is the mixture Σ w_c p_c, the weight f_c / mixture.
    const Spectrum w(0.2f, 0.3f, 0.5f);
    Rng rng(3, 4);
    int scattered = 0, picked[3] = {0, 0, 0};
    for (int i = 0; i < 2000; ++i) {
        const float uChannel = rng.next1D();
        MediumSample ms = m.sampleDistance(ray, 1.0f, 3.0f, rng.next1D(), uChannel, w, false);
        ++picked[pickChannel(w, uChannel)];
        const float len = ms.t - 1.0f;
        REQUIRE(ms.t >= 1.0f);
        REQUIRE(ms.t <= 3.0f);
        double mix = 0;
        for (int c = 0; c < 3; ++c) {
            const double p = ms.scattered ? freeFlightPdfScatter(st[c], len) : freeFlightPdfPass(st[c], len);
            REQUIRE(ms.fwd[c] == Approx(p));
            REQUIRE(ms.rev[c] == Approx(freeFlightPdfPass(st[c], len)));
            mix += w[c] * p;
        }
        REQUIRE(ms.pdf == Approx(mix));
        if (ms.scattered) {
            ++scattered;
            REQUIRE(ms.weight.x == Approx(std::exp(-0.5 * len) * 0.4 / mix));
            REQUIRE(ms.weight.z == Approx(std::exp(-1.3 * len) * 1.2 / mix));
        } else {
            REQUIRE(ms.t == 3.0f);
            REQUIRE(ms.weight.z == Approx(std::exp(-1.3 * 2.0) / mix));
        }
    }
    CHECK(scattered > 1000);
    CHECK(picked[0] > 300);  // 400 expected
    CHECK(picked[2] > 900);  // 1000 expected
    // A hero channel (one-hot weights): its own density, the others' ratios in the weight.
    for (int i = 0; i < 200; ++i) {
        MediumSample ms = m.sampleDistance(ray, 0.0f, 2.0f, rng.next1D(), rng.next1D(), heroChannel(2), false);
        REQUIRE(ms.pdf == Approx(ms.fwd[2]));
    }
    // A grey medium takes its own path (one exponential): the same closed forms.
    Medium grey;
    grey.sigmaS = Spectrum(0.6f);
    grey.sigmaA = Spectrum(0.2f);
    for (int i = 0; i < 200; ++i) {
        MediumSample ms = grey.sampleDistance(ray, 0.0f, 2.0f, rng.next1D(), rng.next1D(), w, true);
        const double len = ms.t;
        if (ms.scattered) {
            REQUIRE(ms.pdf == Approx(0.8 * std::exp(-0.8 * len)));
            REQUIRE(ms.rev[1] == Approx(ms.pdf));  // the reverse walk scatters at the start point
            REQUIRE(ms.weight.y == Approx(std::exp(-0.8 * len) * 0.6 / ms.pdf));
        } else {
            REQUIRE(ms.pdf == Approx(std::exp(-1.6)));
            REQUIRE(ms.rev[0] == Approx(0.8 * std::exp(-1.6)));
            REQUIRE(ms.weight.x == Approx(1.0));
        }
        REQUIRE(ms.fwd[2] == Approx(ms.pdf));
    }
    MediumTransit gt = grey.transit(ray, 0.5f, 2.0f, false, true);
    CHECK(gt.T.x == Approx(std::exp(-0.8 * 1.5)));
    CHECK(gt.fwd[1] == Approx(0.8 * std::exp(-0.8 * 1.5)));
    CHECK(gt.rev[2] == Approx(std::exp(-0.8 * 1.5)));
    // Over an infinite piece nothing passes.
    MediumSample out = m.sampleDistance(ray, 0.0f, kInfinity, 0.999999f, 0.1f, w, false);
    CHECK((out.scattered || isBlack(out.weight)));
}
