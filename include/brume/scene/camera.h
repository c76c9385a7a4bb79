// Pinhole camera looking down its local −Z, +Y up. Pixel (0,0) is the top-left pixel.
#pragma once
#include "brume/math/ray.h"

namespace brume {

struct Camera {
    Vec3 position;
    Vec3 right{1, 0, 0}, up{0, 1, 0}, forward{0, 0, -1};  // world-space, orthonormal
    float yfov = 0.8f;          // vertical field of view [rad]
    float aspectRatio = 0;      // glTF aspectRatio; 0 when absent

    // Primary ray through film position (fx, fy) in pixels, image of width × height.
    Ray generateRay(float fx, float fy, int width, int height) const;
};

}  // namespace brume
