// The volumetric path tracer (`--integrator pt`): free-flight sampling in homogeneous media,
// next-event estimation from surface and medium vertices MIS-combined (power heuristic) with
// BSDF/phase sampling, and equi-angular light connections on medium segments
// (`--connect`). It is the reference every other method is tested against.
#pragma once
#include "brume/integrators/integrator.h"

namespace brume {

// How light is connected to medium segments (docs/path-tracer.md):
//  Density:     next-event estimation from the free-flight scatter point;
//  EquiAngular: from a point sampled equi-angularly towards the light on each segment
//               (directional lights keep the free-flight point);
//  Mis:         both, weighted by the power heuristic together with phase sampling.
enum class ConnectMode { Density, EquiAngular, Mis };

struct PathTracerOptions {
    int maxDepth = -1;                // most scattering events on a path; −1 = unlimited
    bool nextEventEstimation = true;  // false: pure BSDF/phase sampling (for the tests)
    ConnectMode connect = ConnectMode::Mis;
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
