// Blackbody emission (math/blackbody.h) against Blender Cycles 3.4, and its loading.
//   - c(T) against Cycles' Blackbody node: a world background of colour Blackbody(T),
//     strength 1, rendered with the Standard view transform (the pixel is the colour);
//   - e(T) against Cycles' Principled Volume: a 1 m slab of density 0, blackbody intensity b,
//     temperature T and tint, seen straight through (the pixel is e × 1 m).
// Measured with Blender 3.4.1 (tests/blender/measure_cycles.py, kept in
// tests/blender/cycles_measurements.json under "blackbody"). Cycles evaluates a fitted curve;
// brume integrates Planck's law against the CIE 1931 observer: they agree to 0.2 % from 800 K
// to 12000 K (0.18 % at worst, at 800 K), negative channels included.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "brume/math/blackbody.h"
#include "brume/math/vec3.h"
#include "brume/scene/density_grid.h"
#include "brume/scene/gltf_loader.h"
#include "brume/scene/medium.h"
#include "support/scratch_files.h"

using namespace brume;

namespace {

struct NodeColour {
    float kelvin;
    float rgb[3];
};

// Cycles' Blackbody node (its negative channels clipped to 0, as the node does).
constexpr NodeColour kCyclesNode[] = {
    {800, {5.41386f, 0, 0}},          {900, {4.98396f, 0, 0}},
    {1000, {4.60136f, 0.0390408f, 0}}, {1200, {3.96553f, 0.227896f, 0}},
    {1500, {3.26431f, 0.434045f, 0}}, {2000, {2.52010f, 0.646850f, 0.0204130f}},
    {2500, {2.06763f, 0.769322f, 0.139430f}}, {3000, {1.77084f, 0.844284f, 0.272223f}},
    {4000, {1.41412f, 0.923641f, 0.533674f}}, {5000, {1.21311f, 0.960781f, 0.762214f}},
    {6500, {1.04255f, 0.984051f, 1.03527f}},  {8000, {0.947344f, 0.991600f, 1.23714f}},
    {10000, {0.871382f, 0.994923f, 1.43051f}}, {12000, {0.826294f, 0.994507f, 1.56631f}},
    {15000, {0.826294f, 0.994507f, 1.56631f}},
};

struct VolumeEmission {
    float kelvin, intensity, tint[3], rgb[3];
};

// Cycles' Principled Volume, e per metre, negative channels (outside the Rec.709 gamut: blue
// at 1000 and 1500 K) included, as brume keeps them.
constexpr VolumeEmission kCyclesVolume[] = {
    {1000, 1, {1, 1, 1}, {0.0830516f, 0.000704682f, -0.00162493f}},
    {1500, 1, {1, 1, 1}, {0.298276f, 0.0396609f, -0.00586965f}},
    {2500, 1, {1, 1, 1}, {1.45779f, 0.542413f, 0.0983053f}},
    {4000, 1, {1, 1, 1}, {6.53412f, 4.26781f, 2.46591f}},
    {1500, 0.5f, {1, 1, 1}, {0.149138f, 0.0198305f, -0.00293483f}},
    {2500, 0.25f, {1, 0.5f, 0.25f}, {0.364447f, 0.0678017f, 0.00614408f}},
};


}  // namespace

TEST_CASE("blackbody colour matches Cycles' Blackbody node", "[blackbody]") {
    for (const NodeColour& m : kCyclesNode) {
        const Spectrum c = blackbodyColourClipped(m.kelvin);
        for (int ch = 0; ch < 3; ++ch) {
            INFO(m.kelvin << " K channel " << ch << ": brume " << c[ch] << ", Cycles " << m.rgb[ch]);
            const float tol = 0.002f;
            // Channels Cycles clips to 0 from a fit: brume's integral is within 0.04 of 0 there.
            if (m.rgb[ch] < 0.05f)
                CHECK(std::abs(c[ch] - m.rgb[ch]) < 0.04f);
            else
                CHECK(c[ch] == Approx(m.rgb[ch]).epsilon(tol));
        }
    }
}

TEST_CASE("blackbody emission matches Cycles' Principled Volume", "[blackbody]") {
    for (const VolumeEmission& m : kCyclesVolume) {
        const Spectrum e = Spectrum(m.tint[0], m.tint[1], m.tint[2]) * blackbodyEmission(m.kelvin, m.intensity);
        for (int ch = 0; ch < 3; ++ch) {
            INFO(m.kelvin << " K, intensity " << m.intensity << ", channel " << ch << ": brume " << e[ch] << ", Cycles "
                          << m.rgb[ch]);
            if (std::abs(m.rgb[ch]) < 0.01f * m.rgb[0])
                CHECK(std::abs(e[ch] - m.rgb[ch]) < 0.01f * m.rgb[0]);
            else
                CHECK(e[ch] == Approx(m.rgb[ch]).epsilon(0.002));
            CHECK((e[ch] < 0) == (m.rgb[ch] < 0));
        }
    }
}

TEST_CASE("blackbody colour: luminance 1, held outside [800, 12000] K, nothing at 0 K", "[blackbody]") {
    for (float T : {900.0f, 1500.0f, 2000.0f, 3300.0f, 6500.0f, 9000.0f})
        CHECK(luminance(blackbodyColour(T)) == Approx(1.0f).epsilon(1e-3));
    // Below ~1900 K blue is out of gamut: negative, and clipped by the node's version, whose
    // luminance then exceeds 1.
    CHECK(blackbodyColour(1500).z < 0);
    CHECK(blackbodyColourClipped(1500).z == 0.0f);
    CHECK(luminance(blackbodyColourClipped(1500)) > 1.0f);
    for (int c = 0; c < 3; ++c) {
        CHECK(blackbodyColour(300)[c] == blackbodyColour(800)[c]);
        CHECK(blackbodyColour(40000)[c] == blackbodyColour(12000)[c]);
    }
    // Redder when cooler.
    CHECK(blackbodyColour(1500).x / blackbodyColour(1500).y > blackbodyColour(3000).x / blackbodyColour(3000).y);
    CHECK(blackbodyEmission(0, 1).x == 0.0f);
    CHECK(blackbodyEmission(-5, 0.5f).x == 0.0f);
    // Stefan–Boltzmann: T⁴ with intensity 1, (1 − b) + b·T⁴ otherwise.
    const Spectrum a = blackbodyEmission(2000, 1), b = blackbodyEmission(4000, 1);
    CHECK(b.y / a.y == Approx(16 * blackbodyColour(4000).y / blackbodyColour(2000).y).epsilon(1e-5));
    CHECK(blackbodyEmission(2000, 0.5f).x == Approx(0.5f * a.x).epsilon(1e-5));
}

TEST_CASE("blackbody media load: a temperature becomes emission, a grid stays a temperature grid", "[blackbody]") {
    SceneDescription desc = loadGltf(std::string(BRUME_TEST_DATA) + "/furnace_blackbody.gltf");
    REQUIRE(desc.media.size() == 1);
    const Medium& m = desc.media[0];
    CHECK(m.blackbody);
    CHECK(m.blackbodyIntensity == 1.0f);
    REQUIRE(m.emissionGrid.grid);
    CHECK(m.emissionGrid.scale == 2500.0f);
    const Spectrum e = m.emissionAt(Vec3(0.3f, -0.7f, 1.1f)), expected = blackbodyEmission(2500, 1);
    for (int c = 0; c < 3; ++c) CHECK(e[c] == Approx(expected[c]).epsilon(1e-5));
    CHECK(m.emissionAt(Vec3(0, 0, 3.5f)).x == 0.0f);  // beyond the grid
}

TEST_CASE("blackbody media load: one temperature adds to the medium's emission", "[blackbody]") {
    // blackbody_intensity.gltf (a refused intensity of 2) with intensity 0.5, a tint and an
    // emission beside it.
    std::string text = test::readFile(std::string(BRUME_TEST_DATA) + "/bad/blackbody_intensity.gltf");
    const std::string from = "\"intensity\": 2.0";
    const size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), "\"intensity\": 0.5, \"tint\": [1.0, 0.5, 0.25]");
    const std::string fog = "\"name\": \"fog\"";
    const size_t f = text.find(fog);
    REQUIRE(f != std::string::npos);
    text.insert(f, "\"emission\": [0.01, 0.02, 0.03], ");
    test::TempDir dir;
    test::writeFile(dir / "ember.gltf", text);
    SceneDescription desc = loadGltf(dir / "ember.gltf");
    const Medium& m = desc.media[0];
    CHECK(!m.blackbody);
    CHECK(!m.emissionGrid.grid);
    const Spectrum bb = blackbodyEmission(1500, 0.5f);
    CHECK(m.emission.x == Approx(0.01f + bb.x).epsilon(1e-5));
    CHECK(m.emission.y == Approx(0.02f + 0.5f * bb.y).epsilon(1e-5));
    CHECK(m.emission.z == Approx(0.03f + 0.25f * bb.z).epsilon(1e-5));
}
