// Solid angle of a triangle and uniform sampling of the directions it subtends (Arvo 1995).
//
// Solid angle (Van Oosterom & Strackee 1983). With R_i = p_i − x and r_i = |R_i|,
//   tan(Ω/2) = |R0·(R1×R2)| / (r0 r1 r2 + (R0·R1) r2 + (R0·R2) r1 + (R1·R2) r0),
// taken with atan2 so that Ω runs over [0, 2π); the sign of the triple product tells from
// which side x sees the triangle (positive: x is behind the plane of p0, p1, p2 as wound, i.e.
// on the side the normal (p1−p0)×(p2−p0) points away from).
//
// Sampling (Arvo, "Stratified sampling of spherical triangles", 1995). The spherical triangle
// ABC (unit vectors) has area Ω = α + β + γ − π, α, β, γ its inner angles. ξ1 picks the
// sub-triangle A B Ĉ of area ξ1·Ω: Ĉ lies on the arc AC, at the point the closed form for
// cos(arc AĈ) gives; ξ2 then picks the direction on the arc B Ĉ so that z = cos(arc from B)
// is uniform between cos(arc BĈ) and 1. The map is an area-preserving bijection from the unit
// square, so the density is 1/Ω per steradian. Computed in double: the angle sum cancels.
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

// Ω of the triangle seen from x, both sides counted (0 when x lies in its plane).
double triangleSolidAngle(Vec3 x, Vec3 p0, Vec3 p1, Vec3 p2);

// Ω as seen from x, signed: > 0 when x sees the front face (the side (p1−p0)×(p2−p0) points
// to), < 0 from behind.
double triangleSolidAngleSigned(Vec3 x, Vec3 p0, Vec3 p1, Vec3 p2);

// A unit direction from x towards the triangle, uniform in solid angle, from u ∈ [0,1)².
// False when the spherical triangle is degenerate (x in the triangle's plane, or Ω so small
// that the construction loses every digit). *solidAngle receives the Ω the sample follows.
bool sampleSphericalTriangle(Vec3 x, Vec3 p0, Vec3 p1, Vec3 p2, Sample2 u, Vec3* wi, double* solidAngle);

}  // namespace brume
