// An allocation: which strategies the bidirectional tracer makes per sample, and how often
// (the sample counts n_k of its MIS weights). The efficiency-aware tracer
// (allocation_planner.h) chooses one of the candidates below from pilot statistics; the fixed
// `--integrator bdpt` runs BdptOptions' own (everything on, general connections with
// probability 1/4).
#pragma once
#include <string>
#include <vector>

#include "brume/integrators/path_tracer.h"

namespace brume {

// The weights count each strategy as often as it is made, so every allocation is unbiased
// wherever its strategies cover the paths.
struct BdptAllocation {
    // One light subpath per sample, or none (then no camera or general connection is made: a
    // path tracer with the s = 0 and s = 1 strategies).
    bool lightSubpaths = true;
    bool lightTracing = true;  // camera connections t = 1 (needs light subpaths)
    // Probability with which each general connection (s, t ≥ 2) is made (probabilistic
    // connections: a made one counts 1/p, and the weights see every general strategy's
    // density times p). 1: every pair of subpath vertices is joined. 1/4 was more efficient
    // than 1 on 12 of the 14 bench scenes, for --connect density and mis (docs/results.md).
    float generalConnection = 0.25f;
    // The equi-angular variants of light (s = 1) and camera (t = 1) connections (with
    // --connect mis|equiangular).
    bool equiAngularLight = true;
    bool equiAngularCamera = true;
    // Where a light or camera connection's equi-angular variant is on and could make the
    // connection vertex (a medium vertex whose edge crossed no boundary), it replaces the
    // free-flight variant instead of adding to it, as --connect equiangular does (there the
    // free-flight variant adds its variance and its rays to a nearly exact technique).
    bool equiAngularOnly = false;
    // The volumetric path tracer itself (`pt`, with --connect mis or density) instead of the
    // bidirectional tracer without light subpaths: the same strategies, at less cost per
    // sample. To the statistics it is "pt+ea" (or "pt"); to the cost model, that times
    // kPathTracerCost.
    bool pathTracer = false;

    // Short and stable, e.g. "pt+ea" or "bdpt lt p=0.25 ea=LC" ("ea-only=LC" with
    // equiAngularOnly); used in reports and by --allocation.
    std::string name() const;
    bool operator==(const BdptAllocation& o) const;
};

// The pilot: every strategy on, so that the statistics see every path any candidate could make.
BdptAllocation pilotAllocation();

// The candidates for a connect mode (density: no equi-angular variants), the pilot among them.
//   no light subpaths:  equi-angular light connections on or off                      (2)
//                       the path tracer                                                (1)
//   light subpaths:     light tracing on:  p ∈ {0, 1/4, 1} × ea light × ea camera      (12)
//                       light tracing off: p ∈ {1/4, 1} × ea light                      (4)
//   and each one with an equi-angular variant on, with it alone (equiAngularOnly)     (12)
std::vector<BdptAllocation> candidateAllocations(ConnectMode connect);

// The candidate named `name` (BdptAllocation::name); false if none is.
bool allocationNamed(const std::string& name, ConnectMode connect, BdptAllocation* out);

}  // namespace brume
