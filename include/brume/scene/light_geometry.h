// Where a light is, as distance sampling along a ray needs it: the point equi-angular
// sampling aims at, the part of a ray the light can reach, and texture coordinates on an
// emitter. With light_sampling.h (points on a light and their densities) and
// light_emission.h (emission and its densities), the operations integrators ask of a light
// instead of switching on its kind (docs/architecture.md, "A light").
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/light.h"

namespace brume {

class Scene;

// The point equi-angular sampling aims at: a point or spot light's position, a sphere
// light's centre, a planar emitter's point uniform by area from u (light point first, as in
// the talk). False for directional lights, which have none.
bool lightAnchor(const Light& light, Sample2 u, Vec3* anchor);

// Narrows [*t0, *t1) of the ray o + t·d to where the light can reach: a spot light's cone, a
// one-sided emitter's front half-space; other lights keep all of it. False if nothing remains.
// Clipping removes only points whose contribution is zero.
bool clipRayToLight(const Light& light, Vec3 o, Vec3 d, float* t0, float* t1);

// Clip [t0, t1] to the points of the ray o + t·d inside a spot light's outer cone
// (a superset at worst). False if nothing remains.
bool clipToSpotCone(const Light& spot, Vec3 o, Vec3 d, float* t0, float* t1);

// Texture coordinates of point p on a planar emitter (barycentrics by areas); u and v are
// left as they are when its mesh has none, or for other lights.
void lightSurfaceUv(const Scene& scene, const Light& light, Vec3 p, float* u, float* v);

// The unit normal at a point p on a light with a surface, on the side facing `towards`
// (towards·n ≥ 0); zero for lights without one.
Vec3 lightNormalFacing(const Light& light, Vec3 p, Vec3 towards);

}  // namespace brume
