#include "brume/integrators/boundary_walk.h"

#include <algorithm>
#include <cmath>

namespace brume {

WalkSegment leaving(Vec3 p, Vec3 ng, Vec3 d, float end, bool endOnSurface, const ShadowTarget& to) {
    WalkSegment s;
    s.o = p;
    s.d = d;
    s.end = end;
    Vec3 q = dot(ng, ng) > 0 ? offsetOrigin(p, ng, d) : p;
    float reach = std::isinf(end) ? end : length(p + d * end - q);
    if (endOnSurface) reach -= rayEpsilon(p + d * end);
    s.query = Ray{q, d, reach};
    s.to = to;
    return s;
}

bool BoundaryWalk::next(BoundaryPiece* piece) {
    if (done_ || crossings_ >= kMaxCrossings) return false;
    if (toggle_ >= 0) media_.toggle(toggle_);  // leave the last piece's boundary behind
    toggle_ = -1;
    entered_ = crossings_;
    *piece = BoundaryPiece{};
    piece->t0 = start_;
    piece->t1 = end_;
    piece->medium = scene_.medium(media_.current());
    piece->index = crossings_;
    if (!(query_.tmin < query_.tmax)) {
        // Nothing left to search (the last boundary lay within its step of the end, or the
        // segment is shorter than its ends' steps): the rest, without a query.
        done_ = true;
        return true;
    }
    ++stats_.rays;
    SurfaceHit hit = scene_.intersect(query_);
    if (!hit.valid() || to_.is(hit)) {
        done_ = true;
        return true;
    }
    // Where the exact segment meets the hit triangle's plane (the same point from either
    // end); along the query's own t if the segment runs in that plane.
    float dn = dot(d_, hit.ng);
    float t = std::abs(dn) > 1e-4f ? dot(hit.p - o_, hit.ng) / dn : dot(hit.p - o_, d_);
    piece->t1 = std::clamp(t, start_, end_);
    piece->hit = hit;
    piece->boundary = hit.mesh >= 0 && scene_.material(hit.mesh).kind == MaterialKind::Invisible;
    if (!piece->boundary) {
        done_ = true;
        return true;
    }
    toggle_ = scene_.mesh(hit.mesh).interiorMedium;
    ++crossings_;
    start_ = piece->t1;
    query_.tmin = hit.t + rayEpsilon(hit.p);
    return true;
}

}  // namespace brume
