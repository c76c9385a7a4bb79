// What a user chooses of an integrator: `brume render`'s and `brume bench`'s flags and the
// tests' methods. Every place that builds an integrator starts from these (makeIntegrator),
// so a flag means the same everywhere.
#pragma once
#include <memory>
#include <string>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"

namespace brume {

enum class IntegratorKind {
    PathTracer,       // `pt`
    Bidirectional,    // `bdpt`
    EfficiencyAware,  // `auto` (the default): the bidirectional tracer choosing its allocation
};

struct IntegratorSettings {
    IntegratorKind kind = IntegratorKind::EfficiencyAware;
    ConnectMode connect = ConnectMode::Mis;
    int maxDepth = -1;  // most scattering events on a path; −1 = unlimited
    // The path tracer: false renders by phase and BSDF sampling alone (tests).
    bool nextEventEstimation = true;
    // Path guiding (`--guiding on`, path_tracer.h and bdpt.h; not with EfficiencyAware).
    bool guiding = false;
    // `--guiding auto` (the command's default; guide_start.h): the path tracer, and auto once
    // it has chosen the path tracer, start a guide where the render is long enough. (The
    // fixed bidirectional tracer does not: its guided camera walk did not pay on the scenes
    // measured, docs/path-guiding.md.)
    bool guidingAuto = false;
    int guidedDistanceDepth = -1;  // the path tracer's guided distances (PathTracerOptions)
    // The path tracer's next-event estimation towards emissive media (`--volume-lights`; also
    // the path tracer inside bdpt and auto).
    bool volumeLights = true;
    // The path tracer with --connect mis learns how often to make its light connections in
    // media (connection_shares.h); false: always both (tests that need fixed weights).
    bool learnShares = true;
    // The passes the render will take, where known in advance (`--spp` without `--time`);
    // 0: not known. auto holds its duel only where enough passes follow it (BdptOptions);
    // --guiding auto starts a guide only where enough do (guide_start.h).
    int plannedPasses = 0;
    // The bidirectional tracer: its MIS heuristic, which strategies it makes and how often
    // (every one by default; `--allocation NAME` picks one of auto's candidates), and two
    // variants kept for measurement (BdptOptions).
    MisHeuristic heuristic = MisHeuristic::Power;
    BdptAllocation allocation;
    bool exactEquiAngular = false, generalEquiAngular = false;
    // The fixed bidirectional tracer's single-scattering split (BdptOptions::oneEventSplit);
    // off where --strategy-images shows the generic strategies, so that they add up to the image.
    bool oneEventSplit = true;
    // auto's partial pilot pass (BdptOptions::partialPilot); `brume render` and `brume bench`
    // take it where the film does not track noise.
    bool partialPilot = false;
};

// "pt", "bdpt" or "auto"; false for anything else.
bool integratorKindNamed(const std::string& name, IntegratorKind* out);

PathTracerOptions pathTracerOptions(const IntegratorSettings& s);
// auto needs equi-angular variants that add to the free-flight ones (mis) or none (density):
// with --connect equiangular or product it renders as bdpt, every strategy on.
BdptOptions bdptOptions(const IntegratorSettings& s);
std::unique_ptr<Integrator> makeIntegrator(const IntegratorSettings& s);

}  // namespace brume
