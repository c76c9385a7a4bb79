#include "brume/scene/camera_importance.h"

#include <cmath>
#include <limits>

namespace brume {

namespace {

// Film extents on the plane at distance 1, computed with the same float operations as
// Camera::generateRay (so that its edge rays project exactly onto the film edges), then
// carried in double.
struct FilmPlane {
    double tanX = 0, tanY = 0, area = 0;
    bool valid = false;
};

FilmPlane filmPlane(const Camera& cam, int width, int height) {
    FilmPlane f;
    if (width <= 0 || height <= 0) return f;
    // (tan of the last field of view asked, per thread: light tracing asks once per splat and
    // its weights several times more, always with the same camera.)
    thread_local float lastYfov = std::numeric_limits<float>::quiet_NaN(), lastTanY = 0;
    if (!(cam.yfov == lastYfov)) {
        lastYfov = cam.yfov;
        lastTanY = std::tan(0.5f * cam.yfov);
    }
    float tanY = lastTanY;
    float tanX = tanY * float(width) / float(height);
    f.tanX = tanX;
    f.tanY = tanY;
    f.area = 4.0 * f.tanX * f.tanY;
    f.valid = tanX > 0 && tanY > 0 && std::isfinite(f.area) && f.area > 0;
    return f;
}

double dotD(Vec3 a, Vec3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }

// Camera-space components of a vector v (not necessarily unit): x along right, y along up,
// z along forward.
struct Local {
    double x, y, z;
};
Local toCamera(const Camera& cam, Vec3 v) { return {dotD(v, cam.right), dotD(v, cam.up), dotD(v, cam.forward)}; }

// Film position of the direction v (any length), if it lies in front of the camera and lands
// in [0, width) × [0, height). The test is made on the float values returned, so that every
// accepted position is accepted by SplatList::splat as well.
bool projectToFilm(const FilmPlane& film, Local v, int width, int height, float* fx, float* fy) {
    if (!film.valid || !(v.z > 0)) return false;
    double sx = v.x / v.z, sy = v.y / v.z;
    float px = float((sx / film.tanX + 1.0) * 0.5 * double(width));
    float py = float((1.0 - sy / film.tanY) * 0.5 * double(height));
    if (!(px >= 0 && px < float(width) && py >= 0 && py < float(height))) return false;
    *fx = px;
    *fy = py;
    return true;
}

// cosθ of the direction v with respect to forward, 0 if undefined.
double cosTheta(Local v) {
    double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return len > 0 && std::isfinite(len) ? v.z / len : 0.0;
}

// 1 / (A cos^k θ) for a direction already known to land on the film.
float inverseAreaCosPow(const FilmPlane& film, double cos, int k) {
    double c = cos;
    double ck = k == 4 ? (c * c) * (c * c) : (c * c) * c;
    return float(1.0 / (film.area * ck));
}

float filmDensity(const Camera& cam, Vec3 w, int width, int height, int cosPower) {
    FilmPlane film = filmPlane(cam, width, height);
    Local v = toCamera(cam, w);
    float fx, fy;
    if (!projectToFilm(film, v, width, height, &fx, &fy)) return 0.0f;
    double c = cosTheta(v);
    if (!(c > 0)) return 0.0f;
    return inverseAreaCosPow(film, c, cosPower);
}

}  // namespace

bool connectToCamera(const Camera& cam, Vec3 ref, int width, int height, CameraConnection* out) {
    FilmPlane film = filmPlane(cam, width, height);
    // ref − position in float, exactly as cameraImportance would receive it.
    Vec3 d = ref - cam.position;
    Local v = toCamera(cam, d);
    float fx, fy;
    if (!projectToFilm(film, v, width, height, &fx, &fy)) return false;
    double dist = std::sqrt(dotD(d, d));
    if (!(dist > 0) || !std::isfinite(dist)) return false;
    double c = v.z / dist;
    if (!(c > 0)) return false;
    out->wi = Vec3(float(-d.x / dist), float(-d.y / dist), float(-d.z / dist));
    out->dist = float(dist);
    out->fx = fx;
    out->fy = fy;
    out->We = inverseAreaCosPow(film, c, 4);
    out->pdf = 1.0f;
    return true;
}

float cameraImportance(const Camera& cam, Vec3 w, int width, int height) {
    return filmDensity(cam, w, width, height, 4);
}

float cameraPdfDir(const Camera& cam, Vec3 w, int width, int height) {
    return filmDensity(cam, w, width, height, 3);
}

bool clipToFrustum(const Camera& cam, int width, int height, Vec3 o, Vec3 d, float* t0, float* t1) {
    FilmPlane film = filmPlane(cam, width, height);
    if (!film.valid) return false;
    const float inT0 = *t0, inT1 = *t1;
    if (!(inT0 <= inT1)) return false;  // also rejects NaN

    // Ray relative to the camera, in camera space (double: o − position rounded in float
    // would lose digits far from the origin).
    const double ox = double(o.x) - cam.position.x, oy = double(o.y) - cam.position.y,
                 oz = double(o.z) - cam.position.z;
    auto along = [&](Vec3 axis) { return ox * axis.x + oy * axis.y + oz * axis.z; };
    const Local q{along(cam.right), along(cam.up), along(cam.forward)};
    const Local e = toCamera(cam, d);

    // Bound on the float rounding a caller makes when it evaluates o + t·d and projects the
    // point, as an error in the plane functions g below:
    //     |Δg(t)| ≤ δ(t) = kRel · |n| · (|o| + |position| + |t|·|d|),
    // a few ulps of each term, plus the rounding of the float film position (an ulp of the
    // film size, ~2^-24 of |t·d| in the plane's units); kRel leaves a margin of ~2 over 7·2^-24.
    const double kRel = 1e-6;
    const double scaleO = std::sqrt(dotD(o, o)) + std::sqrt(dotD(cam.position, cam.position));
    const double lenD = std::sqrt(dotD(d, d));
    if (!std::isfinite(scaleO) || !std::isfinite(lenD)) return false;
    // The largest |t| of the input (+∞ if unbounded).
    const double tIn = std::max(std::abs(double(inT0)), std::abs(double(inT1)));

    double lo = inT0, hi = inT1;
    // Inside ⇔ for each of the four planes g(t) = g0 + t·gd ≥ 0, with g = a·z − s·c, where
    // (a, c) is (tanX, x) or (tanY, y) and s = ±1; the plane's normal has length sqrt(a² + 1).
    // The kept set is g(t) + margin ≥ 0: still one linear constraint per plane.
    const double tans[2] = {film.tanX, film.tanY};
    const double qc[2] = {q.x, q.y}, ec[2] = {e.x, e.y};
    for (int axis = 0; axis < 2; ++axis) {
        const double a = tans[axis];
        const double nlen = std::sqrt(a * a + 1.0);
        for (double s : {1.0, -1.0}) {
            const double g0 = a * q.z - s * qc[axis];
            const double gd = a * e.z - s * ec[axis];
            // The margin is δ at the largest |t| where rounding can flip the sign of g: within
            // the input and, unless the ray grazes the plane, near the crossing t = −g0/gd
            // (|g| grows at rate |gd| away from it, δ only at rate kRel·|n|·|d|).
            double tMax = tIn;
            if (gd != 0) {
                const double tCross = std::abs(g0 / gd);
                const double rate = kRel * nlen * lenD;
                if (std::abs(gd) >= 2 * rate) {
                    tMax = std::min(tMax, tCross + 2 * kRel * nlen * (scaleO + tCross * lenD) / std::abs(gd));
                } else if (!std::isfinite(tMax)) {
                    tMax = tCross;  // grazing an unbounded ray: best effort
                }
            }
            const double margin = kRel * nlen * (scaleO + tMax * lenD);
            if (gd == 0) {
                // Parallel to the plane: all inside or all outside.
                if (g0 + margin < 0) return false;
                continue;
            }
            const double tc = -(g0 + margin) / gd;
            if (gd > 0) {
                lo = std::max(lo, tc);
            } else {
                hi = std::min(hi, tc);
            }
        }
    }
    if (!(lo < hi)) return false;

    // Round outwards to float, then stay within the input interval.
    float flo = float(lo), fhi = float(hi);
    if (double(flo) > lo) flo = std::nextafter(flo, -std::numeric_limits<float>::infinity());
    if (double(fhi) < hi) fhi = std::nextafter(fhi, std::numeric_limits<float>::infinity());
    flo = std::max(flo, inT0);
    fhi = std::min(fhi, inT1);
    if (!(flo < fhi)) return false;
    *t0 = flo;
    *t1 = fhi;
    return true;
}

}  // namespace brume
