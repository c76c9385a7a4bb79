// Sampling light emission: the first vertex of a light subpath (a point on a light) and the
// direction in which it leaves, with both densities from one call (as in SmallVCM), and the
// densities of a given origin and direction for multiple importance sampling.
//
// Conventions. pdfPos is a density per unit area of the origin, pdfDir a density per
// steradian of the direction given the origin; neither includes the probability of picking
// the light. Delta parts carry density 1 and are flagged (deltaPos: point and spot lights;
// deltaDir: directional lights), so that Le·|cos|/(pdfPos·pdfDir) is always the weight of the
// sample (|cos| = 1 where there is no surface): its expectation is the light's total power.
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

class Scene;
struct Light;

struct EmissionSample {
    Vec3 p;            // origin on the light; directional: on a disk outside the scene's bounds
    Vec3 n;            // area and sphere lights: unit surface normal at p on the emitting side
                       // (for a double-sided triangle the side d leaves from); zero otherwise
    Vec3 d;            // unit emission direction
    Spectrum Le{0.0f}; // area/sphere: radiance leaving p along d; point/spot: intensity
                       // (times the cone attenuation); directional: irradiance E
    float pdfPos = 0;  // area density of p; 1 for point and spot lights (delta position)
    float pdfDir = 0;  // solid-angle density of d given p; 1 for directional lights (delta)
    bool deltaPos = false, deltaDir = false;
};

// Samples an origin (from u1) and a direction (from u2) of emission from `light`:
//   point        p = position, d uniform on the sphere;
//   spot         p = position, d uniform in the outer cone, Le = I·spotAttenuation;
//   sphere       p uniform on the surface, d cosine-distributed about the outward normal;
//   triangle     p uniform on the triangle, d cosine-distributed about the front normal; a
//                double-sided material first picks either side with probability 1/2 (the
//                1/2 is part of pdfDir); Le comes from Scene::emission (emissive texture);
//   directional  d = light direction, p uniform on the disk of radius R = boundsRadius()
//                centred at boundsCenter() − d·R, perpendicular to d.
// Returns false, leaving *out with zero densities, when nothing can be emitted (a degenerate
// light, or a direction with zero density lost to rounding). Le may be black on a success
// (the rim of a spot cone, a black texel): the sample is valid, it merely carries nothing.
bool sampleEmission(const Scene& scene, const Light& light, Sample2 u1, Sample2 u2, EmissionSample* out);

// Densities with which sampleEmission would produce the origin p and the unit direction d:
// the same values (and the same 1 for delta parts) that the sample would carry; 0 where the
// direction cannot be emitted (behind a one-sided triangle, outside a spot cone, into a
// sphere light). p is assumed to lie on the light; the geometry (normal, emitting side) is
// taken from the light itself, so `n` (the surface normal at p, as a caller has it) is not
// needed and is ignored.
void emissionPdf(const Scene& scene, const Light& light, Vec3 p, Vec3 n, Vec3 d, float* pdfPos, float* pdfDir);

// What a delta light (Light::isDelta) emits in direction d: a point light's intensity, a spot
// light's times its cone attenuation, a directional light's irradiance. Emission from a light
// with a surface is Scene::emission at the point.
Spectrum deltaEmission(const Light& light, Vec3 d);

}  // namespace brume
