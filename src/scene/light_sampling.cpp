#include "brume/scene/light_sampling.h"

#include "brume/math/frame.h"
#include "brume/scene/scene.h"
#include "brume/scene/sphere_intersect.h"
#include "brume/sampling/warp.h"

namespace brume {

namespace {

struct TriangleGeometry {
    Vec3 p0, p1, p2, n;  // n: unit front-face normal
    float area;
};

TriangleGeometry triangleOf(const Scene& scene, const Light& light) {
    const Mesh& mesh = scene.mesh(light.mesh);
    const uint32_t* idx = &mesh.indices[3 * light.triangle];
    TriangleGeometry g{mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]], Vec3(), 0};
    Vec3 c = cross(g.p1 - g.p0, g.p2 - g.p0);
    float len = length(c);
    g.area = 0.5f * len;
    g.n = len > 0 ? c / len : Vec3(0, 0, 1);
    return g;
}

// 1 − cosθmax of the cone a sphere of radius r subtends at distance dc > r, without the
// cancellation of 1 − sqrt(1 − s²) for small s = r/dc.
float sphereConeOneMinusCos(float r, float dc) {
    float s2 = (r / dc) * (r / dc);
    return s2 / (1.0f + std::sqrt(std::max(0.0f, 1.0f - s2)));
}

}  // namespace

bool sampleLight(const Scene& scene, const Light& light, const Vec3& refIn, Sample2 u, LightSample* out) {
    const Vec3 ref = loadVec3(refIn);  // just written by the caller, float by float
    *out = LightSample{};
    switch (light.kind) {
    case LightKind::Point:
    case LightKind::Spot: {
        Vec3 d = light.position - ref;
        float dist2 = dot(d, d);
        if (!(dist2 > 0)) return false;
        float dist = std::sqrt(dist2);
        out->wi = d / dist;
        out->p = light.position;
        out->dist = dist;
        float atten = light.kind == LightKind::Spot ? spotAttenuation(light, dot(-out->wi, light.direction)) : 1.0f;
        if (atten <= 0) return false;
        out->Le = light.intensity * (atten / dist2);
        out->pdf = 1.0f;
        out->isDelta = true;
        return true;
    }
    case LightKind::Directional:
        out->wi = -light.direction;
        out->dist = kInfinity;
        out->Le = light.intensity;
        out->pdf = 1.0f;
        out->isDelta = true;
        return true;
    case LightKind::Sphere: {
        // Uniform in the cone of directions the sphere subtends; only its outside emits.
        Vec3 d = light.position - ref;
        float dc = length(d);
        if (!(dc > light.radius)) return false;
        Vec3 axis = d / dc;
        float oneMinusCos = sphereConeOneMinusCos(light.radius, dc);
        float cosTheta = 1.0f - u.u * oneMinusCos;
        float sinTheta = std::sqrt(std::max(0.0f, u.u * oneMinusCos * (2.0f - u.u * oneMinusCos)));
        float phi = 2.0f * kPi * u.v;
        Vec3 wi = Frame(axis).toWorld(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
        float t;
        if (!intersectSphere(ref, wi, light.position, light.radius, kInfinity, &t))
            t = dc * cosTheta;  // grazing ray lost to rounding: take the tangent point
        out->wi = wi;
        out->dist = t;
        out->p = ref + wi * t;
        out->Le = light.intensity / (kPi * light.radius * light.radius);
        out->pdf = 1.0f / (2.0f * kPi * oneMinusCos);
        return true;
    }
    case LightKind::Triangle: {
        TriangleGeometry g = triangleOf(scene, light);
        if (!(g.area > 0)) return false;
        Sample2 b = sampleUniformTriangle(u);
        float b0 = b.u, b1 = b.v, b2 = 1.0f - b0 - b1;
        Vec3 p = g.p0 * b0 + g.p1 * b1 + g.p2 * b2;
        Vec3 d = p - ref;
        float dist2 = dot(d, d);
        if (!(dist2 > 0)) return false;
        float dist = std::sqrt(dist2);
        Vec3 wi = d / dist;
        float cosLight = dot(g.n, -wi);
        const Material& m = scene.material(light.mesh);
        if (cosLight == 0 || (!m.doubleSided && cosLight < 0)) return false;
        // Area density 1/A becomes solid-angle density dist²/(A·|cosθ_light|).
        out->pdf = dist2 / (g.area * std::abs(cosLight));
        out->wi = wi;
        out->p = p;
        out->dist = dist;
        SurfaceHit hit;
        hit.mesh = light.mesh;
        hit.triangle = light.triangle;
        hit.p = p;
        hit.ng = hit.ns = g.n;
        const Mesh& mesh = scene.mesh(light.mesh);
        if (!mesh.uvs.empty()) {
            const uint32_t* idx = &mesh.indices[3 * light.triangle];
            hit.u = mesh.uvs[2 * idx[0]] * b0 + mesh.uvs[2 * idx[1]] * b1 + mesh.uvs[2 * idx[2]] * b2;
            hit.v = mesh.uvs[2 * idx[0] + 1] * b0 + mesh.uvs[2 * idx[1] + 1] * b1 + mesh.uvs[2 * idx[2] + 1] * b2;
        }
        out->Le = scene.emission(hit, -wi);
        return out->pdf > 0 && std::isfinite(out->pdf);
    }
    }
    return false;
}

float lightPdf(const Scene& scene, const Light& light, Vec3 ref, Vec3 p, Vec3 n) {
    switch (light.kind) {
    case LightKind::Sphere: {
        float dc = length(light.position - ref);
        if (!(dc > light.radius)) return 0.0f;
        return 1.0f / (2.0f * kPi * sphereConeOneMinusCos(light.radius, dc));
    }
    case LightKind::Triangle: {
        TriangleGeometry g = triangleOf(scene, light);
        Vec3 d = p - ref;
        float dist2 = dot(d, d);
        float cosLight = -dot(g.n, d) / std::sqrt(dist2);  // dot(n, −wi), as in sampleLight
        const Material& m = scene.material(light.mesh);
        if (!(g.area > 0) || cosLight == 0 || (!m.doubleSided && cosLight < 0)) return 0.0f;
        return dist2 / (g.area * std::abs(cosLight));
    }
    default:
        return 0.0f;  // delta lights are never hit
    }
}

float lightPower(const Scene& scene, const Light& light) {
    switch (light.kind) {
    case LightKind::Point:
    case LightKind::Sphere:
        return 4.0f * kPi * average(light.intensity);
    case LightKind::Spot:
        // Solid angle of the cone halfway between the inner and outer edge.
        return 2.0f * kPi * (1.0f - 0.5f * (light.cosInner + light.cosOuter)) * average(light.intensity);
    case LightKind::Directional:
        return kPi * scene.boundsRadius() * scene.boundsRadius() * average(light.intensity);
    case LightKind::Triangle: {
        const Material& m = scene.material(light.mesh);
        Spectrum L = m.emission;
        if (m.emissiveTexture >= 0) L *= scene.desc().textures[m.emissiveTexture].average();
        return triangleOf(scene, light).area * kPi * average(L) * (m.doubleSided ? 2.0f : 1.0f);
    }
    }
    return 0.0f;
}

}  // namespace brume
