// The volumetric path tracer (`--integrator pt`): free-flight sampling in homogeneous media,
// next-event estimation from surface and medium vertices MIS-combined (power heuristic) with
// BSDF/phase sampling. It is the reference every other method is tested against.
#pragma once
#include "brume/integrators/integrator.h"

namespace brume {

struct PathTracerOptions {
    int maxDepth = -1;                // most scattering events on a path; −1 = unlimited
    bool nextEventEstimation = true;  // false: pure BSDF/phase sampling (for the tests)
};

class PathTracer : public Integrator {
public:
    explicit PathTracer(PathTracerOptions options) : options_(options) {}
    Spectrum sample(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                    PathStats& stats) const override;

private:
    PathTracerOptions options_;
};

}  // namespace brume
