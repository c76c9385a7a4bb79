// Quadrature references for single scattering in an infinite homogeneous fog
// (σs = 0.2, σa = 0.05, g = 0.3, as tests/data/make_test_scenes.py writes them), seen from a
// camera at the origin: point and spot lights (1D), sphere and quad lights (1D × 2D); and
// singleScatterReference, a point or spot light in any such fog.
#pragma once
#include <cmath>
#include <vector>

#include "brume/integrators/path_tracer.h"
#include "brume/math/frame.h"
#include "brume/scene/light.h"

namespace brume::test {

constexpr double kSigmaS = 0.2, kSigmaT = 0.25, kG = 0.3, kYfov = 0.6;

inline double phaseHG(double cosTheta, double g = kG) {
    double denom = 1 + g * g - 2 * g * cosTheta;
    return (1 - g * g) / (4 * M_PI * denom * std::sqrt(denom));
}

// Gauss–Legendre nodes and weights on [−1, 1] (Newton on the Legendre recurrence).
inline void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

// ∫0^tEnd g(t) dt for g peaked like 1/|x(t) − c|²: t = Δ + D·tanφ, composite Simpson in φ.
template <class G>
double integrateAlongRayN(Vec3 d, Vec3 c, double tEnd, G g, int n);
template <class G>
double integrateAlongRay(Vec3 d, Vec3 c, double tEnd, G g) {
    return integrateAlongRayN(d, c, tEnd, g, 2000);
}
template <class G>
double integrateAlongRayN(Vec3 d, Vec3 c, double tEnd, G g, int n) {
    double delta = double(c.x) * d.x + double(c.y) * d.y + double(c.z) * d.z;
    double px = c.x - delta * d.x, py = c.y - delta * d.y, pz = c.z - delta * d.z;
    double D = std::sqrt(px * px + py * py + pz * pz);
    double a = std::atan2(-delta, D), b = std::isinf(tEnd) ? 0.5 * M_PI : std::atan2(tEnd - delta, D);
    auto f = [&](double phi) {
        if (phi >= 0.5 * M_PI) return 0.0;
        double tanp = std::tan(phi);
        return g(delta + D * tanp) * D * (1 + tanp * tanp);
    };
    double h = (b - a) / n, sum = f(a) + f(b);
    for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 ? 4 : 2);
    return sum * h / 3;
}

// Sphere light (centre c, radius r, intensity I → radiance I/(π r²)) seen along d from the origin.
inline double sphereReference(Vec3 d, Vec3 c, double r, double I, double g = kG) {
    double Ls = I / (M_PI * r * r);
    // Does the pixel's ray hit the sphere? Then it sees the emitter attenuated, and the
    // scattering integral stops there.
    double b = double(c.x) * d.x + double(c.y) * d.y + double(c.z) * d.z;
    double cc = double(c.x) * c.x + double(c.y) * c.y + double(c.z) * c.z;
    double disc = b * b - (cc - r * r);
    double tEnd = INFINITY, direct = 0;
    if (disc > 0 && b - std::sqrt(disc) > 0) {
        tEnd = b - std::sqrt(disc);
        direct = Ls * std::exp(-kSigmaT * tEnd);
    }
    std::vector<double> gx, gw;
    gaussLegendre(12, gx, gw);
    const int nPsi = 24;
    auto inScatter = [&](double t) {
        double x[3] = {t * d.x, t * d.y, t * d.z};
        double a[3] = {c.x - x[0], c.y - x[1], c.z - x[2]};
        double dc = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        if (dc <= r) return 0.0;
        Vec3 axis(float(a[0] / dc), float(a[1] / dc), float(a[2] / dc));
        Frame frame(axis);
        double s2max = (r / dc) * (r / dc), cosMax = std::sqrt(1 - s2max);
        double sum = 0;
        for (int i = 0; i < 12; ++i) {
            double u = cosMax + (1 - cosMax) * 0.5 * (gx[i] + 1);  // cosθ in [cosMax, 1]
            double sinT = std::sqrt(std::max(0.0, 1 - u * u));
            double s = dc * u - std::sqrt(std::max(0.0, r * r - dc * dc * sinT * sinT));
            for (int j = 0; j < nPsi; ++j) {  // trapezoid in ψ: exact for periodic smooth integrands
                double psi = 2 * M_PI * (j + 0.5) / nPsi;
                Vec3 w = frame.toWorld(Vec3(float(sinT * std::cos(psi)), float(sinT * std::sin(psi)), float(u)));
                sum += gw[i] * phaseHG(dot(d, w), g) * std::exp(-kSigmaT * s);
            }
        }
        double domega = 0.5 * (1 - cosMax) * (2 * M_PI / nPsi);  // du·dψ per unit weight
        return kSigmaS * std::exp(-kSigmaT * t) * Ls * sum * domega;
    };
    return direct + integrateAlongRay(d, c, tEnd, inScatter);
}

// One-sided quad light centred at q, spanned by half-vectors eu, ev, front normal n, radiance Le.
inline double quadReference(Vec3 d, Vec3 q, Vec3 eu, Vec3 ev, Vec3 n, double Le) {
    std::vector<double> gx, gw;
    gaussLegendre(10, gx, gw);
    double area = 4 * length(eu) * length(ev);
    auto inScatter = [&](double t) {
        Vec3 x = d * float(t);
        double sum = 0;
        for (int i = 0; i < 10; ++i)
            for (int j = 0; j < 10; ++j) {
                Vec3 y = q + eu * float(gx[i]) + ev * float(gx[j]);
                Vec3 toX = x - y;
                double r2 = dot(toX, toX), r = std::sqrt(r2);
                double cosY = dot(n, toX) / r;
                if (cosY <= 0) continue;
                double cosPhase = -dot(d, toX) / r;  // light travels y → x, then along −d
                sum += gw[i] * gw[j] * 0.25 * phaseHG(cosPhase) * cosY / r2 * std::exp(-kSigmaT * r);
            }
        return kSigmaS * std::exp(-kSigmaT * t) * Le * sum * area;
    };
    return integrateAlongRay(d, q, INFINITY, inScatter);
}

// One-sided rectangle light (corner q0, perpendicular full edges e1, e2, front normal n,
// radiance Le) seen along d from the origin, for rectangles close to the ray: the inner
// integral is taken over the solid angle, where its integrand is smooth however close the
// rectangle is. For x at height h in front of the plane, with (a, b) the in-plane offsets of a
// rectangle point from x's foot, a = h·tanα and b = √(h² + a²)·tanβ give dω = cosβ dα dβ
// (nGL Gauss–Legendre nodes in each). The rays must not hit the rectangle.
inline double rectangleReferenceClose(Vec3 d, Vec3 q0, Vec3 e1, Vec3 e2, Vec3 n, double Le, int nT = 2000, int nGL = 12) {
    std::vector<double> gx, gw;
    gaussLegendre(nGL, gx, gw);
    const double l1 = length(e1), l2 = length(e2);
    const Vec3 u1 = e1 / float(l1), u2 = e2 / float(l2);
    auto inScatter = [&](double t) {
        const double x[3] = {t * d.x, t * d.y, t * d.z};
        const double rel[3] = {x[0] - q0.x, x[1] - q0.y, x[2] - q0.z};
        auto along = [&](Vec3 e) { return rel[0] * e.x + rel[1] * e.y + rel[2] * e.z; };
        const double h = along(n), ac = along(u1), bc = along(u2);
        if (!(h > 0)) return 0.0;
        const double a0 = std::atan(-ac / h), a1 = std::atan((l1 - ac) / h);
        double sum = 0;
        for (int i = 0; i < nGL; ++i) {
            const double alpha = 0.5 * (a0 + a1) + 0.5 * (a1 - a0) * gx[i];
            const double a = h * std::tan(alpha), Ra = std::sqrt(h * h + a * a);
            const double b0 = std::atan(-bc / Ra), b1 = std::atan((l2 - bc) / Ra);
            double inner = 0;
            for (int j = 0; j < nGL; ++j) {
                const double beta = 0.5 * (b0 + b1) + 0.5 * (b1 - b0) * gx[j];
                const double b = Ra * std::tan(beta), r = Ra / std::cos(beta);
                // x − y = h·n − a·u1 − b·u2; light travels y → x, then along −d.
                const double toX[3] = {h * n.x - a * u1.x - b * u2.x, h * n.y - a * u1.y - b * u2.y,
                                       h * n.z - a * u1.z - b * u2.z};
                const double cosPhase = -(d.x * toX[0] + d.y * toX[1] + d.z * toX[2]) / r;
                inner += gw[j] * std::cos(beta) * phaseHG(cosPhase) * std::exp(-kSigmaT * r);
            }
            sum += gw[i] * inner * 0.5 * (b1 - b0);
        }
        return kSigmaS * std::exp(-kSigmaT * t) * Le * sum * 0.5 * (a1 - a0);
    };
    // Along the ray in the angle towards the rectangle's centre, as for the other lights.
    return integrateAlongRayN(d, q0 + (e1 + e2) * 0.5f, INFINITY, inScatter, nT);
}

// The four --connect modes, for tests that run each.
const ConnectMode kConnectModes[] = {ConnectMode::Density, ConnectMode::EquiAngular, ConnectMode::Product,
                                     ConnectMode::Mis};
inline const char* connectModeName(ConnectMode m) {
    return m == ConnectMode::Density ? "density" : m == ConnectMode::EquiAngular ? "equiangular"
                                       : m == ConnectMode::Product ? "product" : "mis";
}

// A single-scattering test scene (tests/data/single_*.gltf): its light, fog and the samples
// per pixel a path tracer needs for it.
struct SingleCase {
    const char* file;
    Vec3 light;
    Vec3 sigmaS, sigmaA;
    double g;
    bool spot;
    int spp = 4096;
};

// The spot light of single_spot.gltf as the generator writes it: pointing straight down, cone
// 0.2–0.4 rad (position and intensity are the caller's).
inline Light singleSpotLight() {
    Light spot;
    spot.kind = LightKind::Spot;
    spot.direction = Vec3(0, -1, 0);
    spot.cosInner = std::cos(0.2f);
    spot.cosOuter = std::cos(0.4f);
    return spot;
}

// Single scattering along ray o + t·d (o = origin) from a point light at c with intensity I,
// optional spot cone, in infinite homogeneous fog:
//   L = ∫0^∞ σs·T(t)·p(cosθ)·I·a(x)·T(r)/r² dt,  r = |c − x|, cosθ = d·(c − x)/r.
// Substituting t = Δ + D·tanφ (dt = D/cos²φ dφ, r² = D²/cos²φ) gives the smooth integrand
//   σs·T(t)·p·I·a·T(r)/D over φ ∈ [atan(−Δ/D), π/2), integrated by composite Simpson.
// n: Simpson intervals (even); 20000 leaves the quadrature error far below any test's noise.
inline Vec3 singleScatterReference(Vec3 d, Vec3 c, Vec3 I, Vec3 sigmaS, Vec3 sigmaA, double g, const Light* spot,
                                   int n = 20000) {
    double dx = d.x, dy = d.y, dz = d.z;
    double delta = c.x * dx + c.y * dy + c.z * dz;
    double px = c.x - delta * dx, py = c.y - delta * dy, pz = c.z - delta * dz;
    double D = std::sqrt(px * px + py * py + pz * pz);
    double a = std::atan2(-delta, D), b = 0.5 * M_PI;
    Vec3 out;
    for (int ch = 0; ch < 3; ++ch) {
        double st = double(sigmaS[ch]) + sigmaA[ch];
        auto f = [&](double phi) {
            if (phi >= b) return 0.0;
            double t = delta + D * std::tan(phi);
            double xx = t * dx, xy = t * dy, xz = t * dz;
            double lx = c.x - xx, ly = c.y - xy, lz = c.z - xz;
            double r = std::sqrt(lx * lx + ly * ly + lz * lz);
            double cosTheta = (dx * lx + dy * ly + dz * lz) / r;
            double denom = 1 + g * g - 2 * g * cosTheta;
            double phase = (1 - g * g) / (4 * M_PI * denom * std::sqrt(denom));
            double atten = 1.0;
            if (spot) atten = spotAttenuation(*spot, float(-(lx * spot->direction.x + ly * spot->direction.y + lz * spot->direction.z) / r));
            return double(sigmaS[ch]) * std::exp(-st * (t + r)) * phase * I[ch] * atten / D;
        };
        double h = (b - a) / n, sum = f(a) + f(b);
        for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 ? 4 : 2);
        out[ch] = float(sum * h / 3);
    }
    return out;
}

}  // namespace brume::test

namespace brume::test {

// tests/data/area_rectangles_close.gltf (make_test_scenes.py, area_rectangles_close): a ceiling
// panel 4 cm above the top plane of the view and a window beside the camera, radiance 3.
inline double rectanglesCloseReference(Vec3 d, int nT = 2000, int nGL = 12) {
    const double slope = std::tan(0.5 * kYfov);
    const Vec3 nTop = normalize(Vec3(0.0f, 1.0f, float(slope)));
    const Vec3 along = normalize(Vec3(0.0f, float(slope), -1.0f));
    const Vec3 center = Vec3(0.0f, float(3.0 * slope), -3.0f) + nTop * 0.04f;
    const Vec3 u(0.5f, 0.0f, 0.0f), v = along * 0.75f;
    const double panel = rectangleReferenceClose(d, center - u - v, u * 2.0f, v * 2.0f, -nTop, 3.0, nT, nGL);
    const double window = rectangleReferenceClose(d, Vec3(0.55f, -0.6f, -1.7f), Vec3(0.0f, 0.0f, 1.6f), Vec3(0.0f, 1.2f, 0.0f),
                                                  Vec3(-1.0f, 0.0f, 0.0f), 3.0, nT, nGL);
    return panel + window;
}

}  // namespace brume::test
