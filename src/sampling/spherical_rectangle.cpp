#include "brume/sampling/spherical_rectangle.h"

#include <algorithm>
#include <cmath>

namespace brume {

namespace {

struct D3 {
    double x, y, z;
};
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 unit(D3 a) {
    const double l = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    return {a.x / l, a.y / l, a.z / l};
}
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double clamp1(double c) { return std::max(-1.0, std::min(1.0, c)); }

}  // namespace

bool makeSphericalRectangle(Vec3 o, Vec3 s, Vec3 ex, Vec3 ey, SphericalRectangle* out) {
    SphericalRectangle& r = *out;
    const float lx = length(ex), ly = length(ey);
    if (!(lx > 0) || !(ly > 0)) return false;
    r.o = o;
    r.x = ex / lx;
    r.y = ey / ly;
    r.z = cross(r.x, r.y);
    const Vec3 d = s - o;
    r.x0 = dot(d, r.x);
    r.y0 = dot(d, r.y);
    r.z0 = dot(d, r.z);
    if (r.z0 > 0) {
        r.z0 = -r.z0;
        r.z = -r.z;
    }
    if (!(r.z0 < 0)) return false;  // o in the plane
    r.x1 = r.x0 + lx;
    r.y1 = r.y0 + ly;
    const D3 v00{r.x0, r.y0, r.z0}, v01{r.x0, r.y1, r.z0}, v10{r.x1, r.y0, r.z0}, v11{r.x1, r.y1, r.z0};
    const D3 n0 = unit(cross(v00, v10)), n1 = unit(cross(v10, v11)), n2 = unit(cross(v11, v01)),
             n3 = unit(cross(v01, v00));
    const double g0 = std::acos(clamp1(-dot(n0, n1))), g1 = std::acos(clamp1(-dot(n1, n2))),
                 g2 = std::acos(clamp1(-dot(n2, n3))), g3 = std::acos(clamp1(-dot(n3, n0)));
    r.b0 = n0.z;
    r.b1 = n2.z;
    r.k = 2 * M_PI - g2 - g3;
    r.solidAngle = g0 + g1 - r.k;
    return r.solidAngle > 0;
}

Vec3 sampleSphericalRectangle(const SphericalRectangle& r, Sample2 u) {
    // The sub-rectangle [x0, xu] of solid angle ξ1·S: its angle at the fourth corner.
    const double au = double(u.u) * r.solidAngle + r.k;
    const double fu = (std::cos(au) * r.b0 - r.b1) / std::sin(au);
    double cu = 1.0 / std::sqrt(fu * fu + r.b0 * r.b0) * (fu > 0 ? 1.0 : -1.0);
    cu = clamp1(cu);
    double xu = -(cu * r.z0) / std::max(1e-300, std::sqrt(1.0 - cu * cu));
    xu = std::min(r.x1, std::max(r.x0, xu));
    // y with the height h uniform.
    const double dd = std::sqrt(xu * xu + r.z0 * r.z0);
    const double h0 = r.y0 / std::sqrt(dd * dd + r.y0 * r.y0), h1 = r.y1 / std::sqrt(dd * dd + r.y1 * r.y1);
    const double hv = h0 + double(u.v) * (h1 - h0), hv2 = hv * hv;
    double yv = hv2 < 1 - 1e-12 ? hv * dd / std::sqrt(1 - hv2) : r.y1;
    yv = std::min(r.y1, std::max(r.y0, yv));
    return r.o + r.x * float(xu) + r.y * float(yv) + r.z * float(r.z0);
}

}  // namespace brume
