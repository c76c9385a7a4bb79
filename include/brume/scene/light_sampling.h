// Sampling a point on a light as seen from a reference point, and the density of the same
// point when it is reached by other means (BSDF or phase sampling). Densities are per unit
// solid angle at the reference point; light selection is not included.
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

class Scene;
struct Light;

struct LightSample {
    Vec3 p;               // point on the light (unused for directional)
    Vec3 wi;              // unit direction from the reference point towards the light
    float dist = 0;       // distance to p; +∞ for directional lights
    Spectrum Le{0.0f};    // area/sphere: emitted radiance towards the reference point;
                          // point/spot: I·attenuation/dist²; directional: E
    float pdf = 0;        // solid-angle density (area/sphere); 1 for delta lights
    bool isDelta = false; // point, spot, directional
    int light = -1;       // the light p lies on: the one sampled, or the other half of its
                          // rectangle (Light::partner)
};

// The index of the light a sample of light `picked` landed on.
inline int landedLight(int picked, const LightSample& ls) { return ls.light >= 0 ? ls.light : picked; }

// Returns false (and leaves pdf = 0) when the light cannot reach `ref` or the sample failed.
// An emissive triangle is sampled uniformly in the solid angle it subtends at `ref`
// (spherical_triangle.h) when Scene::emitterSampling() says so and that solid angle lies in
// [kMinSphericalSolidAngle, kMaxSphericalSolidAngle]; by area otherwise. The switch depends
// on the geometry alone, so lightPdf makes the same choice.
bool sampleLight(const Scene& scene, const Light& light, const Vec3& ref, Sample2 u, LightSample* out);

// Half of a rectangle (Light::partner) sampled by solid angle is sampled as the whole
// rectangle (spherical_rectangle.h), whichever half was picked: the point may lie on the other
// half (LightSample::light), and pdf is P(rectangle)/(P(light)·Ω), so that P(light)·pdf is the
// rectangle's density whichever half the caller picked.
//
// Solid-angle density with which sampleLight would pick the light point `p` (with unit
// geometric normal `n`, front side for triangles; ignored for spheres) from `ref`.
float lightPdf(const Scene& scene, const Light& light, Vec3 ref, Vec3 p, Vec3 n);

// The same with a triangle's point uniform by area whatever the scene says: the light
// point that equi-angular sampling aims at before the distance is known (light point first).
// Other lights: as sampleLight.
bool sampleLightByArea(const Scene& scene, const Light& light, const Vec3& ref, Sample2 u, LightSample* out);
float lightPdfByArea(const Scene& scene, const Light& light, Vec3 ref, Vec3 p, Vec3 n);

// Solid angles below which the spherical construction loses its digits (a tiny or far
// emitter, where area sampling is as good) and above which it is ill-conditioned (the
// reference point on the emitter's plane, close in): area sampling there (pbrt-v4's limits).
constexpr double kMinSphericalSolidAngle = 3e-4, kMaxSphericalSolidAngle = 6.22;

// Whether sampleLight samples `light` from `ref` by solid angle (not when its area over the
// squared distance to its centre is below kMinSphericalSolidAngle/4: small or far, decided
// without the solid angle), and *omega that solid angle
// (of the whole rectangle for a half of one; front side only for one-sided emitters: 0 from
// behind).
bool samplesBySolidAngle(const Scene& scene, const Light& light, Vec3 ref, double* omega);

// Total emitted power (grey average), used to pick lights in proportion to power.
float lightPower(const Scene& scene, const Light& light);

}  // namespace brume
