#include "brume/integrators/equiangular_segment.h"

#include <cmath>

#include "brume/sampling/warp.h"
#include "brume/scene/scene.h"

namespace brume {

bool equiAngularAnchor(const Scene& scene, const Light& light, Sample2 u, Vec3* anchor) {
    switch (light.kind) {
    case LightKind::Point:
    case LightKind::Spot:
    case LightKind::Sphere:
        *anchor = light.position;
        return true;
    case LightKind::Triangle: {
        const Mesh& mesh = scene.mesh(light.mesh);
        const uint32_t* idx = &mesh.indices[3 * light.triangle];
        Sample2 b = sampleUniformTriangle(u);
        *anchor = mesh.positions[idx[0]] * b.u + mesh.positions[idx[1]] * b.v +
                  mesh.positions[idx[2]] * (1.0f - b.u - b.v);
        return true;
    }
    case LightKind::Directional:
        return false;
    }
    return false;
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

bool clipToLight(const Scene& scene, const Light& light, const MediumSegment& seg, float* t0, float* t1) {
    float a = 0, b = seg.tEnd;
    if (light.kind == LightKind::Spot && !clipToSpotCone(light, seg.o, seg.d, &a, &b)) return false;
    if (light.kind == LightKind::Triangle && !scene.material(light.mesh).doubleSided) {
        // Front half-space of the emitter: n·(o + t·d − y) > 0.
        const Mesh& mesh = scene.mesh(light.mesh);
        const uint32_t* idx = &mesh.indices[3 * light.triangle];
        Vec3 p0 = mesh.positions[idx[0]];
        Vec3 n = cross(mesh.positions[idx[1]] - p0, mesh.positions[idx[2]] - p0);
        float h = dot(n, seg.o - p0), dn = dot(n, seg.d);
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

bool equiAngularTowards(const Scene& scene, const Light& light, Vec3 anchor, const MediumSegment& seg, float g,
                        EquiAngular* out) {
    float a, b;
    if (!clipToLight(scene, light, seg, &a, &b)) return false;
    *out = makeEquiAngular(seg.o, seg.d, anchor, a, b, g);
    return true;
}

}  // namespace brume
