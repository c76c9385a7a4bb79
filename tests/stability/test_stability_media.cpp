// Stability: extreme media (σt × scene size = 50, σt = 1e-6), extreme anisotropy (g = ±0.999)
// and a coloured haze whose channels differ 10×.
#include "stability/stability_case.h"

using namespace brume;
using namespace brume::test;

TEST_CASE("stability: extremely dense fog", "[stability]") {
    // The reference is bdpt (light tracing from the light inside the fog): its relative RMSE is
    // 3% at 256 spp where the path tracer's is 7-20% at 2048. Free-flight points near the light
    // give pt:density its heavy tail (1/r²).
    runStabilityCase(StabilityCase("dense", "dense.gltf")
                         .referenceMethod(kBdptDensity)
                         .weakMethod(kPtDensity, 0.41, 0.012, true));
}

TEST_CASE("stability: extremely thin fog", "[stability]") {
    // The reference is bdpt with equi-angular connections. Free flight scatters within 10 m with
    // probability 1e-5, so the density methods see almost none of the fog; and the path tracer
    // continues paths only from free-flight points, so it misses the fog lit by the floor (4-26%
    // of the fog-only pixels) but for rare spikes. auto drops the equi-angular variants here,
    // by design: the fog is 1e-5 of the floor's radiance, far below the relative-error floor
    // ε = 0.01 of the measure it optimises (brume bench's relative MSE), where they cost time
    // and buy nothing the measure sees; its fog pixels are then as weak as bdpt:density's
    // (max |z| 36 there), the floor and the image mean are right.
    runStabilityCase(StabilityCase("thin", "thin.gltf")
                         .referenceMethod(kBdptEquiAngular)
                         .weakMethod(kPtDensity, 0.017, 0.001, true)
                         .weakMethod(kPtEquiAngular, 0.016, 0.001, true)
                         .weakMethod(kPtProduct, 0.016, 0.001, true)
                         .weakMethod(kPtMis, 0.016, 0.001, true)
                         .weakMethod(kBdptDensity, 0.042, 0.001, true)
                         .weakMethod(kAuto, 0.042, 0.001, true));
}

TEST_CASE("stability: g = +0.999", "[stability]") {
    // The reference is bdpt: light scattered forward by a few milliradians keeps travelling
    // away from the light, and a camera path meets it only by aiming within ~1e-3 rad of the
    // light at a scattering event; light tracing follows it. At exactly two scattering events
    // the path tracer's 2×2 blocks stay up to 22% below bdpt at 262144 spp (z down to −14).
    runStabilityCase(StabilityCase("g_forward", "g_forward.gltf")
                         .referenceMethod(kBdptDensity)
                         .weakMethod(kPtDensity, 30.0, 0.005, true, 0.55)
                         .weakMethod(kPtEquiAngular, 2.1, 0.0015, false, 0.58)
                         // Product sampling follows the forward peak (image bias −6 % where plain
                         // equi-angular has −49 %), but its blocks still miss the two-event paths.
                         .weakMethod(kPtProduct, 1.9, 0.0065, true, 0.51)
                         .weakMethod(kPtMis, 1.9, 0.0065, true, 0.45));
}

TEST_CASE("stability: g = -0.999", "[stability]") {
    // Equi-angular connections aim at the light, which is behind the camera: once in four seed
    // sets bdpt:equiangular reached z = 6.4. At this budget no method resolves the image mean
    // (the median of means of methods not listed as weak strayed up to 0.31 over three seed
    // sets): bound 0.65.
    runStabilityCase(StabilityCase("g_backward", "g_backward.gltf")
                         .meanResolvedTo(0.65)
                         .weakMethod(kBdptEquiAngular, 0.74, 0.02, true, 0.87));
}

TEST_CASE("stability: blue haze (coloured fog, a street lamp and a sun)", "[stability][chromatic]") {
    runStabilityCase(StabilityCase("blue_haze", "blue_haze.gltf"));
}
