// A ray o + t·d, t in [tmin, tmax). d is unit length. tmin > 0 lets a walk step past a
// surface it crossed while keeping its origin (integrators/boundary_walk.h).
#pragma once
#include <limits>
#include "brume/math/vec3.h"

namespace brume {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Ray {
    Vec3 o;
    Vec3 d;
    float tmax = kInfinity;
    float tmin = 0;
    Vec3 at(float t) const { return o + d * t; }
};

// Offset for spawning rays off a surface: 0.1 mm, or 4e-7 of the point's largest coordinate
// where that is more. A float's spacing is 1.2e-7 to 2.4e-7 of its magnitude, so the offset
// is 2 to 4 spacings wide and a point 1e5 m from the origin still escapes its own surface
// (a smaller factor rounds the offset point back onto the surface and the ray hits it again).
inline float rayEpsilon(Vec3 p) {
    return 1e-4f * std::max(1.0f, maxComponent(vmax(p, -p)) * 4e-3f);
}

}  // namespace brume
