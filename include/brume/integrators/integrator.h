// An integrator estimates the radiance reaching the camera through one film position.
#pragma once
#include <cstdint>
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

class Scene;

// Per-thread counters, summed by the renderer for the summary line.
struct PathStats {
    uint64_t rays = 0;  // closest-hit and shadow rays traced
};

class Integrator {
public:
    virtual ~Integrator() = default;
    // Radiance estimate through film point (fx, fy) in pixels, top-left origin, for an image
    // of width × height. Uses only `sampler` for randomness.
    virtual Spectrum sample(const Scene& scene, float fx, float fy, int width, int height,
                            Sampler& sampler, PathStats& stats) const = 0;
};

}  // namespace brume
