#include "brume/integrators/volume_light_sampling.h"

#include <cmath>

#include "brume/scene/density_grid.h"
#include "brume/scene/grid_tracking.h"

namespace brume {

bool connectVolumeLight(const Scene& scene, Vec3 x, Vec3 ng, const MediumStack& media, const Sampler& sampler,
                        uint32_t dims, PathStats& stats, VolumeLightConnection* out) {
    const VolumeLights& lights = scene.volumeLights();
    if (lights.empty()) return false;
    const Sample2 uv = sampler.get2D(dims + dim::kLightPoint);
    VolumeLightSample s;
    if (!lights.sample(sampler.get1D(dims + dim::kPick), Vec3(uv.u, uv.v, sampler.get1D(dims + dim::kAnchor)), &s))
        return false;
    const Medium& medium = *scene.medium(s.medium);
    const Spectrum e = medium.emissionAt(s.p);
    if (isBlack(e)) return false;
    Vec3 d = s.p - x;
    const float dist = length(d);
    if (!(dist > 0)) return false;
    d = d / dist;
    // The shadow ray, piece by piece: y counts only if the walk arrives inside y's medium
    // (its bounding mesh holds y, and no other medium fills that space).
    const WalkSegment seg = leaving(x, ng, d, dist);
    const Ray ray{seg.o, seg.d, seg.end};
    Spectrum T(1.0f);
    BoundaryWalk walk(scene, seg, media, stats);
    BoundaryPiece piece;
    while (walk.next(&piece)) {
        if (piece.medium) T *= piece.medium->transmittance(ray, piece.t0, piece.t1);
        if ((piece.hit.valid() && !piece.boundary) || isBlack(T)) return false;
    }
    if (walk.exhausted() || walk.media().current() != s.medium) return false;
    // ℓ: y's stratum of the ray's interval in its brick, as the gathering along this ray
    // would draw it (Medium::emitted).
    const grid::LocalRay lr = grid::toLocal(medium.emissionGrid, Ray{x, d});
    float a, z;
    if (!medium.emissionGrid.grid->brickInterval(s.brick, lr.q0, lr.dq, &a, &z)) return false;
    out->wi = d;
    out->Le = e * T / (dist * dist * s.pdf);
    out->pdf = s.pdf;
    out->dist = dist;
    out->stratumLength = (z - a) / float(medium.emissionStrata());
    return isFinite(out->Le);
}

}  // namespace brume
