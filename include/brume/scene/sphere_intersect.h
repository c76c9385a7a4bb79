// Ray–sphere intersection for analytic sphere lights.
#pragma once
#include "brume/math/vec3.h"

namespace brume {

// Nearest t in (max(tmin, ε), tmax) where o + t·d (d unit) meets the sphere; from inside, the exit.
// Uses the numerically stable form (the discriminant from the closest-approach distance).
inline bool intersectSphere(Vec3 o, Vec3 d, Vec3 c, float r, float tmax, float* tHit, float tmin = 0) {
    Vec3 oc = o - c;
    float b = dot(oc, d);
    Vec3 closest = oc - d * b;  // perpendicular offset of the line from the centre
    float disc = r * r - dot(closest, closest);
    if (disc < 0) return false;
    float h = std::sqrt(disc);
    float t0 = -b - h, t1 = -b + h;
    float eps = std::max(tmin, 1e-5f * std::max(1.0f, r));
    float t = t0 > eps ? t0 : t1;
    if (t <= eps || t >= tmax) return false;
    *tHit = t;
    return true;
}

}  // namespace brume
