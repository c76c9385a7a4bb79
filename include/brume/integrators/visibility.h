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

// What a shadow ray aims at: a triangle (mesh, triangle) or a sphere light. A hit on it
// counts as arriving, not as a blocker, so rounding in the distance (which grows with every
// invisible boundary crossed) cannot make a surface shadow itself.
struct ShadowTarget {
    int mesh = -1, triangle = -1;
    int sphereLight = -1;
    bool is(const SurfaceHit& h) const {
        return (sphereLight >= 0 && h.sphereLight == sphereLight) ||
               (mesh >= 0 && h.mesh == mesh && h.triangle == triangle);
    }
};

// The target of a shadow ray towards light `index` (its triangle or sphere; none for point,
// spot and directional lights).
ShadowTarget lightTarget(const Scene& scene, int index);

// Transmittance from o along unit d over distance dist (+∞ allowed), starting in `media`.
// Zero if anything but an invisible boundary or the target lies in between. Each ray traced
// is counted in stats.
Spectrum transmittanceAlong(const Scene& scene, Vec3 o, Vec3 d, float dist, MediumStack media,
                            const ShadowTarget& target, PathStats& stats);

}  // namespace brume

namespace brume {

// A connection between two path vertices a and b: the transmittance between them and the
// free-flight densities with which a walk from a would stop at b (and from b at a): the
// product of the pass probabilities of every medium crossed, except that a medium point at
// the end contributes its scattering density instead.
struct Connection {
    Spectrum T{0.0f};
    double freeFlightToB = 1;  // walk a → b stops at b
    double freeFlightToA = 1;  // walk b → a stops at a
    bool crossed = false;     // passed through an invisible boundary
};

// o: the origin already offset off a's surface if a is one; d unit; dist the distance to b
// (shortened so as not to hit b's own surface). aIsMedium/bIsMedium: whether the ends are
// medium points. Blocked or fully absorbed: T = 0.
Connection connectPoints(const Scene& scene, Vec3 o, Vec3 d, float dist, MediumStack media, bool aIsMedium,
                         bool bIsMedium, const ShadowTarget& target, PathStats& stats);

}  // namespace brume
