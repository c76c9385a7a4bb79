// The equi-angular sampler: chi-square against its pdf, pdf integrates to 1, inverse-CDF
// round trip, edge cases (D → 0, unbounded segments, segments behind the closest approach,
// tiny segments), and the spot-cone clip used to restrict segments.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/integrators/equiangular_segment.h"
#include "brume/math/fast_atan.h"
#include "brume/math/frame.h"
#include "brume/sampling/equiangular.h"
#include "brume/sampling/sampler.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

struct Case {
    const char* name;
    Vec3 c;      // light position; the ray is the +z axis from the origin
    float a, b;  // segment
};

// Ray along +z from the origin; Δ = c.z, D = sqrt(c.x² + c.y²).
const Case kCases[] = {
    {"light beside the middle", Vec3(0.5f, 0, 2), 0, 4},
    {"far light, long segment", Vec3(3, 4, 10), 0.5f, 30},
    {"segment wholly before the closest approach", Vec3(0.2f, 0, 10), 0, 3},
    {"segment wholly behind the closest approach", Vec3(0.3f, 0.1f, -2), 1, 6},
    {"light very close to the ray", Vec3(1e-3f, 0, 1), 0, 2},
    {"long segment, light near the start", Vec3(0.05f, 0.05f, 0.1f), 0, 50},
};

}  // namespace

TEST_CASE("equi-angular samples follow their pdf (chi-square, p > 0.01 / cases)", "[sampling][equiangular]") {
    const double alpha = 0.01 / double(std::size(kCases));
    for (const Case& c : kCases) {
        EquiAngular ea = makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), c.c, c.a, c.b);
        REQUIRE_FALSE(ea.uniform);
        // Bins equal in angle carry equal probability; put the edges there so that even the
        // sharply peaked cases have well-filled bins.
        auto result = intervalHistogramTest(
            [&](Sample2 u) { return std::optional<double>(sampleEquiAngular(ea, u.u)); },
            [&](double t) { return double(equiAngularPdf(ea, float(t))); }, c.a, c.b, 40, 400000);
        INFO(c.name << "\n" << result.chi2.table);
        CHECK(result.chi2.pValue > alpha);
        CHECK(result.outside == 0);
        CHECK(result.pdfIntegral == Approx(1.0).epsilon(2e-3));
    }
}

TEST_CASE("equi-angular pdf integrates to 1 and the cdf inverts", "[sampling][equiangular]") {
    for (const Case& c : kCases) {
        EquiAngular ea = makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), c.c, c.a, c.b);
        // Integrate in θ where the pdf is flat: ∫ pdf dt = ∫ pdf(t(θ)) dt/dθ dθ.
        double integral = integrate1D([&](double t) { return double(equiAngularPdf(ea, float(t))); }, c.a, c.b, 1e-9, 1e-7);
        INFO(c.name);
        CHECK(integral == Approx(1.0).epsilon(1e-3));
        // Round trip: the cdf of the sampled t is ξ. cdf(t) = (atan((t−Δ)/D) − θa)/(θb − θa).
        for (float u : {0.0f, 0.1f, 0.37f, 0.5f, 0.81f, 0.999f}) {
            float t = sampleEquiAngular(ea, u);
            double cdf = (std::atan((double(t) - ea.delta) / ea.D) - ea.thetaA) / (ea.thetaB - ea.thetaA);
            CHECK(cdf == Approx(u).margin(1e-4));
        }
    }
}

TEST_CASE("equi-angular edge cases stay finite", "[sampling][equiangular]") {
    SECTION("light exactly on the ray (D = 0)") {
        EquiAngular ea = makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, 2), 0, 4);
        CHECK(ea.D > 0);
        for (float u : {0.0f, 0.25f, 0.5f, 0.75f, 0.9999f}) {
            float t = sampleEquiAngular(ea, u);
            float pdf = equiAngularPdf(ea, t);
            CHECK(std::isfinite(t));
            CHECK(t >= 0);
            CHECK(t <= 4);
            CHECK(std::isfinite(pdf));
            CHECK(pdf > 0);
        }
    }
    SECTION("unbounded segment: θb = π/2, samples finite, pdf integrates to 1") {
        EquiAngular ea = makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 3), 0, INFINITY);
        CHECK(ea.thetaB == Approx(0.5 * M_PI));
        for (float u : {0.0f, 0.5f, 0.999999f}) {
            float t = sampleEquiAngular(ea, u);
            CHECK(std::isfinite(t));
            CHECK(equiAngularPdf(ea, t) > 0);
        }
        // ∫0^∞ D/((θb−θa)(D²+(t−Δ)²)) dt = 1 exactly; numerically via t = Δ + D tanθ.
        double sum = 0;
        const int n = 100000;
        for (int i = 0; i < n; ++i) {
            double th = ea.thetaA + (ea.thetaB - ea.thetaA) * (i + 0.5) / n;
            double t = ea.delta + ea.D * std::tan(th);
            sum += double(equiAngularPdf(ea, float(t))) * ea.D / (std::cos(th) * std::cos(th));
        }
        CHECK(sum * (ea.thetaB - ea.thetaA) / n == Approx(1.0).epsilon(1e-3));
    }
    SECTION("very short segment far away falls back to uniform") {
        EquiAngular ea = makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0, 1000, 0), 5.0f, 5.0f + 1e-5f);
        CHECK(ea.uniform);
        float t = sampleEquiAngular(ea, 0.5f);
        CHECK(t >= 5.0f);
        CHECK(t <= 5.0f + 1e-5f);
        CHECK(std::isfinite(equiAngularPdf(ea, t)));
    }
}

TEST_CASE("spot-cone clipping keeps every point inside the cone", "[sampling][equiangular]") {
    Light spot;
    spot.kind = LightKind::Spot;
    spot.position = Vec3(0, 2, 0);
    spot.direction = normalize(Vec3(0.2f, -1, 0.1f));
    spot.cosInner = std::cos(0.2f);
    spot.cosOuter = std::cos(0.45f);
    Pcg32 rng(7, 3);
    auto uni = [&] { return float(rng.next() >> 8) * 0x1p-24f; };
    int clippedAway = 0, kept = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 o(uni() * 8 - 4, uni() * 6 - 3, uni() * 8 - 4);
        Vec3 d = normalize(Vec3(uni() * 2 - 1, uni() * 2 - 1, uni() * 2 - 1));
        float t0 = 0, t1 = 10;
        bool any = clipToSpotCone(spot, o, d, &t0, &t1);
        // Dense check along [0, 10]: points in the cone must lie in the clipped interval.
        for (int k = 0; k <= 400; ++k) {
            float t = 10.0f * k / 400;
            Vec3 w = o + d * t - spot.position;
            float len = length(w);
            bool inside = len > 0 && dot(w, spot.direction) / len > spot.cosOuter + 1e-4f;
            if (inside) {
                REQUIRE(any);
                REQUIRE(t >= t0 - 1e-3f);
                REQUIRE(t <= t1 + 1e-3f);
            }
        }
        if (any) {
            ++kept;
            // The ends of the clipped interval lie on the cone (or the segment's ends).
            for (float t : {t0, t1}) {
                if (t <= 1e-4f || t >= 10 - 1e-4f) continue;
                Vec3 w = o + d * t - spot.position;
                CHECK(dot(w, spot.direction) / length(w) == Approx(spot.cosOuter).margin(1e-3));
            }
        } else {
            ++clippedAway;
        }
    }
    CHECK(kept > 100);
    CHECK(clippedAway > 100);
}

// The bidirectional weights' stand-in density (float, polynomial atan) is the unbounded-ray
// equi-angular density: within 1e-5 of the double computation over offsets from far behind to
// far ahead of the ray origin, and over distances from the closest approach to 1e4·D, plus
// what float positions allow: D comes from c − o less its part along the ray, known to
// ~2^-23·|c − o|.
TEST_CASE("equi-angular stand-in density matches the double computation", "[equiangular]") {
    for (double x : {-1e4, -30.0, -1.5, -1.0, -0.3, 0.0, 1e-3, 0.7, 1.0, 2.0, 1e3})
        CHECK(std::abs(double(halfPiPlusAtan(float(x))) - (M_PI / 2 + std::atan(x))) <=
              1e-6 * (M_PI / 2 + std::atan(x)) + 1e-7);
    const Vec3 o(0.3f, -0.2f, 1.0f), d = normalize(Vec3(0.2f, 1.0f, -0.4f));
    double worst = 0;
    for (float D : {0.01f, 0.5f, 3.0f})
        for (float delta : {-40.0f, -2.0f, 0.0f, 0.4f, 5.0f, 200.0f}) {
            Vec3 side = normalize(cross(d, Vec3(1, 0, 0)));
            Vec3 c = o + d * delta + side * D;
            EquiAngular ea = makeEquiAngular(o, d, c, 0.0f, kInfinity);
            for (float t : {0.0f, 0.01f, std::max(0.0f, delta), delta + D, 3 * D + 1, 1e4f * D}) {
                if (t < 0) continue;
                double ref = equiAngularPdf(ea, t), got = equiAngularStandInPdf(o, d, c, t);
                REQUIRE(got > 0);
                double tolerance = 1e-5 + 8 * 0x1p-23 * length(c - o) / D;
                worst = std::max(worst, std::abs(got - ref) / ref / tolerance);
            }
        }
    INFO("worst relative difference over its tolerance " << worst);
    CHECK(worst < 1);
}
