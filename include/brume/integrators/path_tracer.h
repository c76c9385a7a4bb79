// The volumetric path tracer (`--integrator pt`): free-flight sampling in every medium
// (homogeneous or grid, grey or coloured), next-event estimation from surface and medium
// vertices MIS-combined (power heuristic) with BSDF/phase sampling, and equi-angular light
// connections on medium segments (`--connect`). It is the reference every other method is
// tested against.
#pragma once
#include "brume/integrators/integrator.h"

namespace brume {

// How light is connected to medium segments (docs/path-tracer.md):
//  Density:     next-event estimation from the free-flight scatter point;
//  EquiAngular: from a point sampled equi-angularly towards the light on each segment
//               (directional lights keep the free-flight point);
//  Product:     the same, the point sampled by equi-angular × phase (product sampling,
//               equiangular.h) in anisotropic media;
//  Mis:         free-flight and product points, weighted by the power heuristic together
//               with phase sampling.
enum class ConnectMode { Density, EquiAngular, Product, Mis };

// Whether the equi-angular (or product) point replaces the free-flight one.
inline bool variantOnly(ConnectMode m) { return m == ConnectMode::EquiAngular || m == ConnectMode::Product; }

// The anisotropy that equi-angular sampling in a medium of anisotropy g takes into its
// product: g for product and mis, 0 (plain equi-angular) otherwise.
inline float connectAnisotropy(ConnectMode m, float g) {
    return m == ConnectMode::Product || m == ConnectMode::Mis ? g : 0.0f;
}

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
