#include "brume/integrators/integrator_settings.h"

namespace brume {

bool integratorKindNamed(const std::string& name, IntegratorKind* out) {
    if (name == "pt") *out = IntegratorKind::PathTracer;
    else if (name == "bdpt") *out = IntegratorKind::Bidirectional;
    else if (name == "auto") *out = IntegratorKind::EfficiencyAware;
    else return false;
    return true;
}

PathTracerOptions pathTracerOptions(const IntegratorSettings& s) {
    PathTracerOptions o;
    o.maxDepth = s.maxDepth;
    o.nextEventEstimation = s.nextEventEstimation;
    o.connect = s.connect;
    o.guiding = s.guiding;
    o.guidingAuto = s.guidingAuto && !s.guiding;
    o.plannedPasses = s.plannedPasses;
    o.guidedDistanceDepth = s.guidedDistanceDepth;
    o.volumeLights = s.volumeLights;
    o.learnShares = s.learnShares;
    return o;
}

BdptOptions bdptOptions(const IntegratorSettings& s) {
    BdptOptions o;
    o.maxDepth = s.maxDepth;
    o.heuristic = s.heuristic;
    o.connect = s.connect;
    o.exactEquiAngular = s.exactEquiAngular;
    o.generalEquiAngular = s.generalEquiAngular;
    o.allocation = s.allocation;
    o.efficiencyAware = s.kind == IntegratorKind::EfficiencyAware && !variantOnly(s.connect);
    o.guiding = s.guiding;
    o.guidingAuto = s.guidingAuto && !s.guiding && o.efficiencyAware;
    o.volumeLights = s.volumeLights;
    o.learnShares = s.learnShares;
    o.plannedPasses = s.plannedPasses;
    o.oneEventSplit = s.oneEventSplit;
    o.partialPilot = s.partialPilot;
    return o;
}

std::unique_ptr<Integrator> makeIntegrator(const IntegratorSettings& s) {
    if (s.kind == IntegratorKind::PathTracer) return std::make_unique<PathTracer>(pathTracerOptions(s));
    return std::make_unique<BdptIntegrator>(bdptOptions(s));
}

}  // namespace brume
