// What samples count of their work (path_tracer.h's counters, the bidirectional tracer's ray
// counters) and what sample_cost.h makes of it: the duel's costs (allocation_planner.h).
#include <catch2/catch.hpp>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/integrators/sample_cost.h"
#include "brume/render/renderer.h"
#include "support/pixel_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

RenderStats renderWith(const Scene& scene, Integrator& integrator) {
    Film film(16, 12);
    RenderOptions o;
    o.width = 16;
    o.height = 12;
    o.spp = 4;
    o.threads = 2;
    return render(scene, integrator, o, film);
}

}  // namespace

TEST_CASE("the path tracer counts every ray in one part of its sample, and its samples", "[cost]") {
    auto scene = loadTestScene("quad_light_fog.gltf");  // a triangle light in fog
    REQUIRE(scene->hasTriangleLights());
    for (ConnectMode mode : {ConnectMode::Density, ConnectMode::EquiAngular, ConnectMode::Mis})
        for (int depth : {1, -1}) {
            PathTracer pt(PathTracerOptions{depth, true, mode});
            const RenderStats s = renderWith(*scene, pt);
            INFO("connect mode " << int(mode) << ", max depth " << depth);
            const PathTracerCounts& n = s.counts.pt;
            CHECK(n.samples == s.samples);
            CHECK(n.walkRays + n.vertexRays + n.segmentRays + n.solidAngleRays == s.rays);
            CHECK(n.walkRays >= s.samples);  // the camera ray at least
            CHECK((n.segmentCalls > 0) == (mode != ConnectMode::Density));
            CHECK((n.solidAngleCalls > 0) == (mode == ConnectMode::Mis));
            CHECK(n.vertexCalls > 0);
        }
}

TEST_CASE("the bidirectional tracer counts every ray in one part of its sample", "[cost]") {
    auto scene = loadTestScene("quad_light_fog.gltf");
    for (int depth : {1, -1}) {
        BdptOptions o{depth, MisHeuristic::Power};
        o.directLightTracing = 1.0;
        BdptIntegrator bdpt(o);
        const RenderStats s = renderWith(*scene, bdpt);
        const BidirectionalCounts& n = s.counts.bdpt;
        uint64_t parts = n.cameraWalkRays + n.lightWalkRays;
        // (Emitter hits trace no ray of their own.)
        CHECK(n.rays(StrategyKind::EmitterHit, false) + n.rays(StrategyKind::EmitterHit, true) == 0);
        for (StrategyKind k : {StrategyKind::LightConnection, StrategyKind::CameraConnection, StrategyKind::SubpathConnection})
            for (bool ea : {false, true}) parts += n.rays(k, ea);
        INFO("max depth " << depth);
        CHECK(parts == s.rays);
        CHECK(bidirectionalCost(n, double(s.samples)) > bdpt_cost::kSample * double(s.samples));
    }
}

// The cost follows the parts made: distances by an emitter's solid angle cost the path tracer
// its tables (on a panel in fog, pt:mis took 3x the time of pt:density per sample in single
// scattering), and equal counts cost the same.
TEST_CASE("a path tracer's cost grows with the parts it makes", "[cost]") {
    auto scene = loadTestScene("quad_light_fog.gltf");
    PathTracer density(PathTracerOptions{1, true, ConnectMode::Density});
    PathTracer mis(PathTracerOptions{1, true, ConnectMode::Mis});
    const RenderStats d = renderWith(*scene, density), m = renderWith(*scene, mis);
    const double perD = pathTracerCost(d.counts.pt) / double(d.samples), perM = pathTracerCost(m.counts.pt) / double(m.samples);
    CHECK(perM > 1.5 * perD);
    CHECK(perD >= pt_cost::kSample + pt_cost::kWalk);
    const PathCounts none;
    CHECK(pathTracerCost(none.pt) == 0.0);
    CHECK(bidirectionalCost(none.bdpt, 0.0) == 0.0);
}

TEST_CASE("pass counts add field by field and visit every field once, in a fixed order", "[cost]") {
    PathCounts a, b;
    uint64_t next = 1;
    a.forEach([&](uint64_t& v) { v = next++; });
    b.forEach([&](uint64_t& v) { v = 1000 * next++; });
    CHECK(int(next - 1) == 2 * PathCounts::kCount);
    PathCounts sum = a;
    sum.add(b);
    CHECK(sum.pt.samples == a.pt.samples + b.pt.samples);
    CHECK(sum.bdpt.rays(StrategyKind::SubpathConnection, true) ==
          a.bdpt.rays(StrategyKind::SubpathConnection, true) + b.bdpt.rays(StrategyKind::SubpathConnection, true));
    CHECK(sum.bdpt.contribution(StrategyKind::CameraConnection, false) ==
          a.bdpt.contribution(StrategyKind::CameraConnection, false) + b.bdpt.contribution(StrategyKind::CameraConnection, false));
    // Distinct fields: the values set first are 1 … kCount, each once.
    uint64_t seen = 0;
    a.forEach([&](uint64_t& v) { seen += v; });
    CHECK(seen == uint64_t(PathCounts::kCount) * (PathCounts::kCount + 1) / 2);
}
