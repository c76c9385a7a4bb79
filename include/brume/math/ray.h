// A ray o + t·d, t in [0, tmax). d is unit length.
#pragma once
#include <limits>
#include "brume/math/vec3.h"

namespace brume {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Ray {
    Vec3 o;
    Vec3 d;
    float tmax = kInfinity;
    Vec3 at(float t) const { return o + d * t; }
};

// Offset for spawning rays off a surface, relative to the point's magnitude so that
// scenes far from the origin (1e5 m) still escape their own surface.
inline float rayEpsilon(Vec3 p) {
    return 1e-4f * std::max(1.0f, maxComponent(vmax(p, -p)) * 1e-3f);
}

}  // namespace brume
