#include "brume/scene/camera.h"

namespace brume {

Ray Camera::generateRay(float fx, float fy, int width, int height) const {
    float tanY = std::tan(0.5f * yfov);
    float tanX = tanY * float(width) / float(height);
    float sx = (2.0f * fx / float(width) - 1.0f) * tanX;
    float sy = (1.0f - 2.0f * fy / float(height)) * tanY;
    return Ray{position, normalize(forward + right * sx + up * sy), kInfinity};
}

}  // namespace brume
