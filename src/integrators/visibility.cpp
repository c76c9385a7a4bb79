#include "brume/integrators/visibility.h"

#include "brume/sampling/free_flight.h"

namespace brume {

ShadowTarget lightTarget(const Scene& scene, int index) {
    ShadowTarget t;
    const Light& l = scene.lights()[index];
    if (l.kind == LightKind::Sphere) t.sphereLight = index;
    if (l.kind == LightKind::Triangle) t.mesh = l.mesh, t.triangle = l.triangle;
    return t;
}

Spectrum transmittanceAlong(const Scene& scene, Vec3 o, Vec3 d, float dist, MediumStack media,
                            const ShadowTarget& target, PathStats& stats) {
    if (!scene.hasInvisibleBoundaries()) {
        // Nothing to pass through: one medium all the way, one occlusion query (skipped when
        // the medium alone already absorbs everything, as over an infinite distance).
        const Medium* m = scene.medium(media.current());
        Spectrum T = m ? transmittance(m->sigmaT(), dist) : Spectrum(1.0f);
        if (isBlack(T)) return T;
        ++stats.rays;
        if (target.mesh < 0) return scene.occluded(Ray{o, d, dist}, target.sphereLight) ? Spectrum(0.0f) : T;
        // Towards an emissive triangle, a hit on that triangle is arrival, not a blocker:
        // shortening the distance by an epsilon does not keep a grazing or degenerate
        // triangle's own plane out of reach, so ask for the closest hit and compare.
        SurfaceHit hit = scene.intersect(Ray{o, d, dist});
        return hit.valid() && !target.is(hit) ? Spectrum(0.0f) : T;
    }
    Spectrum T(1.0f);
    float remaining = dist;
    for (int crossings = 0; crossings < 64; ++crossings) {
        ++stats.rays;
        SurfaceHit hit = scene.intersect(Ray{o, d, remaining});
        if (hit.valid() && target.is(hit)) hit = SurfaceHit{};
        const Medium* m = scene.medium(media.current());
        float segment = hit.valid() ? hit.t : remaining;
        if (m) T *= transmittance(m->sigmaT(), segment);
        if (!hit.valid()) return T;
        if (hit.mesh < 0 || scene.material(hit.mesh).kind != MaterialKind::Invisible) return Spectrum(0.0f);
        if (isBlack(T)) return T;
        int interior = scene.mesh(hit.mesh).interiorMedium;
        if (interior >= 0) media.toggle(interior);
        float eps = rayEpsilon(hit.p);
        o = hit.p + d * eps;
        remaining -= hit.t + eps;
        if (!(remaining > 0)) return T;
    }
    return Spectrum(0.0f);  // pathological stack of boundaries: treat as blocked
}

}  // namespace brume

namespace brume {

Connection connectPoints(const Scene& scene, Vec3 o, Vec3 d, float dist, MediumStack media, bool aIsMedium,
                         bool bIsMedium, const ShadowTarget& target, PathStats& stats) {
    Connection c;
    // Per sub-segment (between invisible boundaries) in medium σt over length ℓ:
    //   pass = avg_c e^(−σt,c ℓ), scatter = avg_c σt,c e^(−σt,c ℓ).
    // The first sub-segment touches a, the last touches b.
    Spectrum T(1.0f);
    double toB = 1, toA = 1;
    float remaining = dist;
    bool first = true;
    auto account = [&](const Medium* m, float len, bool last) {
        if (!m) return;
        Spectrum sigmaT = m->sigmaT();
        T *= transmittance(sigmaT, len);
        double pass = freeFlightPdfPass(sigmaT, len);
        toB *= last && bIsMedium ? freeFlightPdfScatter(sigmaT, len) : pass;
        toA *= first && aIsMedium ? freeFlightPdfScatter(sigmaT, len) : pass;
    };
    for (int crossings = 0; crossings < 64; ++crossings) {
        ++stats.rays;
        SurfaceHit hit = scene.intersect(Ray{o, d, remaining});
        if (hit.valid() && target.is(hit)) hit = SurfaceHit{};
        const Medium* m = scene.medium(media.current());
        if (!hit.valid()) {
            account(m, remaining, true);
            c.T = T;
            c.freeFlightToB = toB;
            c.freeFlightToA = toA;
            return c;
        }
        if (hit.mesh < 0 || scene.material(hit.mesh).kind != MaterialKind::Invisible) return c;  // blocked
        account(m, hit.t, false);
        if (isBlack(T)) return c;
        int interior = scene.mesh(hit.mesh).interiorMedium;
        if (interior >= 0) media.toggle(interior);
        float eps = rayEpsilon(hit.p);
        o = hit.p + d * eps;
        remaining -= hit.t + eps;
        first = false;
        c.crossed = true;
        if (!(remaining > 0)) {
            c.T = T;
            c.freeFlightToB = toB;
            c.freeFlightToA = toA;
            return c;
        }
    }
    return c;
}

}  // namespace brume
