// Uniform sampling of the solid angle a rectangle subtends (Ureña, Fajardo and King, "An
// area-preserving parametrization for spherical rectangles", EGSR 2013).
//
// In the rectangle's frame (x̂, ŷ along its edges, ẑ their normal turned away from the
// reference point o), its corners seen from o are (x0|x1, y0|y1, z0), z0 < 0. The four great
// circles through neighbouring corners have unit normals n0..n3 and inner angles g0..g3; the
// solid angle is S = g0 + g1 + g2 + g3 − 2π. ξ1 picks the sub-rectangle [x0, xu] of solid angle
// ξ1·S, which has a closed form for xu; ξ2 then picks y on the segment at xu so that the
// height h = y/√(xu² + z0² + y²) is uniform between its values at y0 and y1. The map is an
// area-preserving bijection from the unit square: density 1/S per steradian.
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

struct SphericalRectangle {
    Vec3 o, x, y, z;                 // reference point; frame (z away from o's side)
    double x0, x1, y0, y1, z0;       // extents in that frame, z0 < 0
    double b0, b1, k, solidAngle;    // Ureña et al.'s constants; S
};

// The rectangle with corner s and perpendicular edges ex, ey, seen from o. False if o lies in
// its plane or the rectangle is degenerate.
bool makeSphericalRectangle(Vec3 o, Vec3 s, Vec3 ex, Vec3 ey, SphericalRectangle* out);

// The point of the rectangle for u ∈ [0,1)², uniform in solid angle from o.
Vec3 sampleSphericalRectangle(const SphericalRectangle& r, Sample2 u);

}  // namespace brume
