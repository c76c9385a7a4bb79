// An allocation: which strategies the bidirectional tracer makes per sample, and how often
// (the sample counts n_k of its MIS weights). The efficiency-aware tracer
// (allocation_planner.h) chooses one of the candidates below from pilot statistics; the fixed
// `--integrator bdpt` runs BdptOptions' own (everything on, general connections with
// probability 1/4).
#pragma once
#include <string>
#include <vector>

#include "brume/integrators/bdpt.h"

namespace brume {

struct BdptAllocation {
    bool lightSubpaths = true;        // one light subpath per sample, or none (path tracing)
    bool lightTracing = true;         // camera connections t = 1 (needs light subpaths)
    float generalConnection = 0.25f;  // probability of each general connection (s, t ≥ 2)
    bool equiAngularLight = true;     // equi-angular variants of light connections (s = 1)
    bool equiAngularCamera = true;    // equi-angular variants of camera connections (t = 1)
    // The volumetric path tracer itself (`pt`, with --connect mis or density) instead of the
    // bidirectional tracer without light subpaths: the same strategies, at less cost per
    // sample. To the statistics it is "pt+ea" (or "pt"); to the cost model, that times
    // kPathTracerCost.
    bool pathTracer = false;

    // Short and stable, e.g. "pt+ea" or "bdpt lt p=0.25 ea=LC"; used in reports and by
    // --allocation.
    std::string name() const;
    void applyTo(BdptOptions& options) const;
    bool operator==(const BdptAllocation& o) const;
};

// The pilot: every strategy on, so that the statistics see every path any candidate could make.
BdptAllocation pilotAllocation();

// The candidates for a connect mode (density: no equi-angular variants), the pilot among them.
//   no light subpaths:  equi-angular light connections on or off                      (2)
//                       the path tracer                                                (1)
//   light subpaths:     light tracing on:  p ∈ {0, 1/4, 1} × ea light × ea camera      (12)
//                       light tracing off: p ∈ {1/4, 1} × ea light                      (4)
std::vector<BdptAllocation> candidateAllocations(ConnectMode connect);

// The candidate named `name` (BdptAllocation::name); false if none is.
bool allocationNamed(const std::string& name, ConnectMode connect, BdptAllocation* out);

}  // namespace brume
