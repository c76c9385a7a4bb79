#include "brume/integrators/sample_cost.h"

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"

namespace brume {

double bidirectionalCost(const uint64_t* n, double samples) {
    using namespace bdpt_cost;
    auto rays = [&](StrategyKind kind, bool ea) { return double(n[rayCounter(kind, ea)]); };
    return kSample * samples + kCameraWalk * double(n[kCameraWalkRays]) + kLightWalk * double(n[kLightWalkRays]) +
           kLightConnection * rays(StrategyKind::LightConnection, false) +
           kLightConnectionEa * rays(StrategyKind::LightConnection, true) +
           kCameraConnection * rays(StrategyKind::CameraConnection, false) +
           kCameraConnectionEa * rays(StrategyKind::CameraConnection, true) +
           kGeneralConnection * (rays(StrategyKind::SubpathConnection, false) + rays(StrategyKind::SubpathConnection, true));
}

double pathTracerCost(const uint64_t* n) {
    using namespace pt_cost;
    return kSample * double(n[kPtSamples]) + kWalk * double(n[kPtWalkRays]) + kVertexCall * double(n[kPtVertexCalls]) +
           kSegmentCall * double(n[kPtSegmentCalls]) + kSolidAngleRay * double(n[kPtSolidAngleRays]);
}

}  // namespace brume
