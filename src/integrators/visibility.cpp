#include "brume/integrators/visibility.h"

namespace brume {

ShadowTarget lightTarget(const Scene& scene, int index) {
    ShadowTarget t;
    const Light& l = scene.lights()[index];
    if (l.isPlanar()) t.mesh = l.mesh, t.triangle = l.triangle;  // a hit on its triangle arrives
    else if (l.hasSurface()) t.sphereLight = index;
    return t;
}

Spectrum transmittanceAlong(const Scene& scene, const WalkSegment& seg, const MediumStack& media, PathStats& stats) {
    const Ray ray{seg.o, seg.d, seg.end};
    const ShadowTarget& target = seg.to;
    if (!scene.hasInvisibleBoundaries()) {
        // Nothing to pass through: one medium all the way, one occlusion query (skipped when
        // the medium alone already absorbs everything, as over an infinite distance).
        const Medium* m = scene.medium(media.current());
        Spectrum T = m ? m->transmittance(ray, 0.0f, seg.end) : Spectrum(1.0f);
        if (isBlack(T)) return T;
        ++stats.rays;
        if (target.mesh < 0) return scene.occluded(seg.query, target.sphereLight) ? Spectrum(0.0f) : T;
        // Towards an emissive triangle, a hit on that triangle is arrival, not a blocker:
        // shortening the distance by an epsilon does not keep a grazing or degenerate
        // triangle's own plane out of reach, so ask for the closest hit and compare.
        SurfaceHit hit = scene.intersect(seg.query);
        return hit.valid() && !target.is(hit) ? Spectrum(0.0f) : T;
    }
    Spectrum T(1.0f);
    BoundaryWalk walk(scene, seg, media, stats);
    BoundaryPiece piece;
    while (walk.next(&piece)) {
        if (piece.medium) T *= piece.medium->transmittance(ray, piece.t0, piece.t1);
        if (piece.hit.valid() && !piece.boundary) return Spectrum(0.0f);  // blocked
        if (isBlack(T)) return T;
    }
    return walk.exhausted() ? Spectrum(0.0f) : T;
}

// Per piece in medium m: pass = avg_c e^(−σt,c ℓ), scatter = avg_c σt,c e^(−σt,c ℓ) for a
// homogeneous medium (Medium::transit). The first piece touches a, the last touches b.
Connection connectPoints(const Scene& scene, const WalkSegment& seg, const MediumStack& media, bool aIsMedium,
                         bool bIsMedium, PathStats& stats) {
    const Ray ray{seg.o, seg.d, seg.end};
    Connection c;
    if (!scene.hasInvisibleBoundaries() && seg.to.mesh < 0) {
        // One medium all the way and no triangle to arrive on: an any-hit query decides, and
        // the one piece [0, end] gives the same numbers the walk below would.
        if (seg.query.tmin < seg.query.tmax) {
            ++stats.rays;
            if (scene.occluded(seg.query, seg.to.sphereLight)) return Connection{};
        }
        if (const Medium* m = scene.medium(media.current())) {
            MediumTransit tr = m->transit(ray, 0.0f, seg.end, aIsMedium, bIsMedium);
            c.T = tr.T;
            c.freeFlightToB = tr.fwd;
            c.freeFlightToA = tr.rev;
        } else {
            c.T = Spectrum(1.0f);
        }
        return c;
    }
    Spectrum T(1.0f);
    Channels toB, toA;
    BoundaryWalk walk(scene, seg, media, stats);
    BoundaryPiece piece;
    while (walk.next(&piece)) {
        if (piece.hit.valid() && !piece.boundary) return Connection{};  // blocked
        bool last = !piece.boundary;
        if (piece.medium) {
            MediumTransit tr = piece.medium->transit(ray, piece.t0, piece.t1, piece.index == 0 && aIsMedium,
                                                     last && bIsMedium);
            T *= tr.T;
            toB *= tr.fwd;
            toA *= tr.rev;
        }
        // A black T (absorbed, or rounded to zero far out) still walks on: the densities are
        // exact whatever the transmittance.
    }
    if (walk.exhausted()) return Connection{};
    c.T = T;
    c.freeFlightToB = toB;
    c.freeFlightToA = toA;
    c.crossed = walk.crossed();
    return c;
}

}  // namespace brume
