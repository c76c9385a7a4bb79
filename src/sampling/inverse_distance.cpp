#include "brume/sampling/inverse_distance.h"

#include <algorithm>
#include <cmath>

namespace brume {

namespace {

// The eight triangles with apex c (inverse_distance.h): legs h along axis `hAxis` with sign
// sh, l along the other axis with sign sl.
struct Triangle {
    double h, l;
    int hAxis;
    double sh, sl;
};

int trianglesAbout(double cx, double cy, Triangle* t) {
    const double ext[2][2] = {{1.0 - cx, cx}, {1.0 - cy, cy}};  // extent along +axis, −axis
    int n = 0;
    for (int ix = 0; ix < 2; ++ix)
        for (int iy = 0; iy < 2; ++iy) {
            const double a = ext[0][ix], b = ext[1][iy];
            const double sx = ix == 0 ? 1.0 : -1.0, sy = iy == 0 ? 1.0 : -1.0;
            t[n++] = Triangle{a, b, 0, sx, sy};
            t[n++] = Triangle{b, a, 1, sy, sx};
        }
    return n;
}

double massOf(const Triangle& t) { return t.h > 0 && t.l > 0 ? t.h * std::asinh(t.l / t.h) : 0.0; }

bool inside(double cx, double cy) { return cx >= 0 && cx <= 1 && cy >= 0 && cy <= 1; }

// c outside the square (inverse_distance.h): angles θ about c, measured from the direction to
// the square's centre (the square spans less than π about c and contains that direction, so
// they lie in (−π, π) without wrapping). Each edge e with c off its line subtends
// [θ0, θ1] and lies at distance d along the direction φ of its foot; the inverse-distance mass
// of the triangle (c, e) up to θ is d·(asinh(tan(θ' − φ)) − asinh(tan(θ0 − φ))), θ' = min(θ, θ1).
struct Edge {
    double theta0, theta1, d, phi;
    bool near;  // c on the outer side of its line: it bounds the region from the inside
};

struct OutsideView {
    double cx, cy, base;  // c, and the angle of the direction to the centre
    Edge edges[4];
    int n = 0;
    double thetaMin = 0, thetaMax = 0;

    OutsideView(double x, double y) : cx(x), cy(y), base(std::atan2(0.5 - y, 0.5 - x)) {
        const double corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        const double outward[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};  // of edge k (corner k → k + 1)
        thetaMin = 1e30;
        thetaMax = -1e30;
        for (int k = 0; k < 4; ++k) {
            const double* p = corner[k];
            const double* q = corner[(k + 1) % 4];
            const double side = (cx - p[0]) * outward[k][0] + (cy - p[1]) * outward[k][1];
            const double a = angleOf(p[0], p[1]), b = angleOf(q[0], q[1]);
            thetaMin = std::min(thetaMin, std::min(a, b));
            thetaMax = std::max(thetaMax, std::max(a, b));
            if (side == 0) continue;  // c on its line: it subtends no angle
            // The foot of the perpendicular from c, as an angle: along −outward if c is outside
            // this edge's line, +outward if inside.
            const double sgn = side > 0 ? -1.0 : 1.0;
            edges[n++] = Edge{std::min(a, b), std::max(a, b), std::abs(side),
                              wrap(std::atan2(sgn * outward[k][1], sgn * outward[k][0]) - base), side > 0};
        }
    }
    double angleOf(double x, double y) const { return wrap(std::atan2(y - cy, x - cx) - base); }
    static double wrap(double a) {
        while (a > kPiD) a -= 2 * kPiD;
        while (a <= -kPiD) a += 2 * kPiD;
        return a;
    }
    static constexpr double kPiD = 3.14159265358979323846;
    // The region's inverse-distance mass between thetaMin and θ.
    double massUpTo(double theta) const {
        double m = 0;
        for (int i = 0; i < n; ++i) {
            const Edge& e = edges[i];
            if (theta <= e.theta0) continue;
            const double hi = std::min(theta, e.theta1);
            const double part = e.d * (std::asinh(std::tan(hi - e.phi)) - std::asinh(std::tan(e.theta0 - e.phi)));
            m += e.near ? -part : part;
        }
        return m;
    }
    // The distance from c along θ to the edges that bound the region: nearest far edge
    // (leaving), farthest near edge (entering).
    void chord(double theta, double* rIn, double* rOut) const {
        *rIn = 0;
        *rOut = 1e30;
        for (int i = 0; i < n; ++i) {
            const Edge& e = edges[i];
            if (theta < e.theta0 || theta > e.theta1) continue;
            const double r = e.d / std::cos(theta - e.phi);
            if (e.near) *rIn = std::max(*rIn, r);
            else *rOut = std::min(*rOut, r);
        }
        if (*rOut < *rIn) *rOut = *rIn;
    }
};

}  // namespace

float inverseDistanceNorm(float cx, float cy) {
    if (!inside(cx, cy)) {
        const OutsideView view(cx, cy);
        return float(view.massUpTo(view.thetaMax));
    }
    Triangle t[8];
    double z = 0;
    for (int i = 0, n = trianglesAbout(cx, cy, t); i < n; ++i) z += massOf(t[i]);
    return float(z);
}

InverseDistanceSample sampleInverseDistance(float cx, float cy, Sample2 u) {
    if (!inside(cx, cy)) {
        // θ by its mass, found by bisection (the mass grows with θ: a chord's length r_out −
        // r_in ≥ 0), then r uniform on the chord (density ∝ 1/r per area is uniform in r, θ).
        const OutsideView view(cx, cy);
        const double z = view.massUpTo(view.thetaMax), target = double(u.u) * z;
        InverseDistanceSample s{0.0f, 0.0f, 0.0f};
        if (!(z > 0)) return s;
        double lo = view.thetaMin, hi = view.thetaMax;
        for (int i = 0; i < 60 && hi - lo > 1e-15; ++i) {
            const double mid = 0.5 * (lo + hi);
            (view.massUpTo(mid) < target ? lo : hi) = mid;
        }
        const double theta = 0.5 * (lo + hi);
        double rIn, rOut;
        view.chord(theta, &rIn, &rOut);
        const double r = rIn + double(u.v) * (rOut - rIn);
        const double x = cx + r * std::cos(theta + view.base), y = cy + r * std::sin(theta + view.base);
        s.x = float(std::min(std::max(x, 0.0), 1.0));
        s.y = float(std::min(std::max(y, 0.0), 1.0));
        s.weight = float(z * r);
        return s;
    }
    Triangle t[8];
    double mass[8], z = 0;
    const int n = trianglesAbout(cx, cy, t);
    for (int i = 0; i < n; ++i) z += mass[i] = massOf(t[i]);
    InverseDistanceSample s{cx, cy, 0.0f};
    if (!(z > 0)) return s;
    // Pick a triangle by u.u, then rescale u.u within it (the last one with mass takes what
    // rounding leaves).
    double target = double(u.u) * z, below = 0;
    int k = -1;
    for (int i = 0; i < n; ++i) {
        if (!(mass[i] > 0)) continue;
        k = i;
        if (target < below + mass[i]) break;
        below += mass[i];
    }
    const Triangle& tri = t[k];
    const double uu = std::min(std::max((target - below) / mass[k], 0.0), 1.0);
    const double tanTheta = std::sinh(uu * std::asinh(tri.l / tri.h));
    const double along = double(u.v) * tri.h, across = along * tanTheta;
    double p[2] = {cx, cy};
    p[tri.hAxis] += tri.sh * along;
    p[1 - tri.hAxis] += tri.sl * across;
    s.x = float(std::min(std::max(p[0], 0.0), 1.0));
    s.y = float(std::min(std::max(p[1], 0.0), 1.0));
    s.weight = float(z * std::hypot(p[0] - cx, p[1] - cy));
    return s;
}

float inverseDistancePdf(float cx, float cy, float x, float y) {
    const double r = std::hypot(double(x) - cx, double(y) - cy);
    if (!(r > 0) || x < 0 || x > 1 || y < 0 || y > 1) return 0.0f;
    return float(1.0 / (double(inverseDistanceNorm(cx, cy)) * r));
}

}  // namespace brume
