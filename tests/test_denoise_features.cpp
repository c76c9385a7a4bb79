// Denoising features (integrators/denoise_features.h) against closed forms: the glowing
// furnace seen from its centre (an inward sphere of radius 2, walls of base colour 0.5, an
// ambient medium scattering 0.6 and absorbing 0.4): along every camera ray the expected albedo
// is (1 − T)·0.6/1.0 + T·0.5 with T = exp(−σt·d), d the distance to the wall, and the expected
// normal is −d (the medium's and the wall's, which faces the centre). And the same image for
// any thread count.
#include <catch2/catch.hpp>
#include <cmath>

#include "brume/integrators/denoise_features.h"
#include "support/pixel_estimates.h"

using namespace brume;

TEST_CASE("denoise features: expected albedo and normal in the fog-filled sphere", "[aov]") {
    auto scene = test::loadTestScene("furnace_glowing.gltf");
    const int W = 12, H = 9;
    const DenoiseFeatures f = denoiseFeatures(*scene, W, H, 5, 2);
    REQUIRE(f.albedo.size() == size_t(3 * W * H));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            // The jitter moves d by less than the tessellation does (1.996 to 2 m): T within 1 %.
            const Ray centre = scene->camera().generateRay(x + 0.5f, y + 0.5f, W, H);
            const float d = scene->intersect(centre).t;
            const double T = std::exp(-1.0 * d), expected = (1 - T) * 0.6 + T * 0.5;
            const size_t i = 3 * (size_t(y) * W + size_t(x));
            INFO("pixel (" << x << "," << y << ")");
            for (int c = 0; c < 3; ++c) CHECK(f.albedo[i + size_t(c)] == Approx(expected).epsilon(2e-3));
            const Vec3 n(f.normal[i], f.normal[i + 1], f.normal[i + 2]);
            CHECK(length(n) == Approx(1.0f).epsilon(2e-3));
            CHECK(dot(n, centre.d) < -0.99f);
        }
    const DenoiseFeatures one = denoiseFeatures(*scene, W, H, 5, 1);
    CHECK(one.albedo == f.albedo);
    CHECK(one.normal == f.normal);
}

