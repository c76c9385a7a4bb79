// Shadow rays in a scene with media: the transmittance along a segment, passing through
// invisible (index-matched) medium boundaries and stopping at anything else.
#pragma once
#include "brume/integrators/integrator.h"
#include "brume/scene/scene.h"

namespace brume {

// Origin offset off a surface towards the side that direction d leaves into.
inline Vec3 offsetOrigin(Vec3 p, Vec3 ng, Vec3 d) {
    float eps = rayEpsilon(p);
    return p + ng * (dot(ng, d) >= 0 ? eps : -eps);
}

// Transmittance from o along unit d over distance dist (+∞ allowed), starting in `media`.
// Zero if a surface other than an invisible boundary, or a sphere light other than
// ignoreLight, lies in between. Each ray traced is counted in stats.
Spectrum transmittanceAlong(const Scene& scene, Vec3 o, Vec3 d, float dist, MediumStack media,
                            int ignoreLight, PathStats& stats);

}  // namespace brume
