#include "brume/sampling/equiangular.h"

#include <cmath>

#include "brume/math/fast_atan.h"

namespace brume {

EquiAngular makeEquiAngular(Vec3 o, Vec3 d, Vec3 c, float a, float b, float g) {
    EquiAngular ea;
    double ox = double(c.x) - o.x, oy = double(c.y) - o.y, oz = double(c.z) - o.z;
    ea.delta = ox * d.x + oy * d.y + oz * d.z;
    double px = ox - ea.delta * d.x, py = oy - ea.delta * d.y, pz = oz - ea.delta * d.z;
    double dist = std::sqrt(ox * ox + oy * oy + oz * oz);
    // A light exactly on the ray (D = 0) has a non-integrable 1/(t−Δ)² peak; a floor on D
    // relative to the distance keeps the density finite and positive everywhere.
    ea.D = std::max(std::sqrt(px * px + py * py + pz * pz), 1e-6 * std::max(1.0, dist));
    ea.a = a;
    ea.b = b;
    ea.thetaA = std::atan((double(a) - ea.delta) / ea.D);
    ea.thetaB = std::isinf(b) ? 0.5 * M_PI : std::atan((double(b) - ea.delta) / ea.D);
    ea.uniform = !(ea.thetaB - ea.thetaA > 1e-7) && !std::isinf(b);
    if (g != 0 && !ea.uniform)
        ea.phase = makeHgAngle(g, halfAngleAt(double(a) - ea.delta, ea.D), halfAngleAt(double(b) - ea.delta, ea.D));
    return ea;
}

float sampleEquiAngular(const EquiAngular& ea, float u) {
    double t;
    if (ea.uniform) {
        t = ea.a + double(u) * (ea.b - ea.a);
    } else if (ea.phase.alpha < 1 && u >= ea.phase.alpha) {
        // The phase part, with the rest of the number (one number picks the part and samples it).
        const double xi = (double(u) - ea.phase.alpha) / (1.0 - ea.phase.alpha);
        t = ea.delta + offsetAt(sampleHgAnglePhase(ea.phase, xi), ea.D);
    } else {
        const double v = ea.phase.alpha < 1 ? double(u) / ea.phase.alpha : double(u);
        double theta = (1.0 - v) * ea.thetaA + v * ea.thetaB;
        t = ea.delta + ea.D * std::tan(theta);
    }
    return float(std::min(std::max(t, ea.a), ea.b));
}

float equiAngularPdf(const EquiAngular& ea, float t) {
    if (t < ea.a || t > ea.b) return 0.0f;
    if (ea.uniform) return float(1.0 / (ea.b - ea.a));
    double x = double(t) - ea.delta;
    const double perAngle = ea.D / (ea.D * ea.D + x * x);  // dθ/dt
    if (ea.phase.alpha >= 1) return float(perAngle / (ea.thetaB - ea.thetaA));
    const double alpha = ea.phase.alpha;
    return float(perAngle * (alpha / (ea.thetaB - ea.thetaA) +
                             (1.0 - alpha) * hgAnglePhasePdf(ea.phase, halfAngleAt(x, ea.D))));
}

float equiAngularStandInPdf(Vec3 o, Vec3 d, Vec3 c, float t, float g) {
    if (!(t >= 0)) return 0.0f;
    if (g != 0) return equiAngularPdf(makeEquiAngular(o, d, c, 0.0f, INFINITY, g), t);
    const Vec3 oc = c - o;
    const float delta = dot(oc, d);
    const Vec3 perp = oc - d * delta;
    // The same floor on D as makeEquiAngular.
    const float D = std::max(std::sqrt(dot(perp, perp)), 1e-6f * std::max(1.0f, std::sqrt(dot(oc, oc))));
    const float x = t - delta;
    return D / (halfPiPlusAtan(delta / D) * (D * D + x * x));
}

}  // namespace brume
