// One training sample for path guiding: a direction a camera walk took at a medium or
// surface vertex, and the radiance the rest of its path brought back along it
// (docs/path-guiding.md).
#pragma once
#include <cstdint>

#include "brume/math/vec3.h"

namespace brume {

struct GuideRecord {
    Vec3 p;             // the vertex
    Vec3 wIn;           // the propagation direction that reached it (the camera walk's ray)
    Vec3 wi;            // the direction it continued in
    float g = 0;        // the medium's anisotropy there (0 at a surface)
    float pdf = 0;      // the density wi was sampled with (guided mixture or unguided alone)
    float radiance = 0; // incident radiance estimate L_i(p, wi), the channel mean
    float scatter = 0;  // the phase function, or f·|cos θ| (channel mean), at wi
    float unguided = 0; // the unguided technique's density at wi (phase or BSDF sampling)
    uint32_t surface = 0;  // 1: a surface vertex
    // Where it came from, for a fixed order whatever thread made it: the pixel and the
    // vertex's index on the path.
    uint32_t pixel = 0;
    uint32_t vertex = 0;
    float count = 1;    // how many walks it stands for (records that saw no light are kept one in 8)
    // At a medium vertex, what its next-event estimate gathered per unit of throughput (the
    // channel mean, MIS-weighted): with scatter·radiance/pdf, all the vertex brought back.
    float direct = 0;
};
// Compared by its bytes for a total order (path_guide.cpp): no padding.
static_assert(sizeof(GuideRecord) == 19 * 4, "GuideRecord has padding");

}  // namespace brume
