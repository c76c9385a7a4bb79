#include "brume/integrators/boundary_walk.h"

#include <algorithm>
#include <cmath>

namespace brume {

bool BoundaryWalk::next(BoundaryPiece* piece) {
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
