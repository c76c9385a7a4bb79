// Chi-square tests of sampleLight against lightPdf (solid angle at the reference point) for
// sphere and triangle lights, that lightPdf integrates to the probability that sampling
// succeeds, and the radiance / intensity each kind of light returns. Significance 0.01 per
// test case, Bonferroni-corrected over the parameter sets of a case; seeds are fixed.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "brume/scene/light.h"
#include "brume/scene/light_sampling.h"
#include "brume/scene/scene.h"
#include "brume/scene/scene_description.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr long kSamples = 1000000;
// Analytically the integrals are exactly 1 (or 0); quadrature is accurate to ~1e-6, the
// float pdfs and float directions to ~1e-5 for the smallest cones used here.
constexpr double kIntegralTol = 1e-3;

void report(const std::string& name, const HistogramResult& r) {
    std::printf("[chi2] %-44s chi2 = %9.2f  dof = %4d  p = %.4f  integral = %.7f  (quadrature warnings %d)\n",
                name.c_str(), r.chi2.chi2, r.chi2.dof, r.chi2.pValue, r.pdfIntegral, r.integrationWarnings);
}

void checkHistogram(const std::string& name, const HistogramResult& r, double alpha) {
    report(name, r);
    INFO(name << "\n" << r.chi2.table);
    CHECK(r.invalid == 0);
    CHECK(r.chi2.pValue > alpha);
}

// Double-precision vector helpers, independent of the renderer's float ones.
struct D3 {
    double x, y, z;
};
D3 d3(Vec3 v) { return {v.x, v.y, v.z}; }
Vec3 f3(D3 v) { return Vec3(float(v.x), float(v.y), float(v.z)); }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double ddot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 dcross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dlen(D3 a) { return std::sqrt(ddot(a, a)); }
D3 dnorm(D3 a) { return a * (1.0 / dlen(a)); }

// Nearest positive t where o + t·w meets the sphere (from outside: the near side).
std::optional<double> raySphere(D3 o, D3 w, D3 c, double r) {
    D3 oc = o - c;
    double b = ddot(oc, w);
    double disc = b * b - (ddot(oc, oc) - r * r);
    if (disc < 0) return std::nullopt;
    double h = std::sqrt(disc);
    double t0 = -b - h, t1 = -b + h;
    if (t0 > 0) return t0;
    if (t1 > 0) return t1;
    return std::nullopt;
}

// Möller–Trumbore in double precision; both faces.
std::optional<double> rayTriangle(D3 o, D3 w, D3 p0, D3 p1, D3 p2) {
    D3 e1 = p1 - p0, e2 = p2 - p0;
    D3 pv = dcross(w, e2);
    double det = ddot(e1, pv);
    if (det == 0) return std::nullopt;
    double inv = 1.0 / det;
    D3 tv = o - p0;
    double b1 = ddot(tv, pv) * inv;
    if (b1 < 0 || b1 > 1) return std::nullopt;
    D3 qv = dcross(tv, e1);
    double b2 = ddot(w, qv) * inv;
    if (b2 < 0 || b1 + b2 > 1) return std::nullopt;
    double t = ddot(e2, qv) * inv;
    if (!(t > 0)) return std::nullopt;
    return t;
}

// Histogram cosθ edges for a light seen within the cone cosθ ≥ cosMin around the axis: one
// empty bin below, then `bins` uniform bins starting a little below cosMin (so float
// rounding at the rim cannot push a sample into the empty bin).
std::vector<double> coneEdges(double cosMin, int bins, double marginFraction) {
    double lo = cosMin - marginFraction * (1.0 - cosMin);
    std::vector<double> e = uniformEdges(bins, lo, 1.0);
    if (lo > -1.0) e.insert(e.begin(), -1.0);
    else e.front() = -1.0;
    return e;
}

// Counts the samples of one light whose LightSample is not self-consistent.
struct SampleChecks {
    long count = 0;
    long badPdf = 0;       // sample.pdf ≠ lightPdf at the sampled point
    long badGeometry = 0;  // p ≠ ref + wi·dist, wi not unit, or p not on the light
    long badLe = 0;
    long badDelta = 0;
    void print(const char* name) const {
        std::printf("       %s: %ld samples, inconsistent pdf %ld, geometry %ld, Le %ld, isDelta %ld\n", name, count,
                    badPdf, badGeometry, badLe, badDelta);
    }
    void require() const {
        CHECK(badPdf == 0);
        CHECK(badGeometry == 0);
        CHECK(badLe == 0);
        CHECK(badDelta == 0);
    }
};

bool close(double a, double b, double rel) { return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)); }
bool close(Vec3 a, Vec3 b, double rel) { return close(a.x, b.x, rel) && close(a.y, b.y, rel) && close(a.z, b.z, rel); }

SceneDescription baseDescription() {
    SceneDescription desc;
    desc.camera.position = Vec3(0, 0, 10);
    return desc;
}

// ----------------------------------------------------------------------------------------
// A planar quadrilateral light made of two triangles of different areas.

struct QuadSetup {
    Vec3 origin;
    Vec3 u, v, n;  // orthonormal, cross(u, v) = n: counter-clockwise (x, y) is the front face
    std::vector<Vec3> corners;
    Spectrum emission{1.5f, 2.0f, 0.5f};
};

QuadSetup makeQuad() {
    QuadSetup q;
    q.origin = Vec3(-0.4f, 0.8f, 1.5f);
    D3 n = dnorm({0.2, -0.4, -1.0});
    D3 u = dnorm(dcross(n, {0.0, 1.0, 0.0}));
    D3 v = dcross(n, u);
    q.u = f3(u);
    q.v = f3(v);
    q.n = f3(n);
    // Plane coordinates: triangle (0, 1, 2) has area 0.75, triangle (0, 2, 3) area 0.37.
    const double xy[4][2] = {{0, 0}, {1.5, 0}, {1.2, 1.0}, {0.1, 0.7}};
    for (auto& c : xy) q.corners.push_back(f3(d3(q.origin) + u * c[0] + v * c[1]));
    return q;
}

SceneDescription quadDescription(const QuadSetup& q, bool doubleSided) {
    SceneDescription desc = baseDescription();
    Light point;
    point.kind = LightKind::Point;
    point.position = Vec3(3, 3, 3);
    point.intensity = Spectrum(1.0f);
    desc.lights.push_back(point);  // a punctual light first: the triangles come after it
    Material m;
    m.emission = q.emission;
    m.doubleSided = doubleSided;
    desc.materials.push_back(m);
    Mesh mesh;
    mesh.positions = q.corners;
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = 0;
    desc.meshes.push_back(mesh);
    return desc;
}

// Direction histogram of one triangle light seen from ref; returns the run and fills checks.
// Solid angle of the triangle abc seen from o by Girard's theorem (the angle excess),
// independent of the renderer's Van Oosterom–Strackee formula.
double girardSolidAngle(D3 o, D3 a, D3 b, D3 c) {
    D3 A = dnorm(a - o), B = dnorm(b - o), C = dnorm(c - o);
    auto angle = [](D3 p, D3 q, D3 r) {
        D3 n1 = dnorm(dcross(p, q)), n2 = dnorm(dcross(p, r));
        return std::acos(std::max(-1.0, std::min(1.0, ddot(n1, n2))));
    };
    return angle(A, B, C) + angle(B, C, A) + angle(C, A, B) - M_PI;
}

// The scene's sampleLight against an independent density: 1/Ω where the light samples by
// solid angle (Ω within the spherical limits), else dist²/(A·|cosθ|); and against lightPdf.
HistogramResult triangleDirectionTest(const Scene& scene, int lightIndex, Vec3 ref, uint64_t seed,
                                      SampleChecks* checks, bool expectSuccess) {
    const Light& light = scene.lights()[lightIndex];
    const Mesh& mesh = scene.mesh(light.mesh);
    D3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = d3(mesh.positions[mesh.indices[3 * light.triangle + k]]);
    D3 nd = dnorm(dcross(p[1] - p[0], p[2] - p[0]));
    Vec3 n = f3(nd);
    D3 o = d3(ref);
    D3 axis = dnorm((p[0] + p[1] + p[2]) * (1.0 / 3.0) - o);
    double cosMin = 1;
    for (const D3& v : p) cosMin = std::min(cosMin, ddot(axis, dnorm(v - o)));
    const Spectrum emission = scene.material(light.mesh).emission;

    SphereHistogramOptions opt;
    opt.seed = seed;
    opt.axis = f3(axis);
    opt.cosThetaEdges = coneEdges(cosMin, 20, 0.02);
    opt.outsideProbability = expectSuccess ? 0.0 : 1.0;
    auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
        LightSample s;
        if (!sampleLight(scene, light, ref, u, &s)) {
            if (s.pdf != 0) ++checks->badPdf;
            return std::nullopt;
        }
        ++checks->count;
        if (!close(double(s.pdf), double(lightPdf(scene, light, ref, s.p, n)), 1e-4)) ++checks->badPdf;
        D3 toP = d3(s.p) - o;
        // p on the triangle's plane, reached along wi after dist.
        if (std::abs(ddot(d3(s.p) - p[0], nd)) > 1e-5 || dlen(toP - d3(s.wi) * s.dist) > 1e-5 * (1 + s.dist) ||
            std::abs(length(s.wi) - 1) > 1e-5)
            ++checks->badGeometry;
        if (!close(s.Le, emission, 1e-6)) ++checks->badLe;
        if (s.isDelta) ++checks->badDelta;
        return s.wi;
    };
    const double omega = girardSolidAngle(o, p[0], p[1], p[2]);
    const bool bySolidAngle = scene.emitterSampling() == EmitterSampling::SolidAngle && omega >= kMinSphericalSolidAngle &&
                              omega <= kMaxSphericalSolidAngle;
    const double area = 0.5 * dlen(dcross(p[1] - p[0], p[2] - p[0]));
    const bool doubleSided = scene.material(light.mesh).doubleSided;
    auto pdfFn = [&](Vec3 w) -> double {
        std::optional<double> t = rayTriangle(o, d3(w), p[0], p[1], p[2]);
        if (!t) return 0.0;
        const double cosLight = -ddot(nd, d3(w));
        if (!doubleSided && cosLight <= 0) return 0.0;
        return bySolidAngle ? 1.0 / omega : *t * *t / (area * std::abs(cosLight));
    };
    return sphereHistogramTest(sampleFn, pdfFn, int(opt.cosThetaEdges.size()) - 1, 24, kSamples, opt);
}

}  // namespace

// ----------------------------------------------------------------------------------------
// Sphere lights

TEST_CASE("sphere light sampling matches lightPdf", "[chi2][light]") {
    const Vec3 centre(0.2f, -0.3f, 1.1f);
    const float radius = 0.5f;
    SceneDescription desc = baseDescription();
    Light sphere;
    sphere.kind = LightKind::Sphere;
    sphere.position = centre;
    sphere.radius = radius;
    sphere.intensity = Spectrum(2.0f, 3.0f, 4.0f);
    desc.lights.push_back(sphere);
    Scene scene(desc);
    REQUIRE(scene.lights().size() == 1);
    const Light& light = scene.lights()[0];
    const Spectrum expectedLe = sphere.intensity / (kPi * radius * radius);

    const D3 towards = dnorm({0.48, 0.6, 0.64});  // from the reference point to the centre
    struct Case {
        double dist;
        bool worldAxis;  // histogram about world +z instead of the cone axis
    };
    const Case cases[] = {{0.55, false}, {1.0, false}, {3.0, false}, {20.0, false}, {1.0, true}};
    const double alpha = kAlpha / 5;
    int k = 0;
    for (const Case& c : cases) {
        const Vec3 ref = f3(d3(centre) - towards * c.dist);
        const D3 o = d3(ref), cd = d3(centre);
        const D3 axis = dnorm(cd - o);
        const double dc = dlen(cd - o);
        const double cosMax = std::sqrt(std::max(0.0, 1.0 - double(radius) * radius / (dc * dc)));
        SampleChecks checks;
        SphereHistogramOptions opt;
        opt.seed = 101 + k;
        int thetaBins = 20;
        if (c.worldAxis) {
            opt.axis = Vec3(0, 0, 1);
        } else {
            opt.axis = f3(axis);
            opt.cosThetaEdges = coneEdges(cosMax, 20, 0.01);
            thetaBins = int(opt.cosThetaEdges.size()) - 1;
        }
        auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
            LightSample s;
            if (!sampleLight(scene, light, ref, u, &s)) return std::nullopt;
            ++checks.count;
            Vec3 n = normalize(s.p - centre);
            if (!close(double(s.pdf), double(lightPdf(scene, light, ref, s.p, n)), 1e-5)) ++checks.badPdf;
            D3 toP = d3(s.p) - o;
            if (std::abs(dlen(d3(s.p) - cd) - radius) > 1e-4 * radius ||
                dlen(toP - d3(s.wi) * s.dist) > 1e-5 * (1 + s.dist) || std::abs(length(s.wi) - 1) > 1e-5)
                ++checks.badGeometry;
            if (!close(s.Le, expectedLe, 1e-6)) ++checks.badLe;
            if (s.isDelta) ++checks.badDelta;
            return s.wi;
        };
        // The density is defined on the directions that hit the sphere.
        auto pdfFn = [&](Vec3 w) -> double {
            std::optional<double> t = raySphere(o, d3(w), cd, radius);
            if (!t) return 0.0;
            D3 p = o + d3(w) * *t;
            return lightPdf(scene, light, ref, f3(p), f3(dnorm(p - cd)));
        };
        HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, thetaBins, 24, kSamples, opt);
        std::string name = "sphere light, distance " + std::to_string(c.dist) + (c.worldAxis ? " (world axis)" : "");
        checkHistogram(name, r, alpha);
        checks.print(name.c_str());
        checks.require();
        CHECK(r.outside == 0);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
        ++k;
    }
}

TEST_CASE("a sphere light is not sampled from inside it", "[chi2][light]") {
    // Only the outside of a sphere light emits, so from inside nothing can be sampled, and the
    // density of every direction (each hits the sphere from inside) is 0: ∫ pdf = 0 = the
    // probability that sampling succeeds.
    const Vec3 centre(0.2f, -0.3f, 1.1f);
    const float radius = 0.5f;
    SceneDescription desc = baseDescription();
    Light sphere;
    sphere.kind = LightKind::Sphere;
    sphere.position = centre;
    sphere.radius = radius;
    sphere.intensity = Spectrum(1.0f);
    desc.lights.push_back(sphere);
    Scene scene(desc);
    const Light& light = scene.lights()[0];
    const Vec3 ref = centre + Vec3(0.1f, 0.15f, -0.2f);
    SphereHistogramOptions opt;
    opt.seed = 121;
    opt.outsideProbability = 1.0;
    long nonzeroPdf = 0;
    HistogramResult r = sphereHistogramTest(
        [&](Sample2 u) -> std::optional<Vec3> {
            LightSample s;
            if (!sampleLight(scene, light, ref, u, &s)) {
                if (s.pdf != 0) ++nonzeroPdf;
                return std::nullopt;
            }
            return s.wi;
        },
        [&](Vec3 w) -> double {
            std::optional<double> t = raySphere(d3(ref), d3(w), d3(centre), radius);
            if (!t) return 0.0;
            D3 p = d3(ref) + d3(w) * *t;
            return lightPdf(scene, light, ref, f3(p), f3(dnorm(p - d3(centre))));
        },
        10, 12, 100000, opt);
    report("sphere light, reference inside", r);
    INFO(r.chi2.table);
    CHECK(r.outside == 100000);
    CHECK(nonzeroPdf == 0);
    CHECK(r.pdfIntegral == 0.0);
}

// ----------------------------------------------------------------------------------------
// Triangle lights

TEST_CASE("emissive triangles become lights after the punctual ones", "[light]") {
    QuadSetup q = makeQuad();
    Scene scene(quadDescription(q, false));
    REQUIRE(scene.lights().size() == 3);
    CHECK(scene.lights()[0].kind == LightKind::Point);
    for (int t = 0; t < 2; ++t) {
        const Light& l = scene.lights()[1 + t];
        CHECK(l.kind == LightKind::Triangle);
        CHECK(l.mesh == 0);
        CHECK(l.triangle == t);
        CHECK(scene.triangleLight(0, t) == 1 + t);
    }
    // Power (grey average) of a one-sided triangle: area·π·L; of a point light 4π·I.
    const double areas[2] = {0.75, 0.37};
    for (int t = 0; t < 2; ++t)
        CHECK(lightPower(scene, scene.lights()[1 + t]) == Approx(areas[t] * M_PI * average(q.emission)).epsilon(1e-5));
    CHECK(lightPower(scene, scene.lights()[0]) == Approx(4 * M_PI).epsilon(1e-6));
    const Distribution1D& dist = scene.lightDistribution();
    REQUIRE(dist.size() == 3);
    CHECK(dist.pmf(1) / dist.pmf(2) == Approx(0.75 / 0.37).epsilon(1e-5));
}

TEST_CASE("triangle light sampling matches its density, by area and by solid angle", "[chi2][light][sanitizer-skip]") {
    QuadSetup q = makeQuad();
    Scene single(quadDescription(q, false));
    Scene twoSided(quadDescription(q, true));
    const D3 o = d3(q.origin), u = d3(q.u), v = d3(q.v), n = d3(q.n);
    const Vec3 front = f3(o + u * 0.7 + v * 0.4 + n * 0.9);   // in front of the quad, fairly close
    const Vec3 front2 = f3(o + u * 2.5 + v * -1.0 + n * 0.6);  // in front, off to the side (oblique)
    const Vec3 behind = f3(o + u * 0.5 + v * 0.3 - n * 1.2);
    const Vec3 grazing = f3(o + u * 1.0 + v * -0.3 + n * 0.05);  // beside the quad, 5 cm above its plane
    const Vec3 close = f3(o + u * 0.6 + v * 0.2 + n * 0.001);   // 1 mm over triangle 0: Ω > 6.22, by area
    const Vec3 near = f3(o + u * 0.3 + v * 0.2 + n * 0.15);     // 15 cm over it: Ω ≈ 4.5
    const Vec3 far = f3(o + u * 0.5 + v * 0.3 + n * 80.0);      // Ω ≈ 1e-4: by area
    struct Case {
        Scene* scene;
        int light;
        Vec3 ref;
        const char* name;
    };
    const Case cases[] = {
        {&single, 1, front, "triangle 0, front"},
        {&single, 2, front, "triangle 1, front"},
        {&single, 1, front2, "triangle 0, front, oblique"},
        {&twoSided, 2, behind, "triangle 1, two-sided, from behind"},
        {&single, 1, grazing, "triangle 0, grazing"},
        {&single, 1, close, "triangle 0, 1 mm above"},
        {&single, 1, near, "triangle 0, 15 cm above"},
        {&single, 2, far, "triangle 1, 80 m away"},
    };
    const int nCases = int(sizeof(cases) / sizeof(cases[0]));
    const double alpha = kAlpha / (2 * nCases);
    int k = 0;
    for (EmitterSampling mode : {EmitterSampling::Area, EmitterSampling::SolidAngle}) {
        for (const Case& c : cases) {
            c.scene->setEmitterSampling(mode);
            const std::string name = std::string(c.name) + (mode == EmitterSampling::Area ? ", by area" : ", by solid angle");
            SampleChecks checks;
            HistogramResult r = triangleDirectionTest(*c.scene, c.light, c.ref, 131 + k++, &checks, true);
            checkHistogram(name, r, alpha);
            checks.print(name.c_str());
            checks.require();
            CHECK(r.outside == 0);
            CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
        }
    }
    // Which construction each case took: the limits are a function of the geometry.
    double omega = 0;
    CHECK(samplesBySolidAngle(single, single.lights()[1], front, &omega));
    CHECK(!samplesBySolidAngle(single, single.lights()[1], close, &omega));
    CHECK(omega > kMaxSphericalSolidAngle);
    CHECK(samplesBySolidAngle(single, single.lights()[1], near, &omega));
    CHECK(!samplesBySolidAngle(single, single.lights()[2], far, &omega));
    CHECK(omega < kMinSphericalSolidAngle);  // (0: decided by area over distance², before Ω)
    CHECK(!samplesBySolidAngle(single, single.lights()[1], behind, &omega));
    CHECK(omega == 0);
}

TEST_CASE("a one-sided triangle light is not sampled from behind", "[chi2][light]") {
    QuadSetup q = makeQuad();
    Scene scene(quadDescription(q, false));
    const Vec3 behind = f3(d3(q.origin) + d3(q.u) * 0.5 + d3(q.v) * 0.3 - d3(q.n) * 1.2);
    SampleChecks checks;
    HistogramResult r = triangleDirectionTest(scene, 1, behind, 141, &checks, false);
    report("triangle 0, one-sided, from behind", r);
    INFO(r.chi2.table);
    CHECK(r.outside == kSamples);
    CHECK(checks.badPdf == 0);  // failed samples leave pdf = 0
    CHECK(r.pdfIntegral == 0.0);
}

TEST_CASE("picking a quad's triangles by power and sampling them is uniform in area", "[chi2][light]") {
    // Both triangles share one emission, so choosing them in proportion to power and then
    // sampling each uniformly must give the quad's uniform-area density dist²/(A cosθ).
    QuadSetup q = makeQuad();
    Scene scene(quadDescription(q, false));
    scene.setEmitterSampling(EmitterSampling::Area);
    const Distribution1D& dist = scene.lightDistribution();
    const double sel1 = dist.pmf(1) / (dist.pmf(1) + dist.pmf(2));
    const Vec3 ref = f3(d3(q.origin) + d3(q.u) * 0.9 + d3(q.v) * 0.2 + d3(q.n) * 1.3);
    const D3 o = d3(ref), n = d3(q.n);
    D3 c[4];
    for (int i = 0; i < 4; ++i) c[i] = d3(q.corners[i]);
    const double area = 0.75 + 0.37;
    D3 axis = dnorm((c[0] + c[1] + c[2] + c[3]) * 0.25 - o);
    double cosMin = 1;
    for (const D3& p : c) cosMin = std::min(cosMin, ddot(axis, dnorm(p - o)));

    long inconsistent = 0;
    SphereHistogramOptions opt;
    opt.seed = 151;
    opt.axis = f3(axis);
    opt.cosThetaEdges = coneEdges(cosMin, 20, 0.02);
    Sampler pick(152, 0, 0);
    auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
        int li = pick.next1D() < sel1 ? 1 : 2;
        const Light& light = scene.lights()[li];
        LightSample s;
        if (!sampleLight(scene, light, ref, u, &s)) return std::nullopt;
        double sel = li == 1 ? sel1 : 1 - sel1;
        double cosLight = -ddot(n, d3(s.wi));
        double quadPdf = double(s.dist) * s.dist / (area * cosLight);
        if (!close(sel * s.pdf, quadPdf, 2e-4)) ++inconsistent;
        return s.wi;
    };
    auto pdfFn = [&](Vec3 w) -> double {
        D3 wd = d3(w);
        std::optional<double> t = rayTriangle(o, wd, c[0], c[1], c[2]);
        if (!t) t = rayTriangle(o, wd, c[0], c[2], c[3]);
        if (!t) return 0.0;
        double cosLight = -ddot(n, wd);
        return cosLight > 0 ? *t * *t / (area * cosLight) : 0.0;
    };
    HistogramResult r =
        sphereHistogramTest(sampleFn, pdfFn, int(opt.cosThetaEdges.size()) - 1, 24, kSamples, opt);
    checkHistogram("quad: triangles picked by power", r, kAlpha);
    CHECK(inconsistent == 0);
    CHECK(r.outside == 0);
    CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
}

TEST_CASE("picking a quad's triangles by power and sampling each by solid angle", "[chi2][light]") {
    // The density of a direction through triangle i is P(i)/Ω_i, Ω_i by Girard's theorem.
    QuadSetup q = makeQuad();
    Scene scene(quadDescription(q, false));
    const Distribution1D& dist = scene.lightDistribution();
    const double sel1 = dist.pmf(1) / (dist.pmf(1) + dist.pmf(2));
    const Vec3 ref = f3(d3(q.origin) + d3(q.u) * 0.9 + d3(q.v) * 0.2 + d3(q.n) * 0.3);
    const D3 o = d3(ref), n = d3(q.n);
    D3 c[4];
    for (int i = 0; i < 4; ++i) c[i] = d3(q.corners[i]);
    const double omega1 = girardSolidAngle(o, c[0], c[1], c[2]), omega2 = girardSolidAngle(o, c[0], c[2], c[3]);
    D3 axis = dnorm((c[0] + c[1] + c[2] + c[3]) * 0.25 - o);
    double cosMin = 1;
    for (const D3& p : c) cosMin = std::min(cosMin, ddot(axis, dnorm(p - o)));
    SphereHistogramOptions opt;
    opt.seed = 161;
    opt.axis = f3(axis);
    opt.cosThetaEdges = coneEdges(std::max(-0.99, cosMin), 20, 0.02);
    Sampler pick(162, 0, 0);
    long inconsistent = 0;
    auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
        int li = pick.next1D() < sel1 ? 1 : 2;
        LightSample s;
        if (!sampleLight(scene, scene.lights()[li], ref, u, &s)) return std::nullopt;
        if (!close(double(s.pdf), 1.0 / (li == 1 ? omega1 : omega2), 1e-4)) ++inconsistent;
        return s.wi;
    };
    auto pdfFn = [&](Vec3 w) -> double {
        D3 wd = d3(w);
        if (-ddot(n, wd) <= 0) return 0.0;
        if (rayTriangle(o, wd, c[0], c[1], c[2])) return sel1 / omega1;
        if (rayTriangle(o, wd, c[0], c[2], c[3])) return (1 - sel1) / omega2;
        return 0.0;
    };
    HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, int(opt.cosThetaEdges.size()) - 1, 24, kSamples, opt);
    checkHistogram("quad: triangles by power, then solid angle", r, kAlpha);
    CHECK(inconsistent == 0);
    CHECK(r.outside == 0);
    CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
}

// ----------------------------------------------------------------------------------------
// Punctual lights

namespace {

// Unit vector at angle theta from axis a (rotated towards a fixed perpendicular).
Vec3 atAngle(Vec3 a, double theta) {
    D3 ad = dnorm(d3(a));
    D3 perp = dnorm(dcross(ad, std::abs(ad.x) < 0.9 ? D3{1, 0, 0} : D3{0, 1, 0}));
    return f3(ad * std::cos(theta) + perp * std::sin(theta));
}

}  // namespace

TEST_CASE("point light: Le = I / dist^2, delta", "[light]") {
    SceneDescription desc = baseDescription();
    Light point;
    point.kind = LightKind::Point;
    point.position = Vec3(1.0f, 2.0f, -0.5f);
    point.intensity = Spectrum(3.0f, 5.0f, 7.0f);
    desc.lights.push_back(point);
    Scene scene(desc);
    const Light& light = scene.lights()[0];
    for (Vec3 ref : {Vec3(0, 0, 0), Vec3(-3, 1, 4), Vec3(1.0f, 2.0f, 0.5f)}) {
        LightSample s;
        REQUIRE(sampleLight(scene, light, ref, Sample2{0.3f, 0.7f}, &s));
        double d = dlen(d3(point.position) - d3(ref));
        CHECK(s.isDelta);
        CHECK(s.pdf == 1.0f);
        CHECK(s.dist == Approx(d).epsilon(1e-6));
        CHECK(close(s.Le, point.intensity / float(d * d), 1e-5));
        CHECK(close(s.wi, f3(dnorm(d3(point.position) - d3(ref))), 1e-5));
        CHECK(close(s.p, point.position, 1e-6));
        CHECK(lightPdf(scene, light, ref, s.p, Vec3(0, 0, 1)) == 0.0f);
    }
}

TEST_CASE("spot light: glTF cone attenuation", "[light]") {
    SceneDescription desc = baseDescription();
    Light spot;
    spot.kind = LightKind::Spot;
    spot.position = Vec3(1.0f, 2.0f, 3.0f);
    spot.direction = normalize(Vec3(0.3f, -1.0f, 0.2f));
    spot.intensity = Spectrum(10.0f, 20.0f, 30.0f);
    const double inner = 0.3, outer = 0.5;  // cone half-angles [rad]
    spot.cosInner = float(std::cos(inner));
    spot.cosOuter = float(std::cos(outer));
    desc.lights.push_back(spot);
    Scene scene(desc);
    const Light& light = scene.lights()[0];
    const double dist = 2.5;
    // glTF: smoothstep-free quadratic falloff between the cones, in cosθ.
    auto attenuation = [&](double theta) {
        double a = (std::cos(theta) - std::cos(outer)) / (std::cos(inner) - std::cos(outer));
        a = std::min(1.0, std::max(0.0, a));
        return a * a;
    };
    struct Case {
        double theta;
        const char* name;
        double tol;  // relative tolerance on Le
    };
    // Inside the inner cone and on its edge: full intensity; between the cones: the
    // quadratic falloff (just inside the outer edge it is ~4e-5, and cosθ's float error of
    // ~1e-7 against cosInner − cosOuter = 0.078 allows a relative error of ~1e-3 there).
    const Case lit[] = {{0.0, "centre", 1e-5},      {0.15, "inside inner cone", 1e-5},
                        {inner, "inner edge", 1e-4}, {0.4, "between the cones", 1e-4},
                        {0.45, "near the outer edge", 1e-4}, {outer - 1e-3, "just inside the outer edge", 5e-3}};
    for (const Case& c : lit) {
        Vec3 ref = f3(d3(spot.position) + d3(atAngle(spot.direction, c.theta)) * dist);
        LightSample s;
        INFO(c.name << ": theta = " << c.theta);
        REQUIRE(sampleLight(scene, light, ref, Sample2{0.5f, 0.5f}, &s));
        CHECK(s.isDelta);
        CHECK(s.pdf == 1.0f);
        CHECK(s.dist == Approx(dist).epsilon(1e-5));
        Spectrum expected = spot.intensity * float(attenuation(c.theta) / (dist * dist));
        INFO("Le = " << s.Le.x << " " << s.Le.y << " " << s.Le.z << ", expected " << expected.x << " " << expected.y
                     << " " << expected.z);
        CHECK(close(s.Le, expected, c.tol));
    }
    // On the outer edge the attenuation is 0 (up to float rounding of cosθ); outside the cone
    // and behind the light sampling fails with pdf 0.
    {
        Vec3 ref = f3(d3(spot.position) + d3(atAngle(spot.direction, outer)) * dist);
        LightSample s;
        bool ok = sampleLight(scene, light, ref, Sample2{0.5f, 0.5f}, &s);
        if (ok) CHECK(maxComponent(s.Le) <= maxComponent(spot.intensity) / float(dist * dist) * 1e-8f);
        else CHECK(s.pdf == 0.0f);
    }
    for (double theta : {outer + 1e-3, 0.8, 1.6, 3.0}) {
        Vec3 ref = f3(d3(spot.position) + d3(atAngle(spot.direction, theta)) * dist);
        LightSample s;
        INFO("outside, theta = " << theta);
        CHECK_FALSE(sampleLight(scene, light, ref, Sample2{0.5f, 0.5f}, &s));
        CHECK(s.pdf == 0.0f);
    }
}

TEST_CASE("directional light: Le = E, delta, at infinity", "[light]") {
    SceneDescription desc = baseDescription();
    Light sun;
    sun.kind = LightKind::Directional;
    sun.direction = normalize(Vec3(0.2f, -1.0f, 0.3f));
    sun.intensity = Spectrum(4.0f, 3.0f, 2.0f);
    desc.lights.push_back(sun);
    Scene scene(desc);
    const Light& light = scene.lights()[0];
    for (Vec3 ref : {Vec3(0, 0, 0), Vec3(100, -20, 5)}) {
        LightSample s;
        REQUIRE(sampleLight(scene, light, ref, Sample2{0.1f, 0.9f}, &s));
        CHECK(s.isDelta);
        CHECK(s.pdf == 1.0f);
        CHECK(std::isinf(s.dist));
        CHECK(close(s.wi, -sun.direction, 1e-6));
        CHECK(close(s.Le, sun.intensity, 1e-6));
    }
}

TEST_CASE("sphere light radiance is I / (pi r^2)", "[light]") {
    SceneDescription desc = baseDescription();
    Light sphere;
    sphere.kind = LightKind::Sphere;
    sphere.position = Vec3(0, 1, 0);
    sphere.radius = 0.25f;
    sphere.intensity = Spectrum(1.0f, 2.0f, 3.0f);
    desc.lights.push_back(sphere);
    Scene scene(desc);
    LightSample s;
    REQUIRE(sampleLight(scene, scene.lights()[0], Vec3(0.3f, -2, 0.1f), Sample2{0.2f, 0.6f}, &s));
    CHECK_FALSE(s.isDelta);
    const double area = M_PI * 0.25 * 0.25;
    CHECK(s.Le.x == Approx(1.0 / area).epsilon(1e-6));
    CHECK(s.Le.y == Approx(2.0 / area).epsilon(1e-6));
    CHECK(s.Le.z == Approx(3.0 / area).epsilon(1e-6));
}
