// Shadow rays and connections in a scene with media: the transmittance along a segment (and
// the free-flight densities of the walks that would cross it), passing through invisible
// medium boundaries (boundary_walk.h) and stopping at anything else. Media answer through
// Medium::transit.
#pragma once
#include "brume/integrators/boundary_walk.h"

namespace brume {

// The target of a shadow ray towards light `index` (its triangle or sphere; none for point,
// spot and directional lights).
ShadowTarget lightTarget(const Scene& scene, int index);

// Transmittance along the segment (its end +∞ allowed), starting in `media`. Zero if anything
// but an invisible boundary or the segment's target lies in between. Each ray traced is
// counted in stats.
Spectrum transmittanceAlong(const Scene& scene, const WalkSegment& seg, const MediumStack& media, PathStats& stats);

// A connection between two path vertices a and b: the transmittance between them and the
// free-flight densities with which a walk from a would stop at b (and from b at a): the
// product of the pass probabilities of every medium crossed, except that a medium point at
// the end contributes its scattering density instead.
struct Connection {
    Spectrum T{0.0f};
    Channels freeFlightToB;   // walk a → b stops at b (per colour channel)
    Channels freeFlightToA;   // walk b → a stops at a
    bool crossed = false;     // passed through an invisible boundary
};

// The segment from a to b (leaving(), exact ends); aIsMedium/bIsMedium: whether the ends are
// medium points. Blocked: T = 0 and no densities; fully absorbed: T = 0, densities exact.
Connection connectPoints(const Scene& scene, const WalkSegment& seg, const MediumStack& media, bool aIsMedium,
                         bool bIsMedium, PathStats& stats);

}  // namespace brume
