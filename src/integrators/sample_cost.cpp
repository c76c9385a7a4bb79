#include "brume/integrators/sample_cost.h"


namespace brume {

double bidirectionalCost(const BidirectionalCounts& n, double samples) {
    using namespace bdpt_cost;
    auto rays = [&](StrategyKind kind, bool ea) { return double(n.rays(kind, ea)); };
    return kSample * samples + kCameraWalk * double(n.cameraWalkRays) + kLightWalk * double(n.lightWalkRays) +
           kLightConnection * rays(StrategyKind::LightConnection, false) +
           kLightConnectionEa * rays(StrategyKind::LightConnection, true) +
           kCameraConnection * rays(StrategyKind::CameraConnection, false) +
           kCameraConnectionEa * rays(StrategyKind::CameraConnection, true) +
           kGeneralConnection * (rays(StrategyKind::SubpathConnection, false) + rays(StrategyKind::SubpathConnection, true));
}

double pathTracerCost(const PathTracerCounts& n) {
    using namespace pt_cost;
    return kSample * double(n.samples) + kWalk * double(n.walkRays) + kVertexCall * double(n.vertexCalls) +
           kSegmentCall * double(n.segmentCalls) + kSolidAngleRay * double(n.solidAngleRays);
}

}  // namespace brume
