// Blender Cycles' spot profile (extras "spotProfile": "cycles", include/brume/scene/light.h):
// its formula against values worked out by hand from Cycles 3.4's spot_attenuation (the
// exporter's cycles_spot_profile, which tests/blender/test_conversions.py checks against
// irradiance measured in Cycles), the loader's checks, and single scattering under a 60° spot
// with that profile against 1D quadrature, for pt and bdpt (which reach the spot by next-event
// estimation, equi-angular sampling and light tracing: each must read the profile).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "support/block_z.h"
#include "support/film_estimates.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

Light cyclesSpot(double spotSize, double blend) {
    Light l;
    l.kind = LightKind::Spot;
    l.direction = Vec3(0, -1, 0);
    l.cyclesSpot = true;
    l.cosOuter = float(std::cos(0.5 * spotSize));
    l.spotSmooth = float((1 - std::cos(0.5 * spotSize)) * blend);
    return l;
}

}  // namespace

TEST_CASE("Cycles spot profile: cos(theta) inside the cone, a smoothstep over the blend band", "[light][spot]") {
    // spot_size 60°, blend 0.15: cut at cos 30° = 0.866025, band 0.866025 … 0.886122.
    const Light l = cyclesSpot(M_PI / 3, 0.15);
    CHECK(spotAttenuation(l, 1.0f) == Approx(1.0));
    CHECK(spotAttenuation(l, 0.95f) == Approx(0.95));      // inside: cosθ itself
    CHECK(spotAttenuation(l, 0.89f) == Approx(0.89));      // just above the band
    CHECK(spotAttenuation(l, 0.866f) == 0.0f);             // outside the cone
    // Halfway through the band: s = 0.5, s²(3 − 2s) = 0.5, times cosθ = 0.876074.
    CHECK(spotAttenuation(l, 0.876074f) == Approx(0.5 * 0.876074).epsilon(1e-4));
    // A quarter: s = 0.25, 0.15625 × cosθ (0.871049).
    CHECK(spotAttenuation(l, 0.871049f) == Approx(0.15625 * 0.871049).epsilon(1e-3));
    // No blend: a hard cut, cosθ up to the edge.
    const Light hard = cyclesSpot(M_PI / 3, 0.0);
    CHECK(spotAttenuation(hard, 0.8661f) == Approx(0.8661));
    CHECK(spotAttenuation(hard, 0.866f) == 0.0f);
}

TEST_CASE("Cycles spot profile: the loader reads it and refuses what it cannot use", "[light][spot]") {
    auto scene = loadTestScene("single_spot_cycles.gltf");
    REQUIRE(scene->lights().size() == 1);
    const Light& l = scene->lights()[0];
    CHECK(l.cyclesSpot);
    CHECK(l.cosOuter == Approx(std::cos(M_PI / 6)));
    CHECK(l.spotSmooth == Approx((1 - std::cos(M_PI / 6)) * 0.15));
    auto plain = loadTestScene("single_spot.gltf");
    CHECK_FALSE(plain->lights()[0].cyclesSpot);
}

TEST_CASE("Cycles spot profile: pt and bdpt single scattering match 1D quadrature", "[light][spot][oracle]") {
    // single_spot_cycles.gltf: the single-scattering fog and camera of single_spot.gltf, a 60°
    // spot (I = 30 W/sr) with Cycles' profile at (0, 1.5, −3) pointing down. Per 2 × 2 block of
    // a 10 × 10 image (batch means, 32 batches), the quadrature averaged over a 16 × 16 grid
    // of film positions in the block; |z| < 4.5.
    auto scene = loadTestScene("single_spot_cycles.gltf");
    const Light spot = cyclesSpot(M_PI / 3, 0.15);
    const int W = 10, B = 2, S = 16;
    std::vector<Vec3> ref(size_t(W / B) * (W / B));
    for (size_t i = 0; i < ref.size(); ++i) {
        const int bx = int(i) % (W / B), by = int(i) / (W / B);
        Vec3 sum(0.0f);
        for (int j = 0; j < S; ++j)
            for (int k = 0; k < S; ++k) {
                Vec3 d = referenceCameraDirection(bx * B + (k + 0.5) * B / S, by * B + (j + 0.5) * B / S, W, W, kYfov);
                sum += singleScatterReference(d, Vec3(0, 1.5f, -3), Vec3(30.0f), Vec3(0.2f), Vec3(0.05f), 0.3, &spot, 2000);
            }
        ref[i] = sum / float(S * S);
    }
    const std::vector<bool> skip(ref.size(), false);
    auto reference = [&](int x, int y) { return ref[size_t(y) * (W / B) + x]; };
    for (ConnectMode mode : {ConnectMode::Density, ConnectMode::Mis}) {
        PathTracer pt(PathTracerOptions{1, true, mode});
        std::string where;
        double z = worstZ(estimateFilm(*scene, pt, W, W, 32, 32, 41, B), W / B, skip, reference, &where);
        INFO("pt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        CHECK(z < 4.5);
        BdptOptions o{1, MisHeuristic::Power};
        o.connect = mode;
        z = worstZ(estimateFilm(*scene, BdptIntegrator(o), W, W, 32, 32, 42, B), W / B, skip, reference, &where);
        INFO("bdpt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        CHECK(z < 4.5);
    }
}
