// The one place that steps a ray through invisible (index-matched) medium boundaries. A walk
// follows a segment between exact points (a vertex's own position, not one pushed off its
// surface) and cuts it into pieces [t0, t1], each in one medium (or vacuum). Surfaces are
// found with a query ray that may start a little off the start's surface (so as not to hit
// it) and stop a little short of the end's; a piece ends where the exact segment crosses the
// plane of the boundary triangle the query hit. After a boundary the walk toggles its medium
// and moves the query's t-near past the hit, keeping its origin. Piece lengths therefore add
// up to the distance between the two exact points, and a crossing is found at the same place
// from either end: an edge's free-flight densities are the same both ways, whichever
// strategy asks.
#pragma once
#include <algorithm>
#include <cmath>

#include "brume/integrators/integrator.h"
#include "brume/scene/scene.h"

namespace brume {

// What a shadow ray or connection aims at: a triangle (mesh, triangle) or a sphere light. A
// hit on it counts as arriving, not as a blocker, so rounding in the distance cannot make a
// surface shadow itself.
struct ShadowTarget {
    int mesh = -1, triangle = -1;
    int sphereLight = -1;
    bool is(const SurfaceHit& h) const {
        return (sphereLight >= 0 && h.sphereLight == sphereLight) ||
               (mesh >= 0 && h.mesh == mesh && h.triangle == triangle);
    }
};

// The segment o + t·d, t in [0, end] (end = +∞: a ray), d unit, and the query ray that looks
// for surfaces along it (parallel, its own t; tmax stops short of a surface at the end). A
// hit on `to` (the end's own triangle or sphere) counts as arriving, not as a blocker.
struct WalkSegment {
    Vec3 o, d;
    float end = kInfinity;
    Ray query;
    ShadowTarget to;
};

// Origin offset off a surface towards the side that direction d leaves into.
inline Vec3 offsetOrigin(Vec3 p, Vec3 ng, Vec3 d) {
    float eps = rayEpsilon(p);
    return p + ng * (dot(ng, d) >= 0 ? eps : -eps);
}

// The segment leaving p in direction d over [0, end]: from a surface with geometric normal ng
// (zero: not on a surface, e.g. a medium point, a point light or the pinhole); endOnSurface:
// the end is on a surface (its primitive `to`), which the query stops short of.
inline WalkSegment leaving(const Vec3& p, const Vec3& ng, const Vec3& d, float end = kInfinity,
                           bool endOnSurface = false, const ShadowTarget& to = ShadowTarget{}) {
    WalkSegment s;
    s.o = p;
    s.d = d;
    s.end = end;
    Vec3 q = dot(ng, ng) > 0 ? offsetOrigin(p, ng, d) : p;
    // The query runs parallel to the segment: its t opposite the end is end − (q − p)·d.
    float reach = end;
    if (!std::isinf(end)) {
        reach = end - dot(q - p, d);
        if (endOnSurface) reach -= rayEpsilon(p + d * end);
    }
    s.query = Ray{q, d, reach};
    s.to = to;
    return s;
}

struct BoundaryPiece {
    float t0 = 0, t1 = 0;            // along the segment; t1 = the surface hit or the segment's end
    const Medium* medium = nullptr;  // the medium the piece lies in (null: vacuum)
    int index = 0;                   // 0 for the piece that starts at the ray's origin
    SurfaceHit hit;                  // the surface ending the piece (invalid: the segment's end or escape)
    bool boundary = false;           // that surface is an invisible boundary: another piece follows
};

class BoundaryWalk {
public:
    // Along the segment, starting in `media`. Each intersection query is counted in stats.
    BoundaryWalk(const Scene& scene, const WalkSegment& seg, const MediumStack& media, PathStats& stats)
        : scene_(scene), o_(seg.o), d_(seg.d), end_(seg.end), query_(seg.query), media_(media), stats_(stats),
          to_(seg.to) {}

    // The next piece; false once the last one (ended by a surface other than an invisible
    // boundary, by the segment's end, or by escaping) has been given, or after 64 crossings (a
    // pathological stack of boundaries, to be treated as blocked: see exhausted()).
    inline bool next(BoundaryPiece* piece);

    // The media of the last piece given (its end's boundary not yet crossed).
    const MediumStack& media() const { return media_; }
    // Whether a piece past an invisible boundary has been given (the walk went through one).
    bool crossed() const { return entered_ > 0; }
    bool exhausted() const { return crossings_ >= kMaxCrossings; }

private:
    static constexpr int kMaxCrossings = 64;
    const Scene& scene_;
    Vec3 o_, d_;
    float end_;  // where the last piece ends
    Ray query_;  // tmin/tmax: the range still to search
    MediumStack media_;
    PathStats& stats_;
    ShadowTarget to_;
    float start_ = 0;  // where the next piece begins
    int crossings_ = 0;
    int toggle_ = -1;
    int entered_ = 0;  // index of the last piece given  // the medium the last piece's boundary toggles, applied by next()
    bool done_ = false;
};

// Inline: it runs for every ray, and its pieces stay in registers.
inline bool BoundaryWalk::next(BoundaryPiece* piece) {
    if (done_ || crossings_ >= kMaxCrossings) return false;
    if (toggle_ >= 0) media_.toggle(toggle_);  // leave the last piece's boundary behind
    toggle_ = -1;
    entered_ = crossings_;
    piece->t0 = start_;
    piece->medium = scene_.medium(media_.current());
    piece->index = crossings_;
    piece->boundary = false;
    if (!(query_.tmin < query_.tmax)) {
        // Nothing left to search (the last boundary lay within its step of the end, or the
        // segment is shorter than its ends' steps): the rest, without a query.
        piece->t1 = end_;
        piece->hit = SurfaceHit{};
        done_ = true;
        return true;
    }
    ++stats_.rays;
    piece->hit = scene_.intersect(query_);
    const SurfaceHit& hit = piece->hit;
    if (!hit.valid() || to_.is(hit)) {
        piece->hit = SurfaceHit{};
        piece->t1 = end_;
        done_ = true;
        return true;
    }
    piece->boundary = hit.mesh >= 0 && scene_.material(hit.mesh).kind == MaterialKind::Invisible;
    if (!piece->boundary) {
        // A surface ends the walk here: the query's distance to it.
        piece->t1 = std::clamp(hit.t + dot(query_.o - o_, d_), start_, end_);
        done_ = true;
        return true;
    }
    // Where the exact segment meets the boundary triangle's plane (the same point from either
    // end); along the query's own t if the segment runs in that plane.
    float dn = dot(d_, hit.ng);
    float t = std::abs(dn) > 1e-4f ? dot(hit.p - o_, hit.ng) / dn : hit.t + dot(query_.o - o_, d_);
    piece->t1 = std::clamp(t, start_, end_);
    toggle_ = scene_.mesh(hit.mesh).interiorMedium;
    ++crossings_;
    start_ = piece->t1;
    query_.tmin = hit.t + rayEpsilon(hit.p);
    return true;
}

}  // namespace brume
