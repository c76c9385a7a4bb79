// Equi-angular sampling on a path's medium segment towards a light (Kulla & Fajardo 2012),
// with the segment clipped to where the light can reach: a spot light's cone, a one-sided
// emitter's front half-space. Clipping only ever removes points whose contribution is zero,
// so the estimator stays unbiased; it just wastes no samples there.
#pragma once
#include "brume/sampling/equiangular.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/light_geometry.h"
#include "brume/scene/medium.h"

namespace brume {

class Scene;

// The part of a ray that lies in one medium: o + t·d for t in [0, tEnd), tEnd = +∞ allowed.
struct MediumSegment {
    Vec3 o, d;
    float tEnd = 0;
    const Medium* medium = nullptr;
};

// Set up equi-angular sampling on seg towards anchor, clipped for the light; false if the
// clipped segment is empty (no point on it can receive light). g ≠ 0: product sampling with
// that anisotropy (connectAnisotropy).
bool equiAngularTowards(const Light& light, Vec3 anchor, const MediumSegment& seg, float g,
                        EquiAngular* out);

// The part [*t0, *t1) of seg that the light can reach (clipRayToLight, light_geometry.h).
bool clipToLight(const Light& light, const MediumSegment& seg, float* t0, float* t1);

}  // namespace brume
