#include "brume/scene/bsdf.h"

#include "brume/sampling/ggx.h"
#include "brume/sampling/warp.h"

namespace brume {

float fresnelDielectric(float cosI, float eta) {
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return 1.0f;  // total internal reflection
    float cosT = std::sqrt(1.0f - sin2T);
    float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5f * (rs * rs + rp * rp);
}

Bsdf::Bsdf(const Material& m, Spectrum baseColor, Vec3 ng, Vec3 ns)
    : kind_(m.kind),
      baseColor_(baseColor),
      metallic_(m.kind == MaterialKind::Glossy ? std::min(1.0f, std::max(0.0f, m.metallic)) : 0.0f),
      alpha_(std::max(1e-3f, m.roughness * m.roughness)),
      ior_(m.ior),
      ng_(ng),
      frame_(ns) {}

// Opaque materials reflect on whichever side wo is (glTF surfaces are two-sided for
// reflection): the local frame is flipped so that wo.z > 0.
Spectrum Bsdf::eval(Vec3 wo, Vec3 wi) const {
    if (isSpecular()) return Spectrum(0.0f);
    float side = dot(wo, ng_) >= 0 ? 1.0f : -1.0f;
    if (dot(wi, ng_) * side <= 0) return Spectrum(0.0f);  // opaque: no transmission
    Vec3 lo = frame_.toLocal(wo) * side, li = frame_.toLocal(wi) * side;
    if (lo.z <= 0 || li.z <= 0) return Spectrum(0.0f);
    return evalLocal(lo, li) * li.z;
}

float Bsdf::pdf(Vec3 wo, Vec3 wi) const {
    if (isSpecular()) return 0.0f;
    float side = dot(wo, ng_) >= 0 ? 1.0f : -1.0f;
    if (dot(wi, ng_) * side <= 0) return 0.0f;
    Vec3 lo = frame_.toLocal(wo) * side, li = frame_.toLocal(wi) * side;
    if (lo.z <= 0 || li.z <= 0) return 0.0f;
    return pdfLocal(lo, li);
}

// f = (1−m)·ρ/π + m·F(wo·h)·D(h)·G1(wo)·G1(wi) / (4 cosθo cosθi), F Schlick with F0 = ρ.
Spectrum Bsdf::evalLocal(Vec3 wo, Vec3 wi) const {
    Spectrum f = baseColor_ * ((1.0f - metallic_) * kInvPi);
    if (metallic_ > 0) {
        Vec3 h = normalize(wo + wi);
        float c = 1.0f - std::max(0.0f, dot(wo, h));
        float c5 = c * c * c * c * c;
        Spectrum F = baseColor_ + (Spectrum(1.0f) - baseColor_) * c5;
        float spec = ggxD(h, alpha_) * ggxG1(wo, alpha_) * ggxG1(wi, alpha_) / (4.0f * wo.z * wi.z);
        f += F * (metallic_ * spec);
    }
    return f;
}

// Lobe mixture: cosine with probability 1−m, GGX normals with probability m.
// A half-vector density D(h)cosθh becomes D(h)cosθh / (4 |wo·h|) over wi.
float Bsdf::pdfLocal(Vec3 wo, Vec3 wi) const {
    float p = (1.0f - metallic_) * cosineHemispherePdf(wi.z);
    if (metallic_ > 0) {
        Vec3 h = normalize(wo + wi);
        float woh = dot(wo, h);
        if (woh > 0) p += metallic_ * ggxNormalPdf(h, alpha_) / (4.0f * woh);
    }
    return p;
}

bool Bsdf::sample(Vec3 wo, float uLobe, Sample2 u, BsdfSample* out, TransportMode mode) const {
    float side = dot(wo, ng_) >= 0 ? 1.0f : -1.0f;
    if (kind_ == MaterialKind::Dielectric) {
        // Front side is outside; eta = ηt/ηi along the direction of travel from wo's side.
        Vec3 n = frame_.n * side;
        float cosI = dot(wo, n);
        if (cosI <= 0) return false;
        float eta = side > 0 ? ior_ : 1.0f / ior_;
        float F = fresnelDielectric(cosI, eta);
        out->specular = true;
        if (uLobe < F) {
            out->wi = reflect(wo, n);
            out->weight = Spectrum(1.0f);  // F / F
            out->pdf = F;
            out->transmitted = false;
        } else {
            float sin2T = (1.0f - cosI * cosI) / (eta * eta);
            float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
            out->wi = normalize(-wo / eta + n * (cosI / eta - cosT));
            // Radiance is compressed by (ηt/ηi)² crossing into the denser side; importance is not.
            out->weight = Spectrum(mode == TransportMode::Radiance ? 1.0f / (eta * eta) : 1.0f);
            out->pdf = 1.0f - F;
            out->transmitted = true;
        }
        return dot(out->wi, ng_) * side * (out->transmitted ? -1.0f : 1.0f) > 0;
    }
    Vec3 lo = frame_.toLocal(wo) * side;
    if (lo.z <= 0) return false;
    Vec3 li;
    if (uLobe < metallic_) {
        Vec3 h = sampleGgxNormal(alpha_, u);
        li = reflect(lo, h);
    } else {
        li = sampleCosineHemisphere(u);
    }
    if (li.z <= 0) return false;
    Vec3 wi = frame_.toWorld(li * side);
    // Density and value through the same world-space path as pdf() and eval(), so that MIS
    // sees identical numbers for a direction however it was found (a sharp GGX lobe turns
    // float round-off in the frame change into per-mille differences otherwise).
    float pdf = this->pdf(wo, wi);
    if (!(pdf > 0)) return false;
    out->wi = wi;
    out->pdf = pdf;
    out->weight = eval(wo, wi) / pdf;
    out->specular = false;
    out->transmitted = false;
    return true;
}

}  // namespace brume
