// Orthonormal frame around a unit normal (Duff et al. 2017, branchless).
#pragma once
#include "brume/math/vec3.h"

namespace brume {

struct Frame {
    Vec3 s, t, n;
    Frame() : s(1, 0, 0), t(0, 1, 0), n(0, 0, 1) {}
    explicit Frame(Vec3 normal) : n(normal) {
        float sign = std::copysign(1.0f, n.z);
        float a = -1.0f / (sign + n.z);
        float b = n.x * n.y * a;
        s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        t = Vec3(b, sign + n.y * n.y * a, -n.y);
    }
    Vec3 toLocal(Vec3 v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 toWorld(Vec3 v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace brume
