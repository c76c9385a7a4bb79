// Stability: lights in awkward places (on a camera ray, right next to the surface camera rays
// end on, a 0.5° spot, a directional light alone, lights inside a bounded medium).
#include "stability/stability_case.h"
#include "stability/stability_exact_ray.h"

using namespace brume;
using namespace brume::test;

TEST_CASE("stability: a point light exactly on a camera ray", "[stability]") {
    runStabilityCase(StabilityCase("on_ray", "on_ray.gltf"));
}

TEST_CASE("stability: samples on the exact ray through a light are finite", "[stability]") {
    // on_ray.gltf: film position (8, 6) of 16x12 looks straight down -Z through the light at
    // (0, 0, -3) (distance from the ray exactly 0). segment_end.gltf: the film position the
    // point light projects to (distance from the ray ~1e-7 m), 1 cm in front of the wall.
    for (const char* file : {"on_ray.gltf", "segment_end.gltf"}) {
        auto scene = loadStabilityScene(file);
        CameraConnection cc;
        REQUIRE(connectToCamera(scene->camera(), scene->lights()[0].position, kWidth, kHeight, &cc));
        if (std::string(file) == "on_ray.gltf") {
            REQUIRE(cc.fx == 8.0f);
            REQUIRE(cc.fy == 6.0f);
        }
        for (const Method& m : allMethods()) {
            auto integrator = m.make(-1);
            ExactRayResult r = sampleExactRay(*scene, *integrator, cc.fx, cc.fy, kWidth, kHeight, m.bdpt ? 1024 : 8192, 5);
            std::printf("exact ray %s %s: %ld samples, mean %.4g, non-finite %ld, splats dropped %ld\n", file,
                        m.name().c_str(), r.samples, r.mean, r.nonFinite, r.splatsDropped);
            INFO(file << " " << m.name() << " at film position (" << cc.fx << ", " << cc.fy << ")");
            CHECK(r.nonFinite == 0);
            CHECK(r.splatsDropped == 0);
        }
    }
}

TEST_CASE("stability: lights 1 cm and 1 mm in front of the wall camera rays end on", "[stability]") {
    // The reference is bdpt: the wall is lit up to 1e5 W/m² next to the point light, a bright
    // spot 2 cm wide that lights the rest of the scene, which the path tracer finds only when a
    // bounce happens to aim at it (light tracing starts there). The path tracer converges
    // (image mean within 0.1% at 32768 spp) but its 4×4-block z stays far from Gaussian.
    runStabilityCase(StabilityCase("segment_end", "segment_end.gltf")
                         .referenceMethod(kBdptDensity)
                         .weakMethod(kPtDensity, 0.42, 0.011, false, 0.25)
                         .weakMethod(kPtEquiAngular, 0.70, 0.015, true, 0.24)
                         .weakMethod(kPtProduct, 0.70, 0.015, true, 0.27)
                         .weakMethod(kPtMis, 0.49, 0.014, true, 0.24));
}

TEST_CASE("stability: a spot light with a 0.5 degree cone", "[stability]") {
    // The reference is bdpt: the beam (2 cm wide) and the spot it makes on the floor light the
    // fog around them, which the path tracer reaches only by chance. Free flight rarely lands
    // in the beam itself (2.7e-5 of the free-flight points on the rays of the pixels next to
    // the spot's apex): pt:density is weakest.
    runStabilityCase(StabilityCase("tiny_spot", "tiny_spot.gltf")
                         .referenceMethod(kBdptDensity)
                         .weakMethod(kPtDensity, 1.2, 0.009, true, 0.75)
                         .weakMethod(kPtEquiAngular, 0.78, 0.027, true, 0.43)
                         .weakMethod(kPtProduct, 0.78, 0.027, true, 0.33)
                         .weakMethod(kPtMis, 0.50, 0.025, true, 0.27));
}

TEST_CASE("stability: the camera on the light subpaths' rays (a spot aimed at the pinhole)", "[stability]") {
    // Every light subpath starts on a segment passing within 3 cm of the pinhole: the camera
    // connections (equi-angular towards the camera) sample at distances near zero there.
    // This case found a bug: uniform cone sampling took sinθ from a rounded cosθ, so a 0.5°
    // spot had only a few hundred distinct polar angles, one of them exactly on its axis,
    // and 1 in ~600 light paths went exactly through the pinhole (D = 0): bdpt:equiangular
    // was 270x too bright on the light's block and 3% dark elsewhere (docs/results.md).
    runStabilityCase(StabilityCase("camera_in_beam", "camera_in_beam.gltf").samples(64, 32));
}

TEST_CASE("stability: only a directional light", "[stability]") {
    runStabilityCase(StabilityCase("directional", "directional.gltf"));
}

TEST_CASE("stability: only a directional light, its node inside the fog box", "[stability]") {
    runStabilityCase(StabilityCase("directional_node_inside", "directional_node_inside.gltf"));
}

TEST_CASE("stability: a point and a sphere light inside a bounded medium", "[stability]") {
    runStabilityCase(StabilityCase("light_in_box", "light_in_box.gltf"));
}

TEST_CASE("stability: the camera in the plane of a large one-sided panel", "[stability]") {
    // The middle row of camera rays runs in the emitter's plane: solid angles of exactly 0
    // there, growing away from it; the rectangle is sampled as one by solid angle.
    runStabilityCase(StabilityCase("camera_in_panel_plane", "camera_in_panel_plane.gltf"));
}

TEST_CASE("stability: rays that start on a reflecting emitter", "[stability]") {
    // A double-sided panel that also reflects: paths bounce off it and sample it from its own
    // surface (solid angle 0 or 2π at the start of the ray; area sampling there).
    runStabilityCase(StabilityCase("reflective_emitter", "reflective_emitter.gltf"));
}

TEST_CASE("stability: a 2 km emitter 1.5 m overhead", "[stability]") {
    // Nearly a hemisphere from everywhere: above the spherical limit, area sampling.
    runStabilityCase(StabilityCase("huge_emitter", "huge_emitter.gltf"));
}
