#include "brume/integrators/solid_angle_segment.h"

#include <algorithm>
#include <cmath>

#include "brume/math/fast_atan.h"
#include "brume/scene/scene.h"

namespace brume {

bool solidAngleDistanceApplies(const Scene& scene, const Light& light, const MediumSegment& seg) {
    if (!light.isPlanar() || !(light.emitterArea > 0)) return false;
    const Vec3 c = light.emitterCentre;
    const float area = light.emitterArea;
    const float along = std::min(seg.tEnd, std::max(0.0f, dot(c - seg.o, seg.d)));
    const Vec3 toC = c - (seg.o + seg.d * along);
    return dot(toC, toC) <= kSolidAngleReach * kSolidAngleReach * area;
}

bool solidAngleDistanceOn(const Scene& scene, const Light& light, const MediumSegment& seg, SolidAngleDistance* out) {
    if (!light.isPlanar()) return false;
    float a, b;
    if (!clipToLight(light, seg, &a, &b)) return false;
    // The emitter: the triangle, or the rectangle it is half of (Light::partner), as triangles.
    // Halves in the order of their numbers: either half builds the same table, bit for bit.
    const EmitterTriangle* tri[2] = {&light.shape, nullptr};
    const int halves = light.partner >= 0 ? 2 : 1;
    if (halves == 2) {
        const EmitterTriangle& other = scene.partnerOf(light).shape;
        tri[0] = light.triangle < light.partner ? &light.shape : &other;
        tri[1] = light.triangle < light.partner ? &other : &light.shape;
    }
    const Vec3 p0 = tri[0]->p0;
    const double area = light.emitterArea;
    if (!(area > 0)) return false;
    const Vec3 c = light.emitterCentre;  // area-weighted centroid
    const bool doubleSided = light.doubleSided;
    SolidAngleDistance& s = *out;
    const Vec3 oc = c - seg.o;
    s.delta = dot(oc, seg.d);
    const Vec3 perp = oc - seg.d * float(s.delta);
    s.D = std::max(double(length(perp)), 0.25 * std::sqrt(area));
    s.a = a;
    s.b = b;
    s.thetaA = std::atan2(double(a) - s.delta, s.D);
    s.thetaB = std::isinf(b) ? 0.5 * M_PI : std::atan2(double(b) - s.delta, s.D);
    if (!(s.thetaB > s.thetaA)) return false;
    // The table in float: it only has to be a deterministic function of the segment (the
    // density is whatever it tabulates), and float halves its cost.
    const float D = float(s.D);
    const Vec3 base = seg.o + seg.d * float(s.delta);
    const Vec3 n = tri[0]->edgeCross();
    // The emitter's corners, each once (a rectangle's halves share their diagonal), and its
    // triangles as corner indices: per node 4 distances for a rectangle, not 6.
    Vec3 corner[6];
    int index[2][3], corners = 0;
    for (int h = 0; h < halves; ++h)
        for (int k = 0; k < 3; ++k) {
            const Vec3& v = k == 0 ? tri[h]->p0 : k == 1 ? tri[h]->p1 : tri[h]->p2;
            int c = 0;
            while (c < corners && !(corner[c].x == v.x && corner[c].y == v.y && corner[c].z == v.z)) ++c;
            if (c == corners) corner[corners++] = v;
            index[h][k] = c;
        }
    // The nodes' offsets t − Δ = D·tan θ_i at θ_i = θa + i·Δθ, by rotating (cos θ, sin θ) by Δθ
    // (in double: 8 rotations lose nothing a float table keeps); an unbounded segment's last
    // node just short of π/2 (tan = 1000), where q has its finite limit.
    constexpr int N = SolidAngleDistance::kBins;
    constexpr double kLastTheta = 0.5 * M_PI - 1e-3;
    const double step = (s.thetaB - s.thetaA) / N, cosStep = std::cos(step), sinStep = std::sin(step);
    double cosT = std::cos(s.thetaA), sinT = std::sin(s.thetaA);
    double q[N + 1], sum = 0;
    for (int i = 0; i <= N; ++i) {
        const float u = s.thetaA + i * step > kLastTheta ? float(s.D * std::tan(kLastTheta)) : float(s.D * sinT / cosT);
        const double c = cosT * cosStep - sinT * sinStep;
        sinT = sinT * cosStep + cosT * sinStep;
        cosT = c;
        const Vec3 x = base + seg.d * u;
        // Van Oosterom–Strackee (spherical_triangle.h) in float, with a polynomial atan; the
        // front side only for a one-sided emitter (n·(x − p0) > 0).
        Vec3 r[6];
        float l[6];
        for (int k = 0; k < corners; ++k) {
            r[k] = corner[k] - x;
            l[k] = length(r[k]);
        }
        float omega = 0;
        for (int h = 0; h < halves; ++h) {
            const int i0 = index[h][0], i1 = index[h][1], i2 = index[h][2];
            const Vec3 &r0 = r[i0], &r1 = r[i1], &r2 = r[i2];
            const float l0 = l[i0], l1 = l[i1], l2 = l[i2];
            const float triple = std::abs(dot(r0, cross(r1, r2)));
            const float den = l0 * l1 * l2 + dot(r0, r1) * l2 + dot(r0, r2) * l1 + dot(r1, r2) * l0;
            omega += 2.0f * atan2NonNegative(triple, den);
        }
        if (!doubleSided && dot(n, x - p0) <= 0) omega = 0;
        q[i] = double(omega) * (D * D + u * u) / D;
        if (!std::isfinite(q[i])) return false;
        sum += (i == 0 || i == N) ? 0.5 * q[i] : q[i];
    }
    if (!(sum > 0)) return false;
    // Piecewise linear in θ between the nodes, plus a tenth of the mean everywhere; normalised
    // over [θa, θb]: node densities v_i, bin probabilities (v_i + v_(i+1))/2 · Δθ.
    const double floor = 0.1 * sum / N, dTheta = (s.thetaB - s.thetaA) / N;
    const double norm = 1.0 / ((sum + floor * N) * dTheta);
    for (int i = 0; i <= N; ++i) s.node[i] = (q[i] + floor) * norm;
    s.cdf[0] = 0;
    for (int i = 0; i < N; ++i) s.cdf[i + 1] = s.cdf[i] + 0.5 * (s.node[i] + s.node[i + 1]) * dTheta;
    s.cdf[N] = 1.0;
    return true;
}

float sampleSolidAngleDistance(const SolidAngleDistance& s, float uf) {
    constexpr int N = SolidAngleDistance::kBins;
    const double u = uf;
    int i = 0;
    while (i + 1 < N && s.cdf[i + 1] <= u) ++i;
    const double dTheta = (s.thetaB - s.thetaA) / N;
    // Within the bin the density runs linearly from a to b (in units of the bin, f ∈ [0, 1]):
    // F(f) = (a·f + (b − a)·f²/2)·Δθ = u − cdf_i, solved in the form without cancellation.
    const double a = s.node[i], b = s.node[i + 1];
    const double r = std::max(0.0, (u - s.cdf[i]) / dTheta);
    double f = (2.0 * r) / (a + std::sqrt(std::max(0.0, a * a + 2.0 * (b - a) * r)));
    f = std::min(1.0, std::max(0.0, f));
    const double theta = s.thetaA + (i + f) * dTheta;
    const double t = s.delta + s.D * std::tan(theta);
    return float(std::min(double(s.b), std::max(double(s.a), t)));
}

float solidAngleDistancePdf(const SolidAngleDistance& s, float tf) {
    if (!(tf >= s.a && tf <= s.b)) return 0.0f;
    constexpr int N = SolidAngleDistance::kBins;
    const double u = double(tf) - s.delta;
    const double x = (std::atan2(u, s.D) - s.thetaA) / (s.thetaB - s.thetaA) * N;
    const int i = std::min(N - 1, std::max(0, int(x)));
    const double f = std::min(1.0, std::max(0.0, x - i));
    const double q = s.node[i] + (s.node[i + 1] - s.node[i]) * f;
    return float(q * s.D / (s.D * s.D + u * u));
}

}  // namespace brume
