#include "brume/sampling/spherical_triangle.h"

#include <algorithm>
#include <cmath>

namespace brume {

namespace {

struct D3 {
    double x, y, z;
};
D3 d3(Vec3 v) { return {v.x, v.y, v.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(D3 a) { return std::sqrt(dot(a, a)); }
double clamp1(double c) { return std::max(-1.0, std::min(1.0, c)); }

// The component of v orthogonal to unit a, normalised; false if v ∥ a.
bool orthoNormal(D3 v, D3 a, D3* out) {
    D3 o = v - a * dot(v, a);
    double len = norm(o);
    if (!(len > 0)) return false;
    *out = o * (1.0 / len);
    return true;
}

// Inner angle of the spherical triangle at vertex a (between the great arcs to b and to c).
double innerAngle(D3 a, D3 b, D3 c) {
    D3 nb = cross(a, b), nc = cross(a, c);
    if (!(dot(nb, nb) > 0) || !(dot(nc, nc) > 0)) return 0.0;
    return std::atan2(norm(cross(nb, nc)), dot(nb, nc));  // no acos: exact near 0 and π
}

double signedSolidAngle(D3 R0, D3 R1, D3 R2) {
    double r0 = norm(R0), r1 = norm(R1), r2 = norm(R2);
    double triple = dot(R0, cross(R1, R2));
    double den = r0 * r1 * r2 + dot(R0, R1) * r2 + dot(R0, R2) * r1 + dot(R1, R2) * r0;
    return 2.0 * std::atan2(triple, den);  // |Ω| < 2π; sign of the triple product
}

}  // namespace

double triangleSolidAngleSigned(Vec3 x, Vec3 p0, Vec3 p1, Vec3 p2) {
    D3 X = d3(x);
    // R0·(R1×R2) > 0 when x is behind the wound face: flip so that the front counts positive.
    return -signedSolidAngle(d3(p0) - X, d3(p1) - X, d3(p2) - X);
}

double triangleSolidAngle(Vec3 x, Vec3 p0, Vec3 p1, Vec3 p2) {
    return std::abs(triangleSolidAngleSigned(x, p0, p1, p2));
}

bool sampleSphericalTriangle(Vec3 x, Vec3 p0, Vec3 p1, Vec3 p2, Sample2 u, Vec3* wi, double* solidAngle) {
    D3 X = d3(x);
    D3 A = d3(p0) - X, B = d3(p1) - X, C = d3(p2) - X;
    double la = norm(A), lb = norm(B), lc = norm(C);
    if (!(la > 0) || !(lb > 0) || !(lc > 0)) return false;
    A = A * (1.0 / la), B = B * (1.0 / lb), C = C * (1.0 / lc);
    const double alpha = innerAngle(A, B, C), beta = innerAngle(B, C, A), gamma = innerAngle(C, A, B);
    const double area = alpha + beta + gamma - M_PI;
    if (!(area > 0)) return false;
    *solidAngle = area;
    // Ĉ on the arc AC such that the sub-triangle A B Ĉ has area ξ1·Ω.
    const double areaHat = double(u.u) * area;
    const double s = std::sin(areaHat - alpha), t = std::cos(areaHat - alpha);
    const double cosC = dot(A, B);  // cos of the arc AB, the side opposite C
    const double uu = t - std::cos(alpha), v = s + std::sin(alpha) * cosC;
    const double den = (v * s + uu * t) * std::sin(alpha);
    double q = den != 0 ? clamp1(((v * t - uu * s) * std::cos(alpha) - v) / den) : 1.0;
    D3 perpC;
    if (!orthoNormal(C, A, &perpC)) return false;
    const D3 Chat = A * q + perpC * std::sqrt(std::max(0.0, 1.0 - q * q));
    // The direction on the arc from B to Ĉ with z = cos(arc from B) uniform in [Ĉ·B, 1].
    const double z = 1.0 - double(u.v) * (1.0 - dot(Chat, B));
    D3 perpB;
    if (!orthoNormal(Chat, B, &perpB)) {
        *wi = Vec3(float(B.x), float(B.y), float(B.z));
        return true;
    }
    const D3 w = B * z + perpB * std::sqrt(std::max(0.0, 1.0 - z * z));
    const double lw = norm(w);
    *wi = Vec3(float(w.x / lw), float(w.y / lw), float(w.z / lw));
    return true;
}

}  // namespace brume
