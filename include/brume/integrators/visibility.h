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

namespace brume {

// A connection between two path vertices a and b: the transmittance between them and the
// free-flight densities with which a walk from a would stop at b (and from b at a): the
// product of the pass probabilities of every medium crossed, except that a medium point at
// the end contributes its scattering density instead.
struct Connection {
    Spectrum T{0.0f};
    float freeFlightToB = 1;  // walk a → b stops at b
    float freeFlightToA = 1;  // walk b → a stops at a
};

// o: the origin already offset off a's surface if a is one; d unit; dist the distance to b
// (shortened so as not to hit b's own surface). aIsMedium/bIsMedium: whether the ends are
// medium points. Blocked or fully absorbed: T = 0.
Connection connectPoints(const Scene& scene, Vec3 o, Vec3 d, float dist, MediumStack media, bool aIsMedium,
                         bool bIsMedium, int ignoreLight, PathStats& stats);

}  // namespace brume
