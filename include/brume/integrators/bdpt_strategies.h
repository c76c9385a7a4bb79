// The strategies of the bidirectional tracer, one function each (docs/mis.md). A strategy
// (s, t) joins the light subpath's first s vertices y0 … y(s−1) with the camera subpath's
// first t vertices z0 … z(t−1):
//   s = 0        the camera subpath reached an emitter by itself;
//   s = 1        light connection: a fresh light sample joined to z(t−1);
//   t = 1        camera connection: y(s−1) joined to the pinhole, splatted (light tracing);
//   s, t ≥ 2     a deterministic connection between y(s−1) and z(t−1).
// Each but s = 0 comes in two variants: free flight (the subpaths' own vertices) and, with
// --connect equiangular|mis, equi-angular (z(t−1), or for t = 1 y(s−1), moved along the ray
// its walk traced towards the other subpath). Every function returns the weighted estimate of
// both variants; the weights come from strategyWeight (bdpt_mis.h).
#pragma once
#include "brume/integrators/bdpt.h"
#include "brume/integrators/allocation_statistics.h"
#include "brume/integrators/bdpt_mis.h"
#include "brume/integrators/direct_light_tracing.h"
#include "brume/integrators/emitter_crossing.h"

namespace brume {

// Everything a strategy reads: the two subpaths of this sample (their MIS sums in their
// vertices), and where its numbers come from.
struct StrategyContext {
    const Scene& scene;
    const BdptOptions& options;
    MisSettings mis;
    PathVertex* camera;
    int nCamera;
    PathVertex* light;
    int nLight;
    bool weighted;  // false: unweighted (BdptOptions::onlyS without `weighted`)
    const Sampler& sampler;
    PathStats& stats;
    int width, height;
    // Non-null while the efficiency-aware tracer gathers statistics: every weighted
    // contribution is recorded there too (allocation_statistics.h).
    std::vector<WeightRecord>* records = nullptr;
    // Non-null in direct_light_tracing.h's learning passes: contributions to one-event paths
    // go there too, weighted as if their family were alone (light tracing's to its image,
    // the camera side's summed into *directCamera, which the sample hands over).
    DirectLightTracing* direct = nullptr;
    Spectrum* directCamera = nullptr;
    // What each technique adds to the sample's own pixel (--stats, technique_sums.h).
    TechniqueSample* techniques = nullptr;
    // auto's partial pilot pass (AllocationPlanner::partialAt), at a pixel that does not
    // record: its light subpath's camera connections reach only the recording pixels (the
    // others' values of that pass are left out of the image), so no ray is traced for the rest.
    bool recordingPixelsOnly = false;
};

// What the camera walk's rays gathered from emissive media (PathVertex::edgeEmission), the
// ghost ray after its last vertex included: weight 1 over the strategies, since no other
// strategy makes these paths (counted with the emitter hits in --stats).
Spectrum mediumEmission(const StrategyContext& c);
// Next-event estimation towards the volume lights (volume_light_sampling.h) from the camera
// vertices 1 … upTo that are not specular, each MIS-weighted against what the camera walk's
// next ray gathers (the only other strategy that makes these paths; grey scenes only).
Spectrum volumeLightConnections(const StrategyContext& c, int upTo);
Spectrum emitterHit(const StrategyContext& c, int t);
// The emission of a transparent emitter the camera walk crossed (emitter_crossing.h), as the
// emitter hit s = 0 of the path that ends there.
Spectrum crossedEmitterHit(const StrategyContext& c, const CrossingVertex& x);
Spectrum lightConnection(const StrategyContext& c, int t);
void cameraConnection(const StrategyContext& c, int s, SplatList& splats);
Spectrum subpathConnection(const StrategyContext& c, int s, int t);

}  // namespace brume
