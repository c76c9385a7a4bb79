// The light operations integrators use instead of a light's kind (scene/light_geometry.h,
// deltaEmission, the emitter record built at load): the record against the mesh it came
// from, the equi-angular anchor's distribution (chi-square, significance 0.01), the clipping
// of a ray to where a light reaches, a point's normal and texture coordinates.
#include <catch2/catch.hpp>

#include <cmath>
#include <optional>

#include "brume/scene/light_emission.h"
#include "brume/scene/light_geometry.h"
#include "brume/scene/light_sampling.h"
#include "brume/scene/scene.h"
#include "brume/scene/scene_description.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

bool same(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// A 2 × 1 rectangle in the plane z = 1, facing −z (towards the camera side below), made of
// two triangles that pair into one rectangle, with texture coordinates.
SceneDescription rectangleScene(bool doubleSided) {
    SceneDescription desc;
    desc.camera.position = Vec3(0, 0, -5);
    Material m;
    m.emission = Spectrum(2.0f, 1.0f, 0.5f);
    m.doubleSided = doubleSided;
    desc.materials.push_back(m);
    Mesh mesh;
    mesh.positions = {Vec3(0, 0, 1), Vec3(0, 1, 1), Vec3(2, 1, 1), Vec3(2, 0, 1)};
    mesh.uvs = {0, 0, 0, 1, 1, 1, 1, 0};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = 0;
    desc.meshes.push_back(mesh);
    return desc;
}

Light spotLight() {
    Light l;
    l.kind = LightKind::Spot;
    l.position = Vec3(0, 0, 0);
    l.direction = Vec3(0, 0, 1);
    l.intensity = Spectrum(3.0f);
    l.cosInner = std::cos(0.2f);
    l.cosOuter = std::cos(0.4f);
    return l;
}

}  // namespace

TEST_CASE("the emitter record is the triangle of its mesh, paired with its rectangle's other half", "[light]") {
    for (bool doubleSided : {false, true}) {
        Scene scene(rectangleScene(doubleSided));
        REQUIRE(scene.lights().size() == 2);
        for (int i = 0; i < 2; ++i) {
            const Light& l = scene.lights()[size_t(i)];
            const Mesh& mesh = scene.mesh(l.mesh);
            const uint32_t* idx = &mesh.indices[3 * size_t(l.triangle)];
            CHECK(l.isPlanar());
            CHECK(l.hasSurface());
            CHECK_FALSE(l.isDelta());
            CHECK_FALSE(l.atInfinity());
            CHECK(same(l.shape.p0, mesh.positions[idx[0]]));
            CHECK(same(l.shape.p1, mesh.positions[idx[1]]));
            CHECK(same(l.shape.p2, mesh.positions[idx[2]]));
            CHECK(l.shape.area == Approx(1.0f));
            // (0,0)→(0,1)→(2,1) turns clockwise seen from −z: the front faces −z.
            CHECK(l.shape.n.z == Approx(-1.0f));
            CHECK(l.doubleSided == doubleSided);
            CHECK(l.power == Approx(lightPower(scene, l)));
            CHECK(l.power > 0);
            REQUIRE(l.partner >= 0);
            const Light& other = scene.partnerOf(l);
            CHECK(&other != &l);
            CHECK(&scene.partnerOf(other) == &l);
        }
    }
}

TEST_CASE("what integrators ask of each kind of light", "[light]") {
    Light point, spot = spotLight(), sphere, directional;
    point.kind = LightKind::Point;
    sphere.kind = LightKind::Sphere;
    sphere.radius = 0.5f;
    directional.kind = LightKind::Directional;
    CHECK(point.isDelta());
    CHECK(spot.isDelta());
    CHECK(directional.isDelta());
    CHECK_FALSE(sphere.isDelta());
    CHECK(directional.atInfinity());
    CHECK_FALSE(point.atInfinity());
    CHECK(sphere.hasSurface());
    CHECK_FALSE(point.hasSurface());
    CHECK_FALSE(sphere.isPlanar());

    // Anchors: a position, or none at infinity.
    point.position = Vec3(1, 2, 3);
    Vec3 anchor;
    REQUIRE(lightAnchor(point, Sample2{0.3f, 0.7f}, &anchor));
    CHECK(same(anchor, point.position));
    CHECK_FALSE(lightAnchor(directional, Sample2{0.3f, 0.7f}, &anchor));

    // Delta emission: a spot's intensity on its axis, nothing outside its outer cone.
    point.intensity = Spectrum(5.0f);
    CHECK(deltaEmission(point, Vec3(0, 1, 0))[0] == 5.0f);
    CHECK(deltaEmission(spot, Vec3(0, 0, 1))[0] == Approx(3.0f));
    CHECK(deltaEmission(spot, normalize(Vec3(1, 0, 1)))[0] == 0.0f);

    // Normals: a sphere's outward one; none for a point light.
    sphere.position = Vec3(0, 0, 0);
    CHECK(lightNormalFacing(sphere, Vec3(0, 0.5f, 0), Vec3(0, -1, 0)).y == Approx(1.0f));
    CHECK(same(lightNormalFacing(point, Vec3(1, 2, 3), Vec3(0, 1, 0)), Vec3(0.0f)));
}

TEST_CASE("lightAnchor: a planar emitter's anchor is uniform by area on it (chi-square)", "[light][chi2]") {
    Scene scene(rectangleScene(false));
    const Light& l = scene.lights()[0];
    const EmitterTriangle& t = l.shape;
    // Barycentrics (b1, b2) of the anchor: density 2 on b1 + b2 ≤ 1.
    auto sample = [&](Sample2 u) -> std::optional<std::pair<double, double>> {
        Vec3 a;
        if (!lightAnchor(l, u, &a)) return std::nullopt;
        const Vec3 n = t.edgeCross();
        const double nn = dot(n, n);
        const double b1 = dot(cross(a - t.p0, t.p2 - t.p0), n) / nn, b2 = dot(cross(t.p1 - t.p0, a - t.p0), n) / nn;
        if (std::abs(dot(a - t.p0, t.n)) > 1e-5) return std::nullopt;  // off the plane
        return std::make_pair(b1, b2);
    };
    auto pdf = [](double b1, double b2) { return b1 >= 0 && b2 >= 0 && b1 + b2 <= 1 ? 2.0 : 0.0; };
    const HistogramResult r = histogram2DTest(sample, pdf, uniformEdges(12, 0, 1), uniformEdges(12, 0, 1), 200000);
    INFO(r.chi2.table);
    CHECK(r.invalid == 0);
    CHECK(r.outside == 0);
    CHECK(r.chi2.pValue > 0.01);
}

TEST_CASE("clipRayToLight keeps exactly the part of a ray the light reaches", "[light]") {
    SECTION("a one-sided emitter: its front half-space; a double-sided one: all of it") {
        for (bool doubleSided : {false, true}) {
            Scene scene(rectangleScene(doubleSided));
            const Light& l = scene.lights()[0];
            // From z = −1 upwards through the plane z = 1: the front (z < 1) is t < 2.
            float t0 = 0, t1 = 10;
            REQUIRE(clipRayToLight(l, Vec3(0.5f, 0.5f, -1), Vec3(0, 0, 1), &t0, &t1));
            CHECK(t0 == 0.0f);
            CHECK(t1 == Approx(doubleSided ? 10.0f : 2.0f));
            // From behind, downwards: the front is t > 1 (z below 1).
            t0 = 0, t1 = 10;
            REQUIRE(clipRayToLight(l, Vec3(0.5f, 0.5f, 2), Vec3(0, 0, -1), &t0, &t1));
            CHECK(t0 == Approx(doubleSided ? 0.0f : 1.0f));
            CHECK(t1 == 10.0f);
            // Parallel to the plane behind it: nothing (one-sided), all (double-sided).
            t0 = 0, t1 = 10;
            CHECK(clipRayToLight(l, Vec3(0, 0, 3), Vec3(1, 0, 0), &t0, &t1) == doubleSided);
        }
    }
    SECTION("a spot light: its cone; a point light: all of it") {
        const Light spot = spotLight();
        float t0 = -10, t1 = 10, s0 = -10, s1 = 10;
        const Vec3 o(-3, 0, 2), d(1, 0, 0);
        REQUIRE(clipRayToLight(spot, o, d, &t0, &t1));
        REQUIRE(clipToSpotCone(spot, o, d, &s0, &s1));
        CHECK(t0 == s0);
        CHECK(t1 == s1);
        // |x| ≤ 2·tan(0.4) on the line z = 2.
        CHECK(t0 == Approx(3 - 2 * std::tan(0.4)).epsilon(1e-4));
        CHECK(t1 == Approx(3 + 2 * std::tan(0.4)).epsilon(1e-4));
        Light point;
        point.kind = LightKind::Point;
        t0 = 0, t1 = 7;
        REQUIRE(clipRayToLight(point, o, d, &t0, &t1));
        CHECK(t0 == 0.0f);
        CHECK(t1 == 7.0f);
    }
}

TEST_CASE("a planar emitter's normal faces the side asked for, its texture coordinates interpolate", "[light]") {
    Scene scene(rectangleScene(true));
    const Light& l = scene.lights()[0];
    const Vec3 p = (l.shape.p0 + l.shape.p1 + l.shape.p2) / 3.0f;
    CHECK(lightNormalFacing(l, p, Vec3(0, 0, -1)).z == Approx(-1.0f));
    CHECK(lightNormalFacing(l, p, Vec3(0, 0, 1)).z == Approx(1.0f));
    // Corners (0,0,1), (0,1,1), (2,1,1) carry uv (0,0), (0,1), (1,1): at the centroid (1/3, 2/3).
    float u = -1, v = -1;
    lightSurfaceUv(scene, l, p, &u, &v);
    CHECK(u == Approx(1.0 / 3.0).epsilon(1e-5));
    CHECK(v == Approx(2.0 / 3.0).epsilon(1e-5));
}
