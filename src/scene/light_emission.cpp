#include "brume/scene/light_emission.h"

#include "brume/math/frame.h"
#include "brume/sampling/warp.h"
#include "brume/scene/light.h"
#include "brume/scene/scene.h"

namespace brume {

namespace {

// Cosine of the spot's outer cone, kept in [−1, 1].
float spotCosOuter(const Light& light) { return std::min(1.0f, std::max(-1.0f, light.cosOuter)); }

// Density of a direction on the triangle's emission lobe(s): cosine about the front normal,
// or half of it about either normal when the material is double-sided.
float triangleDirPdf(float cosFront, bool doubleSided) {
    return doubleSided ? 0.5f * std::abs(cosFront) * kInvPi : cosineHemispherePdf(cosFront);
}

}  // namespace

bool sampleEmission(const Scene& scene, const Light& light, Sample2 u1, Sample2 u2, EmissionSample* out) {
    *out = EmissionSample{};
    EmissionSample s;
    switch (light.kind) {
    case LightKind::Point:
        s.p = light.position;
        s.d = sampleUniformSphere(u2);
        s.Le = light.intensity;
        s.pdfPos = 1.0f;
        s.pdfDir = uniformSpherePdf();
        s.deltaPos = true;
        break;
    case LightKind::Spot: {
        float cosOuter = spotCosOuter(light);
        if (!(cosOuter < 1.0f)) return false;  // an empty cone
        Vec3 axis = normalize(light.direction);
        Vec3 local = sampleUniformCone(u2, cosOuter);
        s.p = light.position;
        s.d = Frame(axis).toWorld(local);
        // Attenuation from the sampled cosθ itself: the world direction's dot product with
        // the axis would differ from it by rounding.
        s.Le = light.intensity * spotAttenuation(light, local.z);
        s.pdfPos = 1.0f;
        s.pdfDir = uniformConePdf(cosOuter);
        s.deltaPos = true;
        break;
    }
    case LightKind::Sphere: {
        float r = light.radius;
        if (!(r > 0)) return false;
        Vec3 n = sampleUniformSphere(u1);
        Vec3 local = sampleCosineHemisphere(u2);
        s.p = light.position + n * r;
        s.n = n;
        s.d = Frame(n).toWorld(local);
        s.Le = light.intensity / (kPi * r * r);
        s.pdfPos = 1.0f / (4.0f * kPi * r * r);
        s.pdfDir = cosineHemispherePdf(local.z);
        if (!(dot(s.d, n) > 0)) return false;  // a grazing direction tipped over by rounding
        break;
    }
    case LightKind::Triangle: {
        const EmitterTriangle& t = light.shape;
        if (!(t.area > 0)) return false;
        const Material& m = scene.material(light.mesh);
        Sample2 b = sampleUniformTriangle(u1);
        float b0 = b.u, b1 = b.v, b2 = 1.0f - b0 - b1;
        Vec3 n = t.n;
        Sample2 ud = u2;
        if (m.doubleSided) {
            // The first half of u2.u picks the front, the second the back; both halves are
            // stretched back to [0, 1) exactly (multiplying by 2 is exact in binary).
            if (ud.u < 0.5f) {
                ud.u = 2.0f * ud.u;
            } else {
                ud.u = 2.0f * ud.u - 1.0f;
                n = -n;
            }
        }
        Vec3 local = sampleCosineHemisphere(ud);
        s.p = t.p0 * b0 + t.p1 * b1 + t.p2 * b2;
        s.n = n;
        s.d = Frame(n).toWorld(local);
        s.pdfPos = 1.0f / t.area;
        s.pdfDir = cosineHemispherePdf(local.z) * (m.doubleSided ? 0.5f : 1.0f);
        // The radiance as a camera ray hitting this point would see it.
        SurfaceHit hit;
        hit.mesh = light.mesh;
        hit.triangle = light.triangle;
        hit.p = s.p;
        hit.ng = hit.ns = t.n;
        const Mesh& mesh = scene.mesh(light.mesh);
        if (!mesh.uvs.empty()) {
            const uint32_t* idx = &mesh.indices[3 * size_t(light.triangle)];
            hit.u = mesh.uvs[2 * idx[0]] * b0 + mesh.uvs[2 * idx[1]] * b1 + mesh.uvs[2 * idx[2]] * b2;
            hit.v = mesh.uvs[2 * idx[0] + 1] * b0 + mesh.uvs[2 * idx[1] + 1] * b1 + mesh.uvs[2 * idx[2] + 1] * b2;
        }
        // On the chosen side by construction, except that rounding in the frame may tip a
        // grazing direction over the edge: such a direction has density ~0 and is dropped below.
        if (!(dot(s.d, n) > 0)) return false;
        s.Le = scene.emission(hit, s.d);
        break;
    }
    case LightKind::Directional: {
        float R = scene.boundsRadius();
        Vec3 d = normalize(light.direction);
        Sample2 disk = sampleConcentricDisk(u1);
        Frame f(d);
        s.p = scene.boundsCenter() - d * R + (f.s * disk.u + f.t * disk.v) * R;
        s.d = d;
        s.Le = light.intensity;
        s.pdfPos = 1.0f / (kPi * R * R);
        s.pdfDir = 1.0f;
        s.deltaDir = true;
        break;
    }
    default:
        return false;
    }
    if (!(s.pdfPos > 0) || !(s.pdfDir > 0) || !std::isfinite(s.pdfPos) || !std::isfinite(s.pdfDir)) return false;
    *out = s;
    return true;
}

void emissionPdf(const Scene& scene, const Light& light, Vec3 p, Vec3 n, Vec3 d, float* pdfPos, float* pdfDir) {
    *pdfPos = 0;
    *pdfDir = 0;
    switch (light.kind) {
    case LightKind::Point:
        *pdfPos = 1.0f;
        *pdfDir = uniformSpherePdf();
        return;
    case LightKind::Spot: {
        float cosOuter = spotCosOuter(light);
        if (!(cosOuter < 1.0f)) return;
        *pdfPos = 1.0f;
        *pdfDir = dot(d, normalize(light.direction)) >= cosOuter ? uniformConePdf(cosOuter) : 0.0f;
        return;
    }
    case LightKind::Sphere: {
        float r = light.radius;
        if (!(r > 0)) return;
        Vec3 radial = p - light.position;
        float len = length(radial);
        *pdfPos = 1.0f / (4.0f * kPi * r * r);
        *pdfDir = len > 0 ? cosineHemispherePdf(dot(radial, d) / len) : 0.0f;
        return;
    }
    case LightKind::Triangle: {
        const EmitterTriangle& t = light.shape;
        if (!(t.area > 0)) return;
        *pdfPos = 1.0f / t.area;
        *pdfDir = triangleDirPdf(dot(t.n, d), scene.material(light.mesh).doubleSided);
        return;
    }
    case LightKind::Directional: {
        float R = scene.boundsRadius();
        *pdfPos = 1.0f / (kPi * R * R);
        *pdfDir = 1.0f;
        return;
    }
    }
}

Spectrum deltaEmission(const Light& light, Vec3 d) {
    if (light.kind == LightKind::Spot) return light.intensity * spotAttenuation(light, dot(d, light.direction));
    return light.intensity;
}

}  // namespace brume
