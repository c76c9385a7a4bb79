// Stability: geometry at the edges (a scene 1e5 m from the origin, an area light over a floor,
// degenerate triangles, emitters of zero area).
#include "stability/stability_case.h"

using namespace brume;
using namespace brume::test;

TEST_CASE("stability: a scene 1e5 m from the origin", "[stability]") {
    // far.gltf is light_in_box.gltf shifted by (60000, 40000, -70000), exactly (every
    // coordinate is a multiple of 1/16): each method against itself at the origin, bdpt with
    // 4× the usual samples (it is cheap here) to resolve a bias of a few percent.
    runStabilityCase(StabilityCase("far", "far.gltf").sameMethodOn("light_in_box.gltf").samples(64, 32));
}

TEST_CASE("stability: an area light over a floor", "[stability]") {
    // The reference is bdpt, whose connections ignore the light's own triangle: the path
    // tracer's shadow rays towards an emissive triangle are what this case checks.
    runStabilityCase(StabilityCase("area_over_floor", "area_over_floor.gltf").referenceMethod(kBdptDensity));
}

TEST_CASE("stability: degenerate triangles in a floor and in an area light", "[stability]") {
    // degenerate.gltf is area_over_floor.gltf plus zero-area, collinear and sliver triangles:
    // each method against itself without them.
    runStabilityCase(StabilityCase("degenerate", "degenerate.gltf").sameMethodOn("area_over_floor.gltf"));
}

TEST_CASE("stability: an emitter of zero area beside a point light", "[stability]") {
    runStabilityCase(StabilityCase("zero_area_emitter", "zero_area_emitter.gltf"));
}

TEST_CASE("stability: an emitter of zero area alone", "[stability]") {
    // The reference is bdpt, as for area_over_floor: the one emitter is a sliver.
    runStabilityCase(StabilityCase("zero_area_only", "zero_area_only.gltf").referenceMethod(kBdptDensity));
}
