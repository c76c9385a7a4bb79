// Tests of sampleEmission / emissionPdf (the first vertex and direction of a light subpath):
// chi-square histograms of emitted directions and origins against the densities the
// samples carry, that every sample's densities agree with emissionPdf and with closed forms,
// the emitted radiance / intensity, and Monte Carlo estimates of each light's total power
// against closed forms and lightPower(). Significance 0.01 per test case, Bonferroni-
// corrected over the runs of a case; seeds are fixed.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brume/scene/light.h"
#include "brume/scene/light_emission.h"
#include "brume/scene/light_sampling.h"
#include "brume/scene/scene.h"
#include "brume/scene/scene_description.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr long kSamples = 200000;
// The densities integrate to 1 analytically; quadrature is good to ~1e-6, float densities
// to ~1e-5 at the edges of their support.
constexpr double kIntegralTol = 1e-3;
constexpr double kPiD = 3.14159265358979323846;

void report(const std::string& name, const HistogramResult& r) {
    std::printf("[chi2] %-46s chi2 = %9.2f  dof = %4d  p = %.4f  integral = %.7f  (quadrature warnings %d)\n",
                name.c_str(), r.chi2.chi2, r.chi2.dof, r.chi2.pValue, r.pdfIntegral, r.integrationWarnings);
}

void checkHistogram(const std::string& name, const HistogramResult& r, double alpha) {
    report(name, r);
    INFO(name << "\n" << r.chi2.table);
    CHECK(r.invalid == 0);
    CHECK(r.outside == 0);
    CHECK(r.chi2.pValue > alpha);
}

// ----------------------------------------------------------------------------------------
// Double-precision vectors for the reference computations.

struct V {
    double x = 0, y = 0, z = 0;
};
V vd(Vec3 a) { return {a.x, a.y, a.z}; }
Vec3 vf(V a) { return Vec3(float(a.x), float(a.y), float(a.z)); }
V operator+(V a, V b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V operator-(V a, V b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V operator*(V a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dotd(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V crossd(V a, V b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double lend(V a) { return std::sqrt(dotd(a, a)); }
V unitd(V a) { return a * (1.0 / lend(a)); }

// Two unit vectors completing a unit axis to a right-handed basis.
void basisOf(V n, V* s, V* t) {
    V h = std::abs(n.x) < 0.6 ? V{1, 0, 0} : (std::abs(n.y) < 0.6 ? V{0, 1, 0} : V{0, 0, 1});
    *s = unitd(h - n * dotd(h, n));
    *t = crossd(n, *s);
}

bool closeRel(double a, double b, double rel, double abs = 0) {
    return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)) + abs;
}
bool closeRel(Vec3 a, Vec3 b, double rel, double abs = 0) {
    return closeRel(a.x, b.x, rel, abs) && closeRel(a.y, b.y, rel, abs) && closeRel(a.z, b.z, rel, abs);
}

// glTF spot attenuation in double precision, written from the spec (with the same 0.001
// floor on the cone difference that brume uses).
double spotAttenuationD(double cosInner, double cosOuter, double c) {
    double scale = 1.0 / std::max(0.001, cosInner - cosOuter);
    double a = std::min(1.0, std::max(0.0, (c - cosOuter) * scale));
    return a * a;
}

// ----------------------------------------------------------------------------------------
// Scenes

SceneDescription baseDescription() {
    SceneDescription desc;
    desc.camera.position = Vec3(0, 0, 8);
    return desc;
}

std::unique_ptr<Scene> singleLightScene(const Light& light) {
    SceneDescription desc = baseDescription();
    desc.lights.push_back(light);
    return std::make_unique<Scene>(desc);
}

Light pointLight() {
    Light l;
    l.kind = LightKind::Point;
    l.position = Vec3(0.7f, -1.2f, 2.1f);
    l.intensity = Spectrum(3.0f, 5.0f, 7.0f);
    return l;
}

// Cone half-angles in radians.
Light spotLight(double inner, double outer) {
    Light l;
    l.kind = LightKind::Spot;
    l.position = Vec3(-1.0f, 2.0f, 0.5f);
    l.direction = normalize(Vec3(0.3f, -1.0f, 0.25f));
    l.intensity = Spectrum(10.0f, 20.0f, 30.0f);
    l.cosInner = float(std::cos(inner));
    l.cosOuter = float(std::cos(outer));
    return l;
}

Light sphereLight() {
    Light l;
    l.kind = LightKind::Sphere;
    l.position = Vec3(0.2f, -0.3f, 1.1f);
    l.radius = 0.35f;
    l.intensity = Spectrum(2.0f, 3.0f, 4.0f);
    return l;
}

const Spectrum kEmission(1.5f, 2.0f, 0.5f);

// A quad of two triangles (0, 1, 2) and (0, 2, 3) in a tilted plane, with texture
// coordinates; the second triangle is the one tested. With `textured` the emission is
// modulated by a 3 × 2 texture of very different texels (bilinear, so it varies smoothly).
std::unique_ptr<Scene> triangleScene(bool doubleSided, bool textured) {
    SceneDescription desc = baseDescription();
    Material m;
    m.emission = kEmission;
    m.doubleSided = doubleSided;
    if (textured) {
        Texture t;
        t.width = 3;
        t.height = 2;
        t.texels = {Spectrum(1.0f, 0.2f, 0.5f), Spectrum(0.1f, 1.0f, 2.0f), Spectrum(3.0f, 0.5f, 0.1f),
                    Spectrum(0.4f, 0.4f, 4.0f), Spectrum(0.05f, 2.5f, 1.0f), Spectrum(1.5f, 1.5f, 0.2f)};
        desc.textures.push_back(t);
        m.emissiveTexture = 0;
    }
    desc.materials.push_back(m);
    Mesh mesh;
    mesh.positions = {Vec3(-0.4f, 0.8f, 1.5f), Vec3(1.0f, 0.5f, 1.1f), Vec3(0.9f, 1.6f, 0.3f),
                      Vec3(-0.2f, 1.7f, 0.6f)};
    mesh.uvs = {0.1f, 0.9f, 0.95f, 0.8f, 0.7f, 0.05f, 0.2f, 0.3f};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = 0;
    desc.meshes.push_back(mesh);
    return std::make_unique<Scene>(desc);
}
constexpr int kTriangleLight = 1;  // lights: triangle 0, triangle 1

// A directional light in a scene whose bounds come from a (non-emissive) triangle and the camera.
std::unique_ptr<Scene> directionalScene() {
    SceneDescription desc = baseDescription();
    Material m;
    desc.materials.push_back(m);
    Mesh mesh;
    mesh.positions = {Vec3(-3, -1, -2), Vec3(4, -1, -1), Vec3(0, 5, 1)};
    mesh.indices = {0, 1, 2};
    mesh.material = 0;
    desc.meshes.push_back(mesh);
    Light l;
    l.kind = LightKind::Directional;
    l.direction = normalize(Vec3(0.2f, -1.0f, 0.3f));
    l.intensity = Spectrum(4.0f, 3.0f, 2.0f);
    desc.lights.push_back(l);
    return std::make_unique<Scene>(desc);
}

// Corners, unit front normal and area of a triangle light, in double precision.
struct TriangleD {
    V p0, p1, p2, n;
    double area;
};
TriangleD triangleD(const Scene& scene, const Light& light) {
    const Mesh& mesh = scene.mesh(light.mesh);
    const uint32_t* idx = &mesh.indices[3 * light.triangle];
    TriangleD t;
    t.p0 = vd(mesh.positions[idx[0]]);
    t.p1 = vd(mesh.positions[idx[1]]);
    t.p2 = vd(mesh.positions[idx[2]]);
    V c = crossd(t.p1 - t.p0, t.p2 - t.p0);
    t.area = 0.5 * lend(c);
    t.n = unitd(c);
    return t;
}

// Barycentrics (b1, b2) of the projection of p onto the triangle's plane, and p's distance
// from that plane.
std::pair<double, double> barycentrics(const TriangleD& t, V p, double* planeDistance = nullptr) {
    V e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, w = p - t.p0;
    double d11 = dotd(e1, e1), d12 = dotd(e1, e2), d22 = dotd(e2, e2);
    double w1 = dotd(w, e1), w2 = dotd(w, e2);
    double det = d11 * d22 - d12 * d12;
    if (planeDistance) *planeDistance = std::abs(dotd(w, t.n));
    return {(d22 * w1 - d12 * w2) / det, (d11 * w2 - d12 * w1) / det};
}

// The surface point of the triangle light at barycentrics (b1, b2), as a hit a camera ray
// would produce, texture coordinates interpolated in double precision.
SurfaceHit triangleHit(const Scene& scene, const Light& light, double b1, double b2) {
    const Mesh& mesh = scene.mesh(light.mesh);
    const uint32_t* idx = &mesh.indices[3 * light.triangle];
    TriangleD t = triangleD(scene, light);
    double b0 = 1 - b1 - b2;
    SurfaceHit hit;
    hit.mesh = light.mesh;
    hit.triangle = light.triangle;
    hit.p = vf(t.p0 * b0 + t.p1 * b1 + t.p2 * b2);
    hit.ng = hit.ns = vf(t.n);
    hit.t = 1;
    if (!mesh.uvs.empty()) {
        hit.u = float(mesh.uvs[2 * idx[0]] * b0 + mesh.uvs[2 * idx[1]] * b1 + mesh.uvs[2 * idx[2]] * b2);
        hit.v = float(mesh.uvs[2 * idx[0] + 1] * b0 + mesh.uvs[2 * idx[1] + 1] * b1 + mesh.uvs[2 * idx[2] + 1] * b2);
    }
    return hit;
}

// ----------------------------------------------------------------------------------------
// Per-sample checks: geometry, flags, Le, and densities against emissionPdf and against the
// closed forms written here in double precision.

struct SampleChecks {
    long count = 0;
    long badEmissionPdf = 0;  // sample's densities ≠ emissionPdf at (p, n, d)
    long badFormula = 0;      // sample's densities ≠ closed form
    long badGeometry = 0;     // p not on the light, d or n not unit, n on the wrong side
    long badFlags = 0;
    long badLe = 0;
    std::string firstFailure;
    // `what` describes the failure; it is only evaluated for the first one.
    template <class Describe>
    void fail(long* counter, const Describe& what) {
        ++*counter;
        if (firstFailure.empty()) firstFailure = what();
    }
    void print(const std::string& name) const {
        std::printf("       %s: %ld samples; inconsistent emissionPdf %ld, closed-form pdf %ld, geometry %ld, "
                    "flags %ld, Le %ld\n",
                    name.c_str(), count, badEmissionPdf, badFormula, badGeometry, badFlags, badLe);
    }
    void require() const {
        INFO("first failure: " << firstFailure);
        CHECK(count > 0);
        CHECK(badEmissionPdf == 0);
        CHECK(badFormula == 0);
        CHECK(badGeometry == 0);
        CHECK(badFlags == 0);
        CHECK(badLe == 0);
    }
};

std::string describe(const EmissionSample& s) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "p = (%g %g %g) n = (%g %g %g) d = (%g %g %g) Le = (%g %g %g) pdfPos = %g pdfDir = %g delta %d %d",
                  s.p.x, s.p.y, s.p.z, s.n.x, s.n.y, s.n.z, s.d.x, s.d.y, s.d.z, s.Le.x, s.Le.y, s.Le.z, s.pdfPos,
                  s.pdfDir, int(s.deltaPos), int(s.deltaDir));
    return buf;
}

void checkSample(const Scene& scene, const Light& light, const EmissionSample& s, SampleChecks* c) {
    ++c->count;
    auto what = [&] { return describe(s); };
    const V p = vd(s.p), d = vd(s.d), n = vd(s.n);
    if (std::abs(lend(d) - 1) > 1e-5) c->fail(&c->badGeometry, [&] { return "d not unit: " + what(); });

    // Densities against emissionPdf (pdfDir may differ by the rounding of a cosine).
    float pdfPos = -1, pdfDir = -1;
    emissionPdf(scene, light, s.p, s.n, s.d, &pdfPos, &pdfDir);
    if (!closeRel(pdfPos, s.pdfPos, 1e-5) || !closeRel(pdfDir, s.pdfDir, 1e-4, 1e-6))
        c->fail(&c->badEmissionPdf,
                [&] { return what() + "; emissionPdf " + std::to_string(pdfPos) + " " + std::to_string(pdfDir); });

    double refPos = 0, refDir = 0;
    bool deltaPos = false, deltaDir = false;
    Spectrum refLe(0.0f);
    double leRel = 1e-5, leAbs = 0;
    switch (light.kind) {
    case LightKind::Point:
        refPos = 1;
        refDir = 1 / (4 * kPiD);
        deltaPos = true;
        refLe = light.intensity;
        if (!(s.p.x == light.position.x && s.p.y == light.position.y && s.p.z == light.position.z) || lend(n) != 0)
            c->fail(&c->badGeometry, what);
        break;
    case LightKind::Spot: {
        refPos = 1;
        refDir = 1 / (2 * kPiD * (1 - double(light.cosOuter)));
        deltaPos = true;
        V axis = unitd(vd(light.direction));
        double cosTheta = dotd(d, axis);
        refLe = light.intensity * float(spotAttenuationD(light.cosInner, light.cosOuter, cosTheta));
        // The attenuation's slope in cosθ is up to 2/(cosInner − cosOuter); cosθ is good to ~1e-7.
        leAbs = 1e-6 / std::max(0.001, double(light.cosInner) - light.cosOuter) * maxComponent(light.intensity);
        if (!(s.p.x == light.position.x && s.p.y == light.position.y && s.p.z == light.position.z) ||
            lend(n) != 0 || cosTheta < double(light.cosOuter) - 1e-6)
            c->fail(&c->badGeometry, what);
        break;
    }
    case LightKind::Sphere: {
        double r = light.radius;
        V radial = p - vd(light.position);
        double cosTheta = dotd(n, d);
        refPos = 1 / (4 * kPiD * r * r);
        refDir = std::max(0.0, cosTheta) / kPiD;
        refLe = light.intensity / float(kPiD * r * r);
        if (std::abs(lend(radial) - r) > 1e-5 * (r + lend(vd(light.position))) || std::abs(lend(n) - 1) > 1e-5 ||
            lend(radial * (1 / r) - n) > 1e-4 || cosTheta < -1e-6)
            c->fail(&c->badGeometry, what);
        break;
    }
    case LightKind::Triangle: {
        TriangleD t = triangleD(scene, light);
        const Material& m = scene.material(light.mesh);
        double dist;
        auto [b1, b2] = barycentrics(t, p, &dist);
        double cosFront = dotd(t.n, d);
        refPos = 1 / t.area;
        refDir = m.doubleSided ? 0.5 * std::abs(cosFront) / kPiD : std::max(0.0, cosFront) / kPiD;
        // The side emitted from: n is the front normal or (double-sided) its opposite, with d on its side.
        bool front = lend(n - t.n) < 1e-5, back = lend(n + t.n) < 1e-5;
        if (dist > 1e-5 || b1 < -1e-5 || b2 < -1e-5 || b1 + b2 > 1 + 1e-5 || !(front || (back && m.doubleSided)) ||
            dotd(n, d) < -1e-6)
            c->fail(&c->badGeometry, what);
        // Le: the emission a camera ray hitting this point from direction −d would see, and
        // (independently of Scene::emission) the material's factor times the texture.
        SurfaceHit hit = triangleHit(scene, light, b1, b2);
        refLe = scene.emission(hit, s.d);
        Spectrum direct = m.emission;
        if (m.emissiveTexture >= 0) direct *= scene.desc().textures[m.emissiveTexture].lookup(hit.u, hit.v);
        if (!closeRel(refLe, direct, 1e-6)) c->fail(&c->badLe, [&] { return "Scene::emission disagrees with emission·texture: " + what(); });
        leRel = 1e-4;  // texture coordinates from recomputed barycentrics
        break;
    }
    case LightKind::Directional: {
        double R = scene.boundsRadius();
        V dir = unitd(vd(light.direction));
        V centre = vd(scene.boundsCenter()) - dir * R;
        refPos = 1 / (kPiD * R * R);
        refDir = 1;
        deltaDir = true;
        refLe = light.intensity;
        if (lend(d - dir) > 1e-6 || std::abs(dotd(p - centre, dir)) > 1e-5 * R || lend(p - centre) > R * (1 + 1e-5) ||
            lend(n) != 0)
            c->fail(&c->badGeometry, what);
        break;
    }
    }
    if (!closeRel(s.pdfPos, refPos, 1e-5) || !closeRel(s.pdfDir, refDir, 1e-4, 1e-6))
        c->fail(&c->badFormula,
                [&] { return what() + "; expected " + std::to_string(refPos) + " " + std::to_string(refDir); });
    if (s.deltaPos != deltaPos || s.deltaDir != deltaDir) c->fail(&c->badFlags, what);
    if (!closeRel(s.Le, refLe, leRel, leAbs))
        c->fail(&c->badLe, [&] {
            return what() + "; expected Le " + std::to_string(refLe.x) + " " + std::to_string(refLe.y) + " " +
                   std::to_string(refLe.z);
        });
}

// ----------------------------------------------------------------------------------------
// Histogram runs

// cosθ edges for a density confined to cosθ ≥ cosMin about the axis: an empty bin below,
// then `bins` uniform bins from a little below cosMin (float rounding at the rim must not
// push a sample into the empty bin).
std::vector<double> capEdges(double cosMin, int bins, double margin) {
    double lo = cosMin - margin * (1 - cosMin);
    std::vector<double> e = uniformEdges(bins, std::max(-1.0, lo), 1.0);
    if (lo > -1.0) e.insert(e.begin(), -1.0);
    return e;
}

// Emitted directions of one light about `axis`, with the position sample u1 fixed (when
// given) or drawn from an independent stream; the expected density is emissionPdf's pdfDir
// at the origin of the fixed u1 (or any origin: only the sphere's depends on it).
HistogramResult directionTest(const Scene& scene, const Light& light, Vec3 axis, const std::vector<double>& cosEdges,
                              int phiBins, uint64_t seed, std::optional<Sample2> fixedU1, SampleChecks* checks) {
    EmissionSample ref;
    // (u2 = (0.5, 0.5) would be the rim of a two-sided triangle's back lobe: density 0.)
    REQUIRE(sampleEmission(scene, light, fixedU1.value_or(Sample2{0.3f, 0.6f}), Sample2{0.3f, 0.6f}, &ref));
    Sampler positions(seed + 1000, 0, 0);
    SphereHistogramOptions opt;
    opt.seed = seed;
    opt.axis = axis;
    opt.cosThetaEdges = cosEdges;
    auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
        Sample2 u1 = fixedU1 ? *fixedU1 : positions.next2D();
        EmissionSample s;
        if (!sampleEmission(scene, light, u1, u, &s)) return std::nullopt;
        checkSample(scene, light, s, checks);
        return s.d;
    };
    auto pdfFn = [&](Vec3 w) -> double {
        float pdfPos, pdfDir;
        emissionPdf(scene, light, ref.p, ref.n, w, &pdfPos, &pdfDir);
        return pdfDir;
    };
    return sphereHistogramTest(sampleFn, pdfFn, int(cosEdges.size()) - 1, phiBins, kSamples, opt);
}

}  // namespace

// ----------------------------------------------------------------------------------------
// Directions

TEST_CASE("emission directions: point light, uniform on the sphere", "[chi2][emission]") {
    auto scene = singleLightScene(pointLight());
    const Light& light = scene->lights()[0];
    SampleChecks checks;
    HistogramResult r = directionTest(*scene, light, normalize(Vec3(0.3f, 0.5f, -0.8f)), uniformEdges(16, -1, 1), 24,
                                      11, std::nullopt, &checks);
    checkHistogram("point light directions", r, kAlpha);
    checks.print("point light");
    checks.require();
    CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
}

TEST_CASE("emission directions: spot light, uniform in the outer cone", "[chi2][emission]") {
    struct Case {
        double inner, outer;  // half-angles [rad]
    };
    const Case cases[] = {{0.02, 0.05}, {0.3, 0.5}, {0.2, 1.1}, {1.0, kPiD / 2}};
    const double alpha = kAlpha / std::size(cases);
    int k = 0;
    for (const Case& c : cases) {
        auto scene = singleLightScene(spotLight(c.inner, c.outer));
        const Light& light = scene->lights()[0];
        SampleChecks checks;
        HistogramResult r = directionTest(*scene, light, light.direction, capEdges(light.cosOuter, 20, 0.02), 24,
                                          21 + k++, std::nullopt, &checks);
        std::string name = "spot light directions, outer " + std::to_string(c.outer);
        checkHistogram(name, r, alpha);
        checks.print(name);
        checks.require();
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
}

TEST_CASE("emission directions: sphere light, cosine lobe about the normal at a fixed point", "[chi2][emission]") {
    auto scene = singleLightScene(sphereLight());
    const Light& light = scene->lights()[0];
    // Points on the sphere near both poles (where Frame switches branch) and in between.
    const Sample2 origins[] = {{0.3f, 0.7f}, {0.0005f, 0.2f}, {0.9995f, 0.9f}};
    const double alpha = kAlpha / std::size(origins);
    int k = 0;
    for (Sample2 u1 : origins) {
        EmissionSample ref;
        REQUIRE(sampleEmission(*scene, light, u1, Sample2{0.3f, 0.6f}, &ref));
        SampleChecks checks;
        HistogramResult r = directionTest(*scene, light, ref.n, capEdges(0.0, 20, 0.05), 24, 31 + k++, u1, &checks);
        std::string name = "sphere light directions, normal z = " + std::to_string(ref.n.z);
        checkHistogram(name, r, alpha);
        checks.print(name);
        checks.require();
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
}

TEST_CASE("emission directions: triangle light, one- and two-sided", "[chi2][emission]") {
    const double alpha = kAlpha / 3;
    auto oneSided = triangleScene(false, false);
    auto twoSided = triangleScene(true, true);
    int k = 0;
    for (const Scene* scene : {oneSided.get(), twoSided.get()}) {
        const Light& light = scene->lights()[kTriangleLight];
        const bool ds = scene->material(light.mesh).doubleSided;
        const Vec3 front = vf(triangleD(*scene, light).n);
        SampleChecks checks;
        // One-sided: the front hemisphere; two-sided: the whole sphere, half on each side.
        HistogramResult r = directionTest(*scene, light, front, ds ? uniformEdges(20, -1, 1) : capEdges(0.0, 20, 0.05),
                                          24, 41 + k++, std::nullopt, &checks);
        std::string name = ds ? "triangle light directions, two-sided" : "triangle light directions, one-sided";
        checkHistogram(name, r, alpha);
        checks.print(name);
        checks.require();
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
    // Two-sided: the cosine lobe on the chosen side, about that side's normal (the returned n).
    {
        const Scene& scene = *twoSided;
        const Light& light = scene.lights()[kTriangleLight];
        Sampler positions(52, 0, 0);
        long back = 0, count = 0;
        SphereHistogramOptions opt;
        opt.seed = 51;
        opt.cosThetaEdges = capEdges(0.0, 20, 0.05);
        // Each direction expressed in the frame of its own n, so both lobes land on +z.
        const TriangleD t = triangleD(scene, light);
        V s0, t0;
        basisOf(t.n, &s0, &t0);
        auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
            EmissionSample s;
            if (!sampleEmission(scene, light, positions.next2D(), u, &s)) return std::nullopt;
            ++count;
            V n = vd(s.n), d = vd(s.d);
            bool isBack = dotd(n, t.n) < 0;
            back += isBack;
            // Mirror the back lobe through the plane: (s, t, n) → (s, −t, −n) keeps handedness.
            double x = dotd(d, s0), y = dotd(d, t0) * (isBack ? -1 : 1), z = dotd(d, n);
            return vf(V{x, y, z});
        };
        auto pdfFn = [&](Vec3 w) -> double { return std::max(0.0f, w.z) / kPi; };
        HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, int(opt.cosThetaEdges.size()) - 1, 24, kSamples, opt);
        checkHistogram("two-sided triangle, lobe about the returned n", r, alpha);
        // The side is a fair coin: within 4 standard deviations of half.
        double sd = std::sqrt(0.25 * double(count));
        std::printf("       back side chosen %ld of %ld (z = %.2f)\n", back, count, (back - 0.5 * count) / sd);
        CHECK(std::abs(back - 0.5 * double(count)) < 4 * sd);
    }
}

// ----------------------------------------------------------------------------------------
// Positions

TEST_CASE("emission origins: uniform on a triangle, on a sphere and on the directional disk", "[chi2][emission]") {
    const double alpha = kAlpha / 5;  // three triangle runs, the sphere and the disk
    // Triangles: barycentrics (b1, b2) have density pdfPos · 2A on b1 + b2 ≤ 1.
    {
        auto oneSided = triangleScene(false, false);
        auto twoSided = triangleScene(true, true);
        int k = 0;
        for (const Scene* scene : {oneSided.get(), twoSided.get()}) {
            for (int li : {0, 1}) {
                if (scene == twoSided.get() && li == 0) continue;  // three runs in all
                const Light& light = scene->lights()[li];
                const TriangleD t = triangleD(*scene, light);
                SampleChecks checks;
                Sampler directions(62 + k, 0, 0);
                HistogramOptions opt;
                opt.seed = 61 + k++;
                auto sampleFn = [&](Sample2 u) -> std::optional<std::pair<double, double>> {
                    EmissionSample s;
                    if (!sampleEmission(*scene, light, u, directions.next2D(), &s)) return std::nullopt;
                    checkSample(*scene, light, s, &checks);
                    // A point on an edge comes back a hair outside from the double-precision
                    // solve; checkSample has checked it lies on the triangle (to 1e-5).
                    auto [b1, b2] = barycentrics(t, vd(s.p));
                    return std::make_pair(std::max(0.0, b1), std::max(0.0, b2));
                };
                auto pdfFn = [&](double b1, double b2) -> double {
                    if (b1 + b2 > 1) return 0.0;
                    V p = t.p0 * (1 - b1 - b2) + t.p1 * b1 + t.p2 * b2;
                    float pdfPos, pdfDir;
                    emissionPdf(*scene, light, vf(p), vf(t.n), vf(t.n), &pdfPos, &pdfDir);
                    return pdfPos * 2 * t.area;
                };
                std::vector<double> edges = uniformEdges(12, 0, 1);
                HistogramResult r = histogram2DTest(sampleFn, pdfFn, edges, edges, kSamples, opt);
                std::string name = std::string("triangle ") + std::to_string(li) + " origins" +
                                   (scene == twoSided.get() ? ", two-sided textured" : "");
                checkHistogram(name, r, alpha);
                checks.print(name);
                checks.require();
                CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
            }
        }
    }
    // Sphere: the outward normal (p − c)/r is uniform on the unit sphere, density pdfPos·r².
    {
        auto scene = singleLightScene(sphereLight());
        const Light& light = scene->lights()[0];
        const V c = vd(light.position);
        const double r0 = light.radius;
        SampleChecks checks;
        Sampler directions(72, 0, 0);
        SphereHistogramOptions opt;
        opt.seed = 71;
        opt.axis = normalize(Vec3(0.2f, -0.5f, 0.6f));
        auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
            EmissionSample s;
            if (!sampleEmission(*scene, light, u, directions.next2D(), &s)) return std::nullopt;
            checkSample(*scene, light, s, &checks);
            return vf(unitd(vd(s.p) - c));
        };
        auto pdfFn = [&](Vec3 w) -> double {
            V n = vd(w);
            float pdfPos, pdfDir;
            emissionPdf(*scene, light, vf(c + n * r0), w, w, &pdfPos, &pdfDir);
            return pdfPos * r0 * r0;
        };
        HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, 20, 24, kSamples, opt);
        checkHistogram("sphere light origins (normals)", r, alpha);
        checks.print("sphere light origins");
        checks.require();
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
    // Directional: on the disk, (ρ/R)² and the angle φ are uniform: density pdfPos·R²/2.
    {
        auto scene = directionalScene();
        const Light& light = scene->lights()[0];
        const double R = scene->boundsRadius();
        const V dir = unitd(vd(light.direction));
        const V centre = vd(scene->boundsCenter()) - dir * R;
        V s0, t0;
        basisOf(dir, &s0, &t0);
        SampleChecks checks;
        HistogramOptions opt;
        opt.seed = 81;
        auto sampleFn = [&](Sample2 u) -> std::optional<std::pair<double, double>> {
            EmissionSample s;
            if (!sampleEmission(*scene, light, u, Sample2{0.5f, 0.5f}, &s)) return std::nullopt;
            checkSample(*scene, light, s, &checks);
            V q = vd(s.p) - centre;
            double x = dotd(q, s0) / R, y = dotd(q, t0) / R;
            double phi = std::atan2(y, x);
            if (phi < 0) phi += 2 * kPiD;
            return std::make_pair(x * x + y * y, phi);
        };
        auto pdfFn = [&](double rho2, double phi) -> double {
            double rho = std::sqrt(rho2) * R;
            V p = centre + s0 * (rho * std::cos(phi)) + t0 * (rho * std::sin(phi));
            float pdfPos, pdfDir;
            emissionPdf(*scene, light, vf(p), Vec3(), light.direction, &pdfPos, &pdfDir);
            return pdfPos * R * R / 2;
        };
        // ρ² may exceed 1 by rounding: the last bin reaches a little beyond the rim (density 0 there).
        std::vector<double> rhoEdges = uniformEdges(10, 0, 1);
        rhoEdges.back() = 1 + 1e-5;
        HistogramResult r = histogram2DTest(
            sampleFn, [&](double x, double y) { return x <= 1 ? pdfFn(x, y) : 0.0; }, rhoEdges,
            uniformEdges(16, 0, 2 * kPiD), kSamples, opt);
        checkHistogram("directional light origins (rho^2, phi)", r, alpha);
        checks.print("directional light origins");
        checks.require();
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
}

// ----------------------------------------------------------------------------------------
// emissionPdf where sampling cannot go, delta conventions, degenerate lights

TEST_CASE("emissionPdf: zero where no emission goes, 1 for delta parts", "[emission]") {
    float pdfPos, pdfDir;
    {  // One-sided triangle: nothing behind; two-sided: the same density on both sides.
        auto oneSided = triangleScene(false, false);
        auto twoSided = triangleScene(true, false);
        const Light& l1 = oneSided->lights()[kTriangleLight];
        const TriangleD t = triangleD(*oneSided, l1);
        V s0, t0;
        basisOf(t.n, &s0, &t0);
        const Vec3 p = vf((t.p0 + t.p1 + t.p2) * (1.0 / 3));
        const Vec3 out = vf(unitd(t.n + s0 * 0.5)), in = vf(unitd(t.n * -1 + s0 * 0.5));
        emissionPdf(*oneSided, l1, p, vf(t.n), in, &pdfPos, &pdfDir);
        CHECK(pdfPos == Approx(1 / t.area).epsilon(1e-5));
        CHECK(pdfDir == 0.0f);
        emissionPdf(*oneSided, l1, p, vf(t.n), out, &pdfPos, &pdfDir);
        CHECK(pdfDir == Approx(dotd(t.n, vd(out)) / kPiD).epsilon(1e-5));
        const Light& l2 = twoSided->lights()[kTriangleLight];
        float frontDir, backDir;
        emissionPdf(*twoSided, l2, p, vf(t.n), out, &pdfPos, &frontDir);
        emissionPdf(*twoSided, l2, p, vf(t.n * -1), in, &pdfPos, &backDir);
        CHECK(frontDir == Approx(0.5 * dotd(t.n, vd(out)) / kPiD).epsilon(1e-5));
        CHECK(backDir == Approx(frontDir).epsilon(1e-6));
    }
    {  // Spot: nothing outside the outer cone; position is a delta (1).
        auto scene = singleLightScene(spotLight(0.3, 0.5));
        const Light& l = scene->lights()[0];
        V axis = unitd(vd(l.direction)), s0, t0;
        basisOf(axis, &s0, &t0);
        emissionPdf(*scene, l, l.position, Vec3(), vf(axis * std::cos(0.49) + s0 * std::sin(0.49)), &pdfPos, &pdfDir);
        CHECK(pdfPos == 1.0f);
        CHECK(pdfDir == Approx(1 / (2 * kPiD * (1 - double(l.cosOuter)))).epsilon(1e-5));
        emissionPdf(*scene, l, l.position, Vec3(), vf(axis * std::cos(0.51) + s0 * std::sin(0.51)), &pdfPos, &pdfDir);
        CHECK(pdfDir == 0.0f);
        emissionPdf(*scene, l, l.position, Vec3(), vf(axis * -1), &pdfPos, &pdfDir);
        CHECK(pdfDir == 0.0f);
    }
    {  // Sphere: nothing into the sphere.
        auto scene = singleLightScene(sphereLight());
        const Light& l = scene->lights()[0];
        V n = unitd({0.3, -0.2, 0.9});
        Vec3 p = vf(vd(l.position) + n * l.radius);
        emissionPdf(*scene, l, p, vf(n), vf(n * -1), &pdfPos, &pdfDir);
        CHECK(pdfDir == 0.0f);
        CHECK(pdfPos == Approx(1 / (4 * kPiD * l.radius * l.radius)).epsilon(1e-5));
        emissionPdf(*scene, l, p, vf(n), vf(n), &pdfPos, &pdfDir);
        CHECK(pdfDir == Approx(1 / kPiD).epsilon(1e-5));
    }
    {  // Point: (1, 1/4π); directional: (1/πR², 1).
        auto scene = singleLightScene(pointLight());
        emissionPdf(*scene, scene->lights()[0], scene->lights()[0].position, Vec3(), Vec3(0, 0, 1), &pdfPos, &pdfDir);
        CHECK(pdfPos == 1.0f);
        CHECK(pdfDir == Approx(1 / (4 * kPiD)).epsilon(1e-6));
        auto dscene = directionalScene();
        const Light& l = dscene->lights()[0];
        emissionPdf(*dscene, l, dscene->boundsCenter() - l.direction * dscene->boundsRadius(), Vec3(), l.direction,
                    &pdfPos, &pdfDir);
        const double R = dscene->boundsRadius();
        CHECK(pdfPos == Approx(1 / (kPiD * R * R)).epsilon(1e-5));
        CHECK(pdfDir == 1.0f);
    }
}

TEST_CASE("degenerate lights emit nothing", "[emission]") {
    EmissionSample s;
    {
        SceneDescription desc = baseDescription();
        Material m;
        m.emission = kEmission;
        desc.materials.push_back(m);
        Mesh mesh;
        mesh.positions = {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)};  // collinear
        mesh.indices = {0, 1, 2};
        mesh.material = 0;
        desc.meshes.push_back(mesh);
        Scene scene(desc);
        REQUIRE(scene.lights().size() == 1);
        CHECK_FALSE(sampleEmission(scene, scene.lights()[0], Sample2{0.3f, 0.3f}, Sample2{0.3f, 0.3f}, &s));
        CHECK(s.pdfPos == 0.0f);
        CHECK(s.pdfDir == 0.0f);
        float pdfPos = -1, pdfDir = -1;
        emissionPdf(scene, scene.lights()[0], Vec3(1, 1, 1), Vec3(0, 0, 1), Vec3(0, 0, 1), &pdfPos, &pdfDir);
        CHECK(pdfPos == 0.0f);
        CHECK(pdfDir == 0.0f);
    }
    {
        Light l = sphereLight();
        l.radius = 0;
        auto scene = singleLightScene(l);
        CHECK_FALSE(sampleEmission(*scene, scene->lights()[0], Sample2{0.3f, 0.3f}, Sample2{0.3f, 0.3f}, &s));
        CHECK(s.pdfPos == 0.0f);
    }
}

// ----------------------------------------------------------------------------------------
// Emitted radiance and intensity

TEST_CASE("emitted Le: sphere radiance, spot attenuation, textured triangle", "[emission]") {
    {  // Sphere: I/(πr²) everywhere, every direction.
        auto scene = singleLightScene(sphereLight());
        const Light& l = scene->lights()[0];
        const double L = 1 / (kPiD * l.radius * l.radius);
        Sampler rng(91, 0, 0);
        long bad = 0;
        for (int i = 0; i < 10000; ++i) {
            EmissionSample s;
            REQUIRE(sampleEmission(*scene, l, rng.next2D(), rng.next2D(), &s));
            if (!closeRel(s.Le, l.intensity * float(L), 1e-6)) ++bad;
        }
        CHECK(bad == 0);
    }
    {  // Spot: full intensity at the centre and across the inner cone, 0 at the outer rim.
        auto scene = singleLightScene(spotLight(0.3, 0.5));
        const Light& l = scene->lights()[0];
        EmissionSample s;
        REQUIRE(sampleEmission(*scene, l, Sample2{0.5f, 0.5f}, Sample2{0.0f, 0.25f}, &s));  // cosθ = 1
        CHECK(closeRel(s.Le, l.intensity, 1e-6));
        CHECK(dotd(vd(s.d), unitd(vd(l.direction))) == Approx(1.0).epsilon(1e-6));
        // u2.u maps linearly to cosθ from 1 down to cosOuter: the inner edge, halfway and the rim.
        const double cosI = l.cosInner, cosO = l.cosOuter;
        const double uInner = (1 - cosI) / (1 - cosO);
        REQUIRE(sampleEmission(*scene, l, Sample2{0.5f, 0.5f}, Sample2{float(uInner * 0.999), 0.6f}, &s));
        CHECK(closeRel(s.Le, l.intensity, 1e-6));
        const double uMid = 0.5 * (uInner + 1);
        REQUIRE(sampleEmission(*scene, l, Sample2{0.5f, 0.5f}, Sample2{float(uMid), 0.1f}, &s));
        const double aMid = spotAttenuationD(cosI, cosO, 1 - uMid * (1 - cosO));  // ≈ 1/4
        INFO("halfway between the cones: attenuation " << aMid << ", Le.x " << s.Le.x);
        CHECK(aMid == Approx(0.25).epsilon(1e-3));
        CHECK(closeRel(s.Le, l.intensity * float(aMid), 1e-3));
        REQUIRE(sampleEmission(*scene, l, Sample2{0.5f, 0.5f}, Sample2{std::nextafter(1.0f, 0.0f), 0.9f}, &s));
        CHECK(maxComponent(s.Le) <= 1e-6f * maxComponent(l.intensity));
        CHECK(dotd(vd(s.d), unitd(vd(l.direction))) == Approx(cosO).epsilon(1e-5));
    }
    {  // Textured triangle, both sides: Le = Scene::emission at the same point (checked per
       // sample in checkSample), and it does vary with the texture.
        auto scene = triangleScene(true, true);
        const Light& l = scene->lights()[kTriangleLight];
        Sampler rng(92, 0, 0);
        SampleChecks checks;
        double lo = 1e30, hi = 0;
        long back = 0;
        for (int i = 0; i < 20000; ++i) {
            EmissionSample s;
            REQUIRE(sampleEmission(*scene, l, rng.next2D(), rng.next2D(), &s));
            checkSample(*scene, l, s, &checks);
            lo = std::min(lo, double(s.Le.x));
            hi = std::max(hi, double(s.Le.x));
            back += dot(s.n, vf(triangleD(*scene, l).n)) < 0;
        }
        checks.print("textured two-sided triangle Le");
        checks.require();
        CHECK(hi > 2 * lo);  // the texture shows
        CHECK(back > 0);
    }
}

// ----------------------------------------------------------------------------------------
// Power: E[Le·|cos|/(pdfPos·pdfDir)] is the light's total (grey) power.

namespace {

struct PowerEstimate {
    double mean, stdError;
    long samples;
};

PowerEstimate estimatePower(const Scene& scene, const Light& light, uint64_t seed, long n) {
    Sampler rng(seed, 0, 0);
    RunningStats stats;
    for (long i = 0; i < n; ++i) {
        Sample2 u1 = rng.next2D(), u2 = rng.next2D();
        EmissionSample s;
        double x = 0;
        if (sampleEmission(scene, light, u1, u2, &s)) {
            // |cos| at the origin: 1 where there is no surface (point, spot, directional).
            double c = (s.n.x == 0 && s.n.y == 0 && s.n.z == 0) ? 1.0 : std::abs(dotd(vd(s.n), vd(s.d)));
            x = average(s.Le) * c / (double(s.pdfPos) * s.pdfDir);
        }
        stats.add(x);
    }
    return {stats.mean(), stats.standardError(), n};
}

}  // namespace

TEST_CASE("emission power matches closed forms and lightPower", "[emission]") {
    struct Case {
        std::string name;
        std::unique_ptr<Scene> scene;
        int light;
        double reference;
        bool lightPowerExact;
    };
    std::vector<Case> cases;
    {
        auto s = singleLightScene(pointLight());
        double ref = 4 * kPiD * average(s->lights()[0].intensity);
        cases.push_back({"point", std::move(s), 0, ref, true});
    }
    const std::pair<double, double> spots[] = {{0.3, 0.5}, {0.02, 0.05}, {0.0, 1.2}, {0.7, 0.7005}};
    for (auto [inner, outer] : spots) {
        auto s = singleLightScene(spotLight(inner, outer));
        const Light& l = s->lights()[0];
        const double ci = l.cosInner, co = l.cosOuter;
        // 2π ∫ attenuation(cosθ) dcosθ over the outer cone, by quadrature (broken at the inner edge).
        auto att = [&](double c) { return spotAttenuationD(ci, co, c); };
        double split = std::min(1.0, std::max(co, co + std::max(0.001, ci - co)));
        double integral = integrate1D(att, co, split, 1e-14, 1e-10) + (split < 1 ? integrate1D(att, split, 1.0, 1e-14, 1e-10) : 0);
        double ref = 2 * kPiD * integral * average(l.intensity);
        cases.push_back({"spot " + std::to_string(inner) + " / " + std::to_string(outer), std::move(s), 0, ref, false});
    }
    {
        auto s = singleLightScene(sphereLight());
        double ref = 4 * kPiD * average(s->lights()[0].intensity);
        cases.push_back({"sphere", std::move(s), 0, ref, true});
    }
    for (bool ds : {false, true}) {
        auto s = triangleScene(ds, false);
        const Light& l = s->lights()[kTriangleLight];
        double ref = kPiD * average(kEmission) * triangleD(*s, l).area * (ds ? 2 : 1);
        cases.push_back({ds ? "triangle, two-sided" : "triangle, one-sided", std::move(s), kTriangleLight, ref, true});
    }
    {
        // Textured: π·A·(mean emission over the triangle), the mean by quadrature over the
        // barycentrics. lightPower uses the whole texture's average instead: not exact here.
        auto s = triangleScene(true, true);
        const Light& l = s->lights()[kTriangleLight];
        const Scene& sc = *s;
        const TriangleD t = triangleD(sc, l);
        auto f = [&](double b1, double b2) -> double {
            if (b1 + b2 > 1) return 0.0;
            return average(sc.emission(triangleHit(sc, l, b1, b2), vf(t.n)));
        };
        double meanL = 2 * integrate2D(f, 0, 1, 0, 1, 1e-9, 1e-7, 16);
        double ref = 2 * kPiD * t.area * meanL;
        cases.push_back({"triangle, two-sided, textured", std::move(s), kTriangleLight, ref, false});
    }
    {
        auto s = directionalScene();
        double R = s->boundsRadius();
        double ref = kPiD * R * R * average(s->lights()[0].intensity);
        cases.push_back({"directional", std::move(s), 0, ref, true});
    }
    uint64_t seed = 101;
    for (const Case& c : cases) {
        const Light& light = c.scene->lights()[c.light];
        PowerEstimate e = estimatePower(*c.scene, light, seed++, 100000);
        double lp = lightPower(*c.scene, light);
        // 4 standard errors, plus float rounding where the estimator is (nearly) constant.
        double tol = 4 * e.stdError + 1e-5 * c.reference;
        // Most of these estimators are constant (perfect importance sampling): their
        // "standard error" is float noise, so the relative difference says more than z.
        std::printf("[power] %-30s estimate %.7g ± %.2g  closed form %.7g  (rel. diff %+.1e, z = %+.2f)  "
                    "lightPower %.6g (%s, ratio %.5f)\n",
                    c.name.c_str(), e.mean, e.stdError, c.reference, e.mean / c.reference - 1,
                    e.stdError > 0 ? (e.mean - c.reference) / e.stdError : 0.0, lp,
                    c.lightPowerExact ? "exact" : "approximate", lp / c.reference);
        INFO(c.name << ": estimate " << e.mean << " ± " << e.stdError << ", closed form " << c.reference
                    << ", lightPower " << lp);
        CHECK(std::abs(e.mean - c.reference) <= tol);
        if (c.lightPowerExact) CHECK(lp == Approx(c.reference).epsilon(1e-5));
    }
}
