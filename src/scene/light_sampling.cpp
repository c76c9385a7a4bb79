#include "brume/scene/light_sampling.h"

#include "brume/math/frame.h"
#include "brume/scene/scene.h"
#include "brume/scene/sphere_intersect.h"
#include "brume/sampling/spherical_rectangle.h"
#include "brume/sampling/spherical_triangle.h"
#include "brume/sampling/warp.h"

namespace brume {

namespace {

// 1 − cosθmax of the cone a sphere of radius r subtends at distance dc > r, without the
// cancellation of 1 − sqrt(1 − s²) for small s = r/dc.
float sphereConeOneMinusCos(float r, float dc) {
    float s2 = (r / dc) * (r / dc);
    return s2 / (1.0f + std::sqrt(std::max(0.0f, 1.0f - s2)));
}

// The light sample at point p of the triangle (barycentrics b0, b1), reached along unit wi
// from ref at distance dist: its emitted radiance (emissive texture at p's uv).
void finishTriangleSample(const Scene& scene, const Light& light, const EmitterTriangle& g, Vec3 p, float b0,
                          float b1, Vec3 wi, float dist, LightSample* out) {
    out->wi = wi;
    out->p = p;
    out->dist = dist;
    out->light = scene.triangleLight(light.mesh, light.triangle);
    SurfaceHit hit;
    hit.mesh = light.mesh;
    hit.triangle = light.triangle;
    hit.p = p;
    hit.ng = hit.ns = g.n;
    const Mesh& mesh = scene.mesh(light.mesh);
    if (!mesh.uvs.empty()) {
        const uint32_t* idx = &mesh.indices[3 * light.triangle];
        const float b2 = 1.0f - b0 - b1;
        hit.u = mesh.uvs[2 * idx[0]] * b0 + mesh.uvs[2 * idx[1]] * b1 + mesh.uvs[2 * idx[2]] * b2;
        hit.v = mesh.uvs[2 * idx[0] + 1] * b0 + mesh.uvs[2 * idx[1] + 1] * b1 + mesh.uvs[2 * idx[2] + 1] * b2;
    }
    out->Le = scene.emission(hit, -wi);
}

// The barycentrics (b0, b1) of p, on the triangle's plane; true if p lies in the triangle.
bool barycentricInside(const EmitterTriangle& g, Vec3 p, float* b0, float* b1) {
    const float inv = 1.0f / (2.0f * g.area);
    *b0 = dot(cross(g.p1 - p, g.p2 - p), g.n) * inv;
    *b1 = dot(cross(g.p2 - p, g.p0 - p), g.n) * inv;
    const float eps = -1e-5f;
    return *b0 >= eps && *b1 >= eps && 1.0f - *b0 - *b1 >= eps;
}

// P(rectangle)/(P(light)·Ω): the solid-angle density of a rectangle's point per pick of the half `light`.
float rectanglePdf(const Scene& scene, const Light& light, double omega) {
    const Distribution1D& d = scene.lightDistribution();
    const int li = scene.triangleLight(light.mesh, light.triangle), pl = scene.triangleLight(light.mesh, light.partner);
    const double self = d.pmf(li);
    if (!(self > 0)) return 0.0f;
    return float((self + double(d.pmf(pl))) / (self * omega));
}

// A point on an emissive triangle seen from ref: uniform in the subtended solid angle
// (density 1/Ω) or uniform by area (density 1/A turned into dist²/(A·|cosθ_light|)).
// omega > 0: by solid angle, the triangle (or its rectangle) subtending omega at ref; 0: by area.
bool sampleTriangle(const Scene& scene, const Light& light, Vec3 ref, Sample2 u, double omega, LightSample* out) {
    const EmitterTriangle& g = light.shape;
    if (!(g.area > 0)) return false;
    const bool doubleSided = scene.material(light.mesh).doubleSided;
    if (omega > 0 && light.partner >= 0) {
        // The whole rectangle by solid angle; the half the point lies on gives its radiance.
        SphericalRectangle rect;
        if (!makeSphericalRectangle(ref, light.rectCorner, light.rectEdgeU, light.rectEdgeV, &rect)) return false;
        const Vec3 p = sampleSphericalRectangle(rect, u);
        const Light* half = &light;
        float b0, b1;
        if (!barycentricInside(g, p, &b0, &b1)) {
            half = &scene.partnerOf(light);
            barycentricInside(half->shape, p, &b0, &b1);
        }
        const EmitterTriangle& h = half->shape;
        const Vec3 d = p - ref;
        const float dist = length(d);
        if (!(dist > 0)) return false;
        const Vec3 wi = d / dist;
        const float cosLight = dot(h.n, -wi);
        if (cosLight == 0 || (!doubleSided && cosLight < 0)) return false;
        out->pdf = rectanglePdf(scene, light, omega);
        finishTriangleSample(scene, *half, h, p, std::max(0.0f, b0), std::max(0.0f, b1), wi, dist, out);
        return out->pdf > 0 && std::isfinite(out->pdf);
    }
    if (omega > 0) {
        Vec3 wi;
        double arvoOmega;
        if (!sampleSphericalTriangle(ref, g.p0, g.p1, g.p2, u, &wi, &arvoOmega)) return false;
        // Where wi meets the triangle's plane: n·(ref + wi·dist − p0) = 0.
        const float cosLight = dot(g.n, -wi);
        if (cosLight == 0 || (!doubleSided && cosLight < 0)) return false;
        const float dist = dot(g.n, g.p0 - ref) / dot(g.n, wi);
        if (!(dist > 0) || !std::isfinite(dist)) return false;
        const Vec3 p = ref + wi * dist;
        float b0, b1;
        barycentricInside(g, p, &b0, &b1);
        out->pdf = float(1.0 / omega);
        finishTriangleSample(scene, light, g, p, std::max(0.0f, b0), std::max(0.0f, b1), wi, dist, out);
        return out->pdf > 0 && std::isfinite(out->pdf);
    }
    Sample2 b = sampleUniformTriangle(u);
    float b0 = b.u, b1 = b.v, b2 = 1.0f - b0 - b1;
    Vec3 p = g.p0 * b0 + g.p1 * b1 + g.p2 * b2;
    Vec3 d = p - ref;
    float dist2 = dot(d, d);
    if (!(dist2 > 0)) return false;
    float dist = std::sqrt(dist2);
    Vec3 wi = d / dist;
    float cosLight = dot(g.n, -wi);
    if (cosLight == 0 || (!doubleSided && cosLight < 0)) return false;
    // Area density 1/A becomes solid-angle density dist²/(A·|cosθ_light|).
    out->pdf = dist2 / (g.area * std::abs(cosLight));
    finishTriangleSample(scene, light, g, p, b0, b1, wi, dist, out);
    return out->pdf > 0 && std::isfinite(out->pdf);
}

float trianglePdf(const Scene& scene, const Light& light, Vec3 ref, Vec3 p, bool bySolidAngle, double omega) {
    const EmitterTriangle& g = light.shape;
    Vec3 d = p - ref;
    float dist2 = dot(d, d);
    float cosLight = -dot(g.n, d) / std::sqrt(dist2);  // dot(n, −wi), as in sampleLight
    const Material& m = scene.material(light.mesh);
    if (!(g.area > 0) || cosLight == 0 || (!m.doubleSided && cosLight < 0)) return 0.0f;
    if (bySolidAngle) return light.partner >= 0 ? rectanglePdf(scene, light, omega) : float(1.0 / omega);
    return dist2 / (g.area * std::abs(cosLight));
}

}  // namespace

bool samplesBySolidAngle(const Scene& scene, const Light& light, Vec3 ref, double* omega) {
    if (light.kind != LightKind::Triangle || scene.emitterSampling() != EmitterSampling::SolidAngle) return false;
    // A cheap first test for small or far emitters, part of the rule: area over squared
    // distance to the centre well below the lower limit.
    const Vec3 toCentre = light.emitterCentre - ref;
    if (light.emitterArea < 0.25f * float(kMinSphericalSolidAngle) * dot(toCentre, toCentre)) {
        if (omega) *omega = 0;
        return false;
    }
    const EmitterTriangle& g = light.shape;
    double o = triangleSolidAngleSigned(ref, g.p0, g.p1, g.p2);
    if (light.partner >= 0) {
        // The rectangle's, summed in the order of the halves' numbers: the same bits from either.
        const EmitterTriangle& h = scene.partnerOf(light).shape;
        const double other = triangleSolidAngleSigned(ref, h.p0, h.p1, h.p2);
        o = light.triangle < light.partner ? o + other : other + o;
    }
    o = scene.material(light.mesh).doubleSided ? std::abs(o) : std::max(0.0, o);
    if (omega) *omega = o;
    return o >= kMinSphericalSolidAngle && o <= kMaxSphericalSolidAngle;
}

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
        double omega = 0;
        const bool bySolidAngle = samplesBySolidAngle(scene, light, ref, &omega);
        return sampleTriangle(scene, light, ref, u, bySolidAngle ? omega : 0.0, out);
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
        double omega = 0;
        const bool bySolidAngle = samplesBySolidAngle(scene, light, ref, &omega);
        return trianglePdf(scene, light, ref, p, bySolidAngle, omega);
    }
    default:
        return 0.0f;  // delta lights are never hit
    }
}

bool sampleLightByArea(const Scene& scene, const Light& light, const Vec3& refIn, Sample2 u, LightSample* out) {
    if (light.kind != LightKind::Triangle) return sampleLight(scene, light, refIn, u, out);
    *out = LightSample{};
    return sampleTriangle(scene, light, loadVec3(refIn), u, 0.0, out);
}

float lightPdfByArea(const Scene& scene, const Light& light, Vec3 ref, Vec3 p, Vec3 n) {
    if (light.kind != LightKind::Triangle) return lightPdf(scene, light, ref, p, n);
    return trianglePdf(scene, light, ref, p, false, 0.0);
}

float lightPower(const Scene& scene, const Light& light) {
    switch (light.kind) {
    case LightKind::Point:
    case LightKind::Sphere:
        return 4.0f * kPi * average(light.intensity);
    case LightKind::Spot:
        // Cycles' profile: ∫ cosθ dω over the cone, 2π·∫ c dc = π(1 − cos²θo) (the blend band
        // left out). glTF's: the solid angle of the cone halfway between its inner and outer edge.
        if (light.cyclesSpot) return kPi * (1.0f - light.cosOuter * light.cosOuter) * average(light.intensity);
        return 2.0f * kPi * (1.0f - 0.5f * (light.cosInner + light.cosOuter)) * average(light.intensity);
    case LightKind::Directional:
        return kPi * scene.boundsRadius() * scene.boundsRadius() * average(light.intensity);
    case LightKind::Triangle: {
        const Material& m = scene.material(light.mesh);
        Spectrum L = m.emission;
        if (m.emissiveTexture >= 0) L *= scene.desc().textures[m.emissiveTexture].average();
        return light.shape.area * kPi * average(L) * (m.doubleSided ? 2.0f : 1.0f);
    }
    }
    return 0.0f;
}

}  // namespace brume
