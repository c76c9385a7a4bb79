#include "brume/scene/light_geometry.h"

#include <cmath>

#include "brume/sampling/warp.h"
#include "brume/scene/scene.h"

namespace brume {

bool lightAnchor(const Light& light, Sample2 u, Vec3* anchor) {
    if (light.atInfinity()) return false;
    if (!light.isPlanar()) {
        *anchor = light.position;
        return true;
    }
    const EmitterTriangle& t = light.shape;
    const Sample2 b = sampleUniformTriangle(u);
    *anchor = t.p0 * b.u + t.p1 * b.v + t.p2 * (1.0f - b.u - b.v);
    return true;
}

// Points x = o + t·d in the spot's (convex, outer angle ≤ π/2) cone satisfy
//   q(t) = (w·a + t·d·a)² − cos²θo·|w + t·d|² ≥ 0  and  w·a + t·d·a ≥ 0,
// with w = o − apex, a the axis. q is quadratic in t: A t² + B t + C.
bool clipToSpotCone(const Light& spot, Vec3 o, Vec3 d, float* t0, float* t1) {
    double lo = *t0, hi = *t1;
    Vec3 w = o - spot.position;
    double dv = dot(d, spot.direction), wv = dot(w, spot.direction);
    double c2 = double(spot.cosOuter) * spot.cosOuter;
    // Forward nappe: wv + t·dv ≥ 0.
    if (std::abs(dv) < 1e-12) {
        if (wv < 0) return false;
    } else if (dv > 0) {
        lo = std::max(lo, -wv / dv);
    } else {
        hi = std::min(hi, -wv / dv);
    }
    if (!(lo < hi)) return false;
    double A = dv * dv - c2, B = 2.0 * (dv * wv - c2 * double(dot(d, w))), C = wv * wv - c2 * double(dot(w, w));
    // Solution set of q ≥ 0 as up to two intervals; the cone ∩ line is one interval, so
    // the hull of the pieces that meet [lo, hi] is exact (and a superset if rounding splits it).
    double pieces[2][2];
    int n = 0;
    const double inf = INFINITY;
    if (std::abs(A) < 1e-12) {
        if (std::abs(B) < 1e-12) {
            if (C < 0) return false;
            pieces[n][0] = -inf, pieces[n][1] = inf, ++n;
        } else if (B > 0) {
            pieces[n][0] = -C / B, pieces[n][1] = inf, ++n;
        } else {
            pieces[n][0] = -inf, pieces[n][1] = -C / B, ++n;
        }
    } else {
        double disc = B * B - 4 * A * C;
        if (disc < 0) {
            if (A < 0) return false;
            pieces[n][0] = -inf, pieces[n][1] = inf, ++n;
        } else {
            double s = std::sqrt(disc);
            double q = -0.5 * (B + std::copysign(s, B));
            double r1 = q / A, r2 = q != 0 ? C / q : r1;
            if (r1 > r2) std::swap(r1, r2);
            if (A < 0) {
                pieces[n][0] = r1, pieces[n][1] = r2, ++n;
            } else {
                pieces[n][0] = -inf, pieces[n][1] = r1, ++n;
                pieces[n][0] = r2, pieces[n][1] = inf, ++n;
            }
        }
    }
    double outLo = inf, outHi = -inf;
    for (int i = 0; i < n; ++i) {
        double a = std::max(lo, pieces[i][0]), b = std::min(hi, pieces[i][1]);
        if (a < b) outLo = std::min(outLo, a), outHi = std::max(outHi, b);
    }
    if (!(outLo < outHi)) return false;
    *t0 = float(outLo);
    *t1 = float(outHi);
    return *t0 < *t1;
}

bool clipRayToLight(const Light& light, Vec3 o, Vec3 d, float* t0, float* t1) {
    float a = *t0, b = *t1;
    if (light.kind == LightKind::Spot && !clipToSpotCone(light, o, d, &a, &b)) return false;
    if (light.isPlanar() && !light.doubleSided) {
        // Front half-space of the emitter: n·(o + t·d − p0) > 0.
        const Vec3 p0 = light.shape.p0, n = light.shape.edgeCross();
        const float h = dot(n, o - p0), dn = dot(n, d);
        if (dn == 0) {
            if (h <= 0) return false;
        } else if (dn > 0) {
            a = std::max(a, -h / dn);
        } else {
            b = std::min(b, -h / dn);
        }
    }
    *t0 = a;
    *t1 = b;
    return a < b;
}

void lightSurfaceUv(const Scene& scene, const Light& light, Vec3 p, float* u, float* v) {
    if (!light.isPlanar()) return;
    const Mesh& mesh = scene.mesh(light.mesh);
    if (mesh.uvs.empty()) return;
    const uint32_t* idx = &mesh.indices[3 * size_t(light.triangle)];
    const EmitterTriangle& t = light.shape;
    const Vec3 n = t.edgeCross();
    const float nn = dot(n, n);
    const float b1 = nn > 0 ? dot(cross(p - t.p0, t.p2 - t.p0), n) / nn : 0.0f;
    const float b2 = nn > 0 ? dot(cross(t.p1 - t.p0, p - t.p0), n) / nn : 0.0f;
    const float b0 = 1 - b1 - b2;
    *u = mesh.uvs[2 * idx[0]] * b0 + mesh.uvs[2 * idx[1]] * b1 + mesh.uvs[2 * idx[2]] * b2;
    *v = mesh.uvs[2 * idx[0] + 1] * b0 + mesh.uvs[2 * idx[1] + 1] * b1 + mesh.uvs[2 * idx[2] + 1] * b2;
}

Vec3 lightNormalFacing(const Light& light, Vec3 p, Vec3 towards) {
    if (!light.hasSurface()) return Vec3(0.0f);
    Vec3 n = light.isPlanar() ? light.shape.n : normalize(p - light.position);
    if (light.isPlanar() && dot(n, towards) < 0) n = -n;
    return n;
}

}  // namespace brume
