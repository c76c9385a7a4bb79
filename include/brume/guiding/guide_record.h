// One training sample for path guiding: a direction a camera walk took at a medium vertex,
// and the radiance the rest of its path brought back along it (docs/path-guiding.md).
#pragma once
#include <cstdint>

#include "brume/math/vec3.h"

namespace brume {

struct GuideRecord {
    Vec3 p;             // the vertex
    Vec3 wIn;           // the propagation direction that reached it (the camera walk's ray)
    Vec3 wi;            // the direction it continued in
    float g = 0;        // the medium's anisotropy there
    float pdf = 0;      // the density wi was sampled with (guided mixture or phase alone)
    float radiance = 0; // incident radiance estimate L_i(p, wi), the channel mean
    // Where it came from, for a fixed order whatever thread made it: the pixel and the
    // vertex's index on the path.
    uint32_t pixel = 0;
    uint32_t vertex = 0;
};

}  // namespace brume
