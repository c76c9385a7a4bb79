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
};

// Returns false (and leaves pdf = 0) when the light cannot reach `ref` or the sample failed.
bool sampleLight(const Scene& scene, const Light& light, const Vec3& ref, Sample2 u, LightSample* out);

// Solid-angle density with which sampleLight would pick the light point `p` (with unit
// geometric normal `n`, front side for triangles; ignored for spheres) from `ref`.
float lightPdf(const Scene& scene, const Light& light, Vec3 ref, Vec3 p, Vec3 n);

// Total emitted power (grey average), used to pick lights in proportion to power.
float lightPower(const Scene& scene, const Light& light);

}  // namespace brume
