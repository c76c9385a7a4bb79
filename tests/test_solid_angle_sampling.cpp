// The solid angle of a triangle, uniform sampling of spherical triangles (Arvo), and
// distance sampling in proportion to an emitter's solid angle along a segment
// (integrators/solid_angle_segment.h): closed forms, chi-square against independent
// densities (significance 0.01 per case, Bonferroni over a case's parameter sets), and the
// tabulated density integrating to 1. Seeds are fixed.
#include <catch2/catch.hpp>

#include <cmath>
#include <optional>

#include "brume/integrators/solid_angle_segment.h"
#include "brume/sampling/spherical_rectangle.h"
#include "brume/sampling/spherical_triangle.h"
#include "brume/scene/light_sampling.h"
#include "brume/scene/scene.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

struct D3 {
    double x, y, z;
};
D3 d3(Vec3 v) { return {v.x, v.y, v.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double ddot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 dcross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dlen(D3 a) { return std::sqrt(ddot(a, a)); }
D3 dnorm(D3 a) { return a * (1.0 / dlen(a)); }

// Girard's theorem: the angle excess, an oracle independent of Van Oosterom–Strackee.
double girard(D3 o, D3 a, D3 b, D3 c) {
    D3 A = dnorm(a - o), B = dnorm(b - o), C = dnorm(c - o);
    auto angle = [](D3 p, D3 q, D3 r) {
        return std::acos(std::max(-1.0, std::min(1.0, ddot(dnorm(dcross(p, q)), dnorm(dcross(p, r))))));
    };
    return angle(A, B, C) + angle(B, C, A) + angle(C, A, B) - M_PI;
}

std::optional<double> rayTriangle(D3 o, D3 w, D3 p0, D3 p1, D3 p2) {
    D3 e1 = p1 - p0, e2 = p2 - p0, pv = dcross(w, e2);
    double det = ddot(e1, pv);
    if (det == 0) return std::nullopt;
    D3 tv = o - p0;
    double b1 = ddot(tv, pv) / det;
    if (b1 < 0 || b1 > 1) return std::nullopt;
    D3 qv = dcross(tv, e1);
    double b2 = ddot(w, qv) / det;
    if (b2 < 0 || b1 + b2 > 1) return std::nullopt;
    double t = ddot(e2, qv) / det;
    return t > 0 ? std::optional<double>(t) : std::nullopt;
}

// Histogram options for directions towards a polygon with corners `corners`, seen from o: cosθ
// bins around the direction to `centre`, uniform from a little below the widest corner, and one
// empty bin below.
SphereHistogramOptions polygonHistogram(D3 o, D3 centre, std::initializer_list<D3> corners, uint64_t seed) {
    const D3 axis = dnorm(centre - o);
    double cosMin = 1;
    for (const D3& p : corners) cosMin = std::min(cosMin, ddot(axis, dnorm(p - o)));
    SphereHistogramOptions opt;
    opt.seed = seed;
    opt.axis = Vec3(float(axis.x), float(axis.y), float(axis.z));
    const double lo = std::max(-1.0, cosMin - 0.02 * (1.0 - cosMin));
    opt.cosThetaEdges = uniformEdges(20, lo, 1.0);
    if (lo > -1.0) opt.cosThetaEdges.insert(opt.cosThetaEdges.begin(), -1.0);
    return opt;
}

struct TriangleCase {
    const char* name;
    Vec3 x, p0, p1, p2;
};

const TriangleCase kTriangles[] = {
    {"ordinary", Vec3(0.1f, -0.2f, 0.0f), Vec3(-1, -1, 2), Vec3(1.5f, -0.5f, 2.2f), Vec3(0.2f, 1.2f, 1.8f)},
    {"sliver (20:1)", Vec3(0, 0, 0), Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0.1f, 0.1f, 1)},
    {"grazing (5 cm above the plane)", Vec3(0.3f, 0.4f, 0.05f), Vec3(0.1f, -1, 0), Vec3(3, -1.2f, 0), Vec3(2.7f, 1, 0)},
    {"close over the interior (Ω ≈ 5.9)", Vec3(0.2f, 0.1f, 0.03f), Vec3(-1, -1, 0), Vec3(1.5f, -1, 0), Vec3(0, 1.5f, 0)},
    {"small and far (Ω ≈ 4e-4)", Vec3(0, 0, 0), Vec3(-0.1f, -0.1f, 10), Vec3(0.1f, -0.1f, 10), Vec3(0, 0.1f, 10)},
};

}  // namespace

TEST_CASE("triangle solid angle: closed forms, the far limit, the side", "[sampling][solidangle]") {
    // Each face of the cube [−1, 1]³ subtends 4π/6 at its centre; each half of a face π/3.
    const Vec3 o(0, 0, 0);
    CHECK(triangleSolidAngle(o, Vec3(-1, -1, 1), Vec3(1, -1, 1), Vec3(1, 1, 1)) == Approx(M_PI / 3).epsilon(1e-12));
    CHECK(triangleSolidAngle(o, Vec3(-1, -1, 1), Vec3(1, 1, 1), Vec3(-1, 1, 1)) == Approx(M_PI / 3).epsilon(1e-12));
    // Front face: the normal (p1−p0)×(p2−p0) points towards x.
    CHECK(triangleSolidAngleSigned(o, Vec3(-1, -1, 1), Vec3(1, 1, 1), Vec3(1, -1, 1)) == Approx(M_PI / 3).epsilon(1e-12));
    CHECK(triangleSolidAngleSigned(o, Vec3(-1, -1, 1), Vec3(1, -1, 1), Vec3(1, 1, 1)) == Approx(-M_PI / 3).epsilon(1e-12));
    // Far away: A·cosθ/r².
    const double r = 1000, area = 0.5;
    CHECK(triangleSolidAngle(Vec3(0, 0, -float(r)), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)) ==
          Approx(area / (r * r)).epsilon(1e-5));
    // In the plane: nothing; just over the interior: almost a hemisphere.
    CHECK(triangleSolidAngle(Vec3(5, 5, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)) == 0.0);
    CHECK(triangleSolidAngle(Vec3(0.25f, 0.25f, 1e-4f), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)) ==
          Approx(2 * M_PI).epsilon(2e-3));
    // Agreement with Girard's theorem wherever that is accurate.
    for (const TriangleCase& c : kTriangles) {
        INFO(c.name);
        CHECK(triangleSolidAngle(c.x, c.p0, c.p1, c.p2) ==
              Approx(girard(d3(c.x), d3(c.p0), d3(c.p1), d3(c.p2))).epsilon(1e-6));
    }
}

TEST_CASE("spherical triangle samples are uniform in solid angle (chi-square)", "[sampling][solidangle][chi2]") {
    const double alpha = 0.01 / double(std::size(kTriangles));
    uint64_t seed = 71;
    for (const TriangleCase& c : kTriangles) {
        const D3 o = d3(c.x), p0 = d3(c.p0), p1 = d3(c.p1), p2 = d3(c.p2);
        const double omega = girard(o, p0, p1, p2);
        const SphereHistogramOptions opt = polygonHistogram(o, (p0 + p1 + p2) * (1.0 / 3.0), {p0, p1, p2}, seed++);
        long badOmega = 0;
        auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
            Vec3 w;
            double sampledOmega;
            if (!sampleSphericalTriangle(c.x, c.p0, c.p1, c.p2, u, &w, &sampledOmega)) return std::nullopt;
            if (std::abs(sampledOmega - omega) > 1e-6 * omega + 1e-9) ++badOmega;
            return w;
        };
        auto pdfFn = [&](Vec3 w) { return rayTriangle(o, d3(w), p0, p1, p2) ? 1.0 / omega : 0.0; };
        HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, int(opt.cosThetaEdges.size()) - 1, 24, 400000, opt);
        INFO(c.name << ": Ω = " << omega << "\n" << r.chi2.table);
        CHECK(r.chi2.pValue > alpha);
        CHECK(r.outside == 0);
        CHECK(r.invalid == 0);
        CHECK(badOmega == 0);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(2e-3));
    }
}

namespace {

// A scene with one emissive triangle (a one-sided ceiling panel's half, facing down).
Scene panelScene(bool doubleSided) {
    SceneDescription desc;
    desc.camera.position = Vec3(0, 0, 10);
    Material m;
    m.emission = Spectrum(1.0f);
    m.doubleSided = doubleSided;
    desc.materials.push_back(m);
    Mesh mesh;
    mesh.positions = {Vec3(-0.5f, 2, -0.75f), Vec3(0.5f, 2, 0.75f), Vec3(-0.5f, 2, 0.75f)};  // normal −y
    mesh.indices = {0, 1, 2};
    mesh.material = 0;
    desc.meshes.push_back(mesh);
    return Scene(desc);
}

struct SegmentCase {
    const char* name;
    Vec3 o, d;
    float tEnd;
};

const SegmentCase kSegments[] = {
    {"grazing, 6 cm below the panel", Vec3(-3, 1.94f, 0.1f), Vec3(1, 0, 0), 6},
    {"through the room, far below", Vec3(-3, 0.5f, -1), normalize(Vec3(1, 0.05f, 0.3f)), 7},
    {"up into the panel (clipped at its plane)", Vec3(0, 0, 0), normalize(Vec3(0.05f, 1, 0.02f)), 10},
    {"unbounded", Vec3(-1, 1.5f, 0), Vec3(0, 0, 1), kInfinity},
};

}  // namespace

TEST_CASE("solid-angle distances follow their tabulated density (chi-square, integral 1)",
          "[sampling][solidangle][chi2]") {
    Scene scene = panelScene(false);
    const Light& light = scene.lights()[0];
    REQUIRE(light.kind == LightKind::Triangle);
    const double alpha = 0.01 / double(std::size(kSegments));
    for (const SegmentCase& c : kSegments) {
        INFO(c.name);
        MediumSegment seg{c.o, c.d, c.tEnd, nullptr};
        SolidAngleDistance s;
        REQUIRE(solidAngleDistanceOn(scene, light, seg, &s));
        const double hi = std::isinf(s.b) ? 200.0 : s.b;  // the unbounded tail beyond 200 goes to "outside"
        double tail = 0;
        if (std::isinf(s.b)) tail = integrate1D([&](double t) { return double(solidAngleDistancePdf(s, float(t))); }, hi, 1e7, 1e-12, 1e-8);
        HistogramOptions opt;
        opt.outsideProbability = tail;
        opt.seed = 91;
        HistogramResult r = intervalHistogramTest(
            [&](Sample2 u) {
                float t = sampleSolidAngleDistance(s, u.u);
                return t <= hi ? std::optional<double>(t) : std::nullopt;
            },
            [&](double t) { return double(solidAngleDistancePdf(s, float(t))); }, s.a, hi, 48, 400000, opt);
        INFO(r.chi2.table);
        CHECK(r.chi2.pValue > alpha);
        CHECK(r.invalid == 0);
        CHECK(r.pdfIntegral + tail == Approx(1.0).epsilon(2e-3));
    }
}

TEST_CASE("solid-angle distances follow Ω(x(t)) where Ω dominates", "[sampling][solidangle]") {
    // Away from the defensive floor, p(t) / Ω(x(t)) is nearly constant: within the tabulation's
    // piecewise-constant error (kBins bins), over the middle of a grazing segment.
    Scene scene = panelScene(false);
    const Light& light = scene.lights()[0];
    const Mesh& mesh = scene.mesh(0);
    MediumSegment seg{Vec3(-3, 1.94f, 0.1f), Vec3(1, 0, 0), 6, nullptr};
    SolidAngleDistance s;
    REQUIRE(solidAngleDistanceOn(scene, light, seg, &s));
    double lo = 1e30, hi = 0;
    for (float t = 2.6f; t <= 3.4f; t += 0.05f) {
        const Vec3 x = seg.o + seg.d * t;
        const double omega = triangleSolidAngle(x, mesh.positions[0], mesh.positions[1], mesh.positions[2]);
        const double ratio = solidAngleDistancePdf(s, t) / omega;
        lo = std::min(lo, ratio), hi = std::max(hi, ratio);
    }
    CHECK(hi / lo < 1.6);
    // The density integrates to 1 and is exactly 0 outside the segment.
    CHECK(solidAngleDistancePdf(s, -0.1f) == 0.0f);
    CHECK(solidAngleDistancePdf(s, 6.1f) == 0.0f);
}

TEST_CASE("solid-angle distances: degenerate and one-sided cases", "[sampling][solidangle]") {
    Scene scene = panelScene(false);
    const Light& light = scene.lights()[0];
    SolidAngleDistance s;
    // Wholly behind a one-sided emitter: nothing to sample.
    CHECK_FALSE(solidAngleDistanceOn(scene, light, MediumSegment{Vec3(-3, 2.5f, 0), Vec3(1, 0, 0), 6, nullptr}, &s));
    // In its plane: nothing either.
    CHECK_FALSE(solidAngleDistanceOn(scene, light, MediumSegment{Vec3(-3, 2, 0), Vec3(1, 0, 0), 6, nullptr}, &s));
    // Starting on the emitter and leaving it: a valid table, finite densities.
    REQUIRE(solidAngleDistanceOn(scene, light, MediumSegment{Vec3(0, 2, 0.3f), Vec3(0, -1, 0), 3, nullptr}, &s));
    for (float u : {0.0f, 0.25f, 0.5f, 0.999f}) {
        float t = sampleSolidAngleDistance(s, u);
        CHECK(t >= 0.0f);
        CHECK(t <= 3.0f);
        CHECK(std::isfinite(solidAngleDistancePdf(s, t)));
        CHECK(solidAngleDistancePdf(s, t) > 0.0f);
    }
    // Not a triangle: refused.
    Light point;
    CHECK_FALSE(solidAngleDistanceOn(scene, point, MediumSegment{Vec3(0, 0, 0), Vec3(1, 0, 0), 1, nullptr}, &s));
}

namespace {

struct RectangleCase {
    const char* name;
    Vec3 o, s, ex, ey;
};

const RectangleCase kRectangles[] = {
    {"ordinary", Vec3(0.2f, -0.3f, 0), Vec3(-1, -0.5f, 2), Vec3(1.6f, 0, 0.3f), Vec3(0, 1.1f, 0)},
    {"grazing (3 cm above the plane, beside it)", Vec3(1.4f, 0.2f, 0.03f), Vec3(-1, -0.75f, 0), Vec3(2, 0, 0), Vec3(0, 1.5f, 0)},
    {"close over the middle (Ω ≈ 5.2)", Vec3(0.1f, 0.2f, 0.15f), Vec3(-1, -0.75f, 0), Vec3(2, 0, 0), Vec3(0, 1.5f, 0)},
    {"far", Vec3(0, 0, 0), Vec3(-0.3f, -0.2f, 12), Vec3(0.6f, 0, 0), Vec3(0, 0.4f, 0)},
};

}  // namespace

TEST_CASE("spherical rectangle samples are uniform in solid angle (chi-square)", "[sampling][solidangle][chi2]") {
    const double alpha = 0.01 / double(std::size(kRectangles));
    uint64_t seed = 171;
    for (const RectangleCase& c : kRectangles) {
        const D3 o = d3(c.o), s = d3(c.s), ex = d3(c.ex), ey = d3(c.ey);
        const D3 q[4] = {s, s + ex, s + ex + ey, s + ey};
        const double omega = girard(o, q[0], q[1], q[2]) + girard(o, q[0], q[2], q[3]);
        SphericalRectangle rect;
        REQUIRE(makeSphericalRectangle(c.o, c.s, c.ex, c.ey, &rect));
        INFO(c.name << ": Ω = " << omega);
        CHECK(rect.solidAngle == Approx(omega).epsilon(1e-5));
        const SphereHistogramOptions opt = polygonHistogram(o, s + ex * 0.5 + ey * 0.5, {q[0], q[1], q[2], q[3]}, seed++);
        long offPlane = 0;
        const D3 n = dnorm(dcross(ex, ey));
        auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
            const Vec3 p = sampleSphericalRectangle(rect, u);
            if (std::abs(ddot(d3(p) - s, n)) > 1e-5) ++offPlane;
            return Vec3(normalize(p - c.o));
        };
        auto pdfFn = [&](Vec3 w) {
            const D3 wd = d3(w);
            return rayTriangle(o, wd, q[0], q[1], q[2]) || rayTriangle(o, wd, q[0], q[2], q[3]) ? 1.0 / omega : 0.0;
        };
        HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, int(opt.cosThetaEdges.size()) - 1, 24, 400000, opt);
        INFO(r.chi2.table);
        CHECK(r.chi2.pValue > alpha);
        CHECK(r.outside == 0);
        CHECK(r.invalid == 0);
        CHECK(offPlane == 0);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(2e-3));
    }
}

namespace {

// An emissive quad (corners c0..c3 in order, triangles (0,1,2), (0,2,3)) facing `n`.
Scene quadScene(const Vec3 (&c)[4], bool textured = false) {
    SceneDescription desc;
    desc.camera.position = Vec3(0, 0, 10);
    Material m;
    m.emission = Spectrum(2.0f);
    desc.materials.push_back(m);
    Mesh mesh;
    mesh.positions = {c[0], c[1], c[2], c[3]};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = 0;
    desc.meshes.push_back(mesh);
    (void)textured;
    return Scene(desc);
}

}  // namespace

TEST_CASE("a quad that is a rectangle is sampled as one by solid angle", "[sampling][solidangle][light][chi2]") {
    // A 2 m × 1.5 m rectangle in z = 2, facing −z (towards the origin side).
    const Vec3 c[4] = {Vec3(-1, -0.75f, 2), Vec3(-1, 0.75f, 2), Vec3(1, 0.75f, 2), Vec3(1, -0.75f, 2)};
    Scene scene = quadScene(c);
    REQUIRE(scene.lights().size() == 2);
    CHECK(scene.lights()[0].partner == 1);
    CHECK(scene.lights()[1].partner == 0);
    const D3 q[4] = {d3(c[0]), d3(c[1]), d3(c[2]), d3(c[3])};
    const Distribution1D& dist = scene.lightDistribution();
    const double alpha = 0.01 / 2;
    int k = 0;
    for (Vec3 ref : {Vec3(0.3f, 0.2f, 1.9f), Vec3(1.3f, -0.2f, 1.97f)}) {  // 10 cm under it; grazing beside it
        const D3 o = d3(ref);
        const double omega = girard(o, q[0], q[1], q[2]) + girard(o, q[0], q[2], q[3]);
        REQUIRE(omega > kMinSphericalSolidAngle);
        REQUIRE(omega < kMaxSphericalSolidAngle);
        long inconsistent = 0, wrongHalf = 0;
        Rng pick(181 + k, 0);
        auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
            float pmf;
            const int li = dist.sample(pick.next1D(), &pmf);
            LightSample s;
            if (!sampleLight(scene, scene.lights()[li], ref, u, &s)) return std::nullopt;
            // P(half) × pdf is the rectangle's density, whichever half was picked.
            if (std::abs(double(pmf) * s.pdf * omega - 1.0) > 1e-4) ++inconsistent;
            if (std::abs(lightPdf(scene, scene.lights()[li], ref, s.p, Vec3(0, 0, -1)) - s.pdf) > 1e-4 * s.pdf) ++inconsistent;
            // The half the point lies on is the one reported (up to rounding on the diagonal).
            const D3 a = q[0], b = s.light == 0 ? q[1] : q[2], cc = s.light == 0 ? q[2] : q[3], p = d3(s.p);
            const D3 nn = dcross(b - a, cc - a);
            const double inv = 1.0 / ddot(nn, nn);
            const double b0 = ddot(dcross(b - p, cc - p), nn) * inv, b1 = ddot(dcross(cc - p, a - p), nn) * inv;
            if (b0 < -1e-5 || b1 < -1e-5 || 1 - b0 - b1 < -1e-5) ++wrongHalf;
            return s.wi;
        };
        auto pdfFn = [&](Vec3 w) {
            const D3 wd = d3(w);
            return rayTriangle(o, wd, q[0], q[1], q[2]) || rayTriangle(o, wd, q[0], q[2], q[3]) ? 1.0 / omega : 0.0;
        };
        const SphereHistogramOptions opt = polygonHistogram(o, (q[0] + q[2]) * 0.5, {q[0], q[1], q[2], q[3]}, 191 + k++);
        HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, int(opt.cosThetaEdges.size()) - 1, 24, 400000, opt);
        INFO(r.chi2.table);
        CHECK(r.chi2.pValue > alpha);
        CHECK(r.outside == 0);
        CHECK(inconsistent == 0);
        CHECK(wrongHalf == 0);
    }
}

TEST_CASE("only rectangles are paired: a parallelogram and a kite stay two triangles", "[light]") {
    const Vec3 parallelogram[4] = {Vec3(0, 0, 2), Vec3(0.5f, 1, 2), Vec3(2.5f, 1, 2), Vec3(2, 0, 2)};
    const Vec3 kite[4] = {Vec3(0, 0, 2), Vec3(-0.5f, 1, 2), Vec3(0, 3, 2), Vec3(0.5f, 1, 2)};
    for (const auto* c : {&parallelogram, &kite}) {
        Scene scene = quadScene(*c);
        REQUIRE(scene.lights().size() == 2);
        CHECK(scene.lights()[0].partner == -1);
        CHECK(scene.lights()[1].partner == -1);
    }
}

TEST_CASE("distances by solid angle apply near the emitter only, the same for both halves of a rectangle",
          "[sampling][solidangle]") {
    const Vec3 c[4] = {Vec3(-1, -0.75f, 2), Vec3(-1, 0.75f, 2), Vec3(1, 0.75f, 2), Vec3(1, -0.75f, 2)};
    Scene scene = quadScene(c);
    const float reach = kSolidAngleReach * std::sqrt(3.0f);  // √A, A = 3 m²
    for (float miss : {0.5f * reach, 0.99f * reach, 1.01f * reach, 3.0f * reach}) {
        // A segment along x passing `miss` below the rectangle's centre (0, 0, 2).
        const MediumSegment seg{Vec3(-10, 0, 2 - miss), Vec3(1, 0, 0), 20, nullptr};
        const bool near = miss < reach;
        CHECK(solidAngleDistanceApplies(scene, scene.lights()[0], seg) == near);
        CHECK(solidAngleDistanceApplies(scene, scene.lights()[1], seg) == near);
    }
    // Either half builds the same table, bit for bit.
    const MediumSegment seg{Vec3(-3, 0.2f, 1.9f), Vec3(1, 0, 0), 6, nullptr};
    SolidAngleDistance s0, s1;
    REQUIRE(solidAngleDistanceOn(scene, scene.lights()[0], seg, &s0));
    REQUIRE(solidAngleDistanceOn(scene, scene.lights()[1], seg, &s1));
    for (int i = 0; i <= SolidAngleDistance::kBins; ++i) CHECK(s0.cdf[i] == s1.cdf[i]);
}
