#include "brume/integrators/equiangular_segment.h"

#include <cmath>

#include "brume/sampling/warp.h"
#include "brume/scene/light_geometry.h"

namespace brume {

bool clipToLight(const Light& light, const MediumSegment& seg, float* t0, float* t1) {
    *t0 = 0;
    *t1 = seg.tEnd;
    return clipRayToLight(light, seg.o, seg.d, t0, t1);
}

bool equiAngularTowards(const Light& light, Vec3 anchor, const MediumSegment& seg, float g,
                        EquiAngular* out) {
    float a, b;
    if (!clipToLight(light, seg, &a, &b)) return false;
    *out = makeEquiAngular(seg.o, seg.d, anchor, a, b, g);
    return true;
}

}  // namespace brume
