// Surface scattering at one hit, built from its material. Directions are world-space unit
// vectors pointing away from the surface: wo towards the previous vertex (the camera side of
// a camera path), wi towards the next. eval() returns f(wo, wi)·|cos θi|.
#pragma once
#include "brume/math/frame.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/material.h"

namespace brume {

// Camera subpaths carry radiance, light subpaths importance; they differ at refraction
// (radiance is scaled by 1/η² crossing an interface, importance is not) and with shading
// normals (the adjoint BSDF; see shadingNormalCorrection).
enum class TransportMode : unsigned char { Radiance, Importance };

struct BsdfSample {
    Vec3 wi;
    Spectrum weight{0.0f};  // f·|cos θi| / pdf
    float pdf = 0;          // solid angle; for a specular lobe, its discrete probability
    bool specular = false;
    bool transmitted = false;  // wi is on the other side of the surface from wo
};

class Bsdf {
public:
    // ng: geometric normal (front side), ns: shading normal on the same side.
    Bsdf(const Material& material, Spectrum baseColor, Vec3 ng, Vec3 ns);

    bool isSpecular() const { return kind_ == MaterialKind::Dielectric; }
    // What a denoiser takes as the surface's colour (integrators/denoise_features.h): the base
    // colour, or 1 for a smooth dielectric (glass), whose colour is what lies behind it.
    Spectrum albedo() const { return isSpecular() ? Spectrum(1.0f) : baseColor_; }
    Spectrum eval(Vec3 wo, Vec3 wi) const;
    float pdf(Vec3 wo, Vec3 wi) const;
    // uLobe picks the lobe (diffuse vs glossy, reflect vs refract), u the direction.
    bool sample(Vec3 wo, float uLobe, Sample2 u, BsdfSample* out,
                TransportMode mode = TransportMode::Radiance) const;

private:
    Spectrum evalLocal(Vec3 wo, Vec3 wi) const;
    float pdfLocal(Vec3 wo, Vec3 wi) const;

    MaterialKind kind_;
    Spectrum baseColor_;
    float metallic_, alpha_, ior_;
    Vec3 ng_;
    Frame frame_;  // around the shading normal
};

// For importance transport with shading normals (Veach 1997, §5.3): the adjoint BSDF times
// |wi·ns| equals f·|wi·ns| times |wo·ns|·|wi·ng| / (|wo·ng|·|wi·ns|); this returns that factor.
inline float shadingNormalCorrection(Vec3 wo, Vec3 wi, Vec3 ng, Vec3 ns) {
    float denom = std::abs(dot(wo, ng)) * std::abs(dot(wi, ns));
    return denom > 0 ? std::abs(dot(wo, ns)) * std::abs(dot(wi, ng)) / denom : 0.0f;
}

// Fresnel reflectance of a smooth dielectric; cosI on the side of relative index eta.
float fresnelDielectric(float cosI, float eta);

}  // namespace brume
