// `brume render --aov albedo,normal`: the EXR carries layers "Albedo" (R, G, B) and "Normal"
// (X, Y, Z) after its R, G, B (the names Blender's compositor shows as passes: the Blender
// test tests/blender/aov_layers.py loads them there), with the values denoiseFeatures gives;
// and what --aov refuses.
#include <catch2/catch.hpp>
#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

#include "brume/film/image_io.h"
#include "brume/integrators/denoise_features.h"
#include "support/pixel_estimates.h"
#include "support/run_brume.h"

using namespace brume::test;

TEST_CASE("render --aov: albedo and normal layers by name, the colour unchanged", "[cli][aov]") {
    TempDir dir;
    const std::string scene = quote(std::string(BRUME_TEST_DATA) + "/furnace_glowing.gltf");
    const std::string common = "render " + scene + " --res 12x9 --spp 4 --seed 5 --threads 2";
    REQUIRE(runBrume(common + " -o " + quote(dir / "plain.exr")).code == 0);
    const BrumeResult r = runBrume(common + " -o " + quote(dir / "aov.exr") + " --aov albedo,normal");
    REQUIRE(r.code == 0);
    auto in = OIIO::ImageInput::open(dir / "aov.exr");
    REQUIRE(in);
    const OIIO::ImageSpec& spec = in->spec();
    const std::vector<std::string> names = {"R", "G", "B", "Albedo.R", "Albedo.G", "Albedo.B", "Normal.X", "Normal.Y", "Normal.Z"};
    REQUIRE(spec.nchannels == 9);
    for (int c = 0; c < 9; ++c) CHECK(spec.channelnames[size_t(c)] == names[size_t(c)]);
    std::vector<float> px(size_t(12 * 9 * 9));
    REQUIRE(in->read_image(0, 0, 0, 9, OIIO::TypeDesc::FLOAT, px.data()));
    in->close();
    auto loaded = loadTestScene("furnace_glowing.gltf");
    const brume::DenoiseFeatures f = brume::denoiseFeatures(*loaded, 12, 9, 5, 1);
    int w = 0, h = 0;
    const std::vector<float> plain = brume::readImage(dir / "plain.exr", &w, &h);
    for (size_t i = 0; i < size_t(12 * 9); ++i)
        for (size_t c = 0; c < 3; ++c) {
            CHECK(px[9 * i + c] == plain[3 * i + c]);
            CHECK(px[9 * i + 3 + c] == f.albedo[3 * i + c]);
            CHECK(px[9 * i + 6 + c] == f.normal[3 * i + c]);
        }
}

// --aov variance: a layer "Variance" (R, G, B) after the others, each pixel's variance of the
// mean (film/pixel_noise.h; its statistics are tested in test_adaptive_stopping.cpp): not
// negative, and 0 in the furnace's constant pixels only if they are constant.
TEST_CASE("render --aov variance: a Variance layer after the colour, the colour unchanged", "[cli][aov]") {
    TempDir dir;
    const std::string scene = quote(std::string(BRUME_TEST_DATA) + "/furnace_glowing.gltf");
    const std::string common = "render " + scene + " --res 12x9 --spp 8 --seed 5 --threads 2";
    REQUIRE(runBrume(common + " -o " + quote(dir / "plain.exr")).code == 0);
    const BrumeResult r = runBrume(common + " -o " + quote(dir / "aov.exr") + " --aov variance,albedo");
    REQUIRE(r.code == 0);
    auto in = OIIO::ImageInput::open(dir / "aov.exr");
    REQUIRE(in);
    const OIIO::ImageSpec& spec = in->spec();
    const std::vector<std::string> names = {"R", "G", "B", "Albedo.R", "Albedo.G", "Albedo.B", "Variance.R", "Variance.G", "Variance.B"};
    REQUIRE(spec.nchannels == 9);
    for (int c = 0; c < 9; ++c) CHECK(spec.channelnames[size_t(c)] == names[size_t(c)]);
    std::vector<float> px(size_t(12 * 9 * 9));
    REQUIRE(in->read_image(0, 0, 0, 9, OIIO::TypeDesc::FLOAT, px.data()));
    in->close();
    int w = 0, h = 0;
    const std::vector<float> plain = brume::readImage(dir / "plain.exr", &w, &h);
    double variance = 0;
    for (size_t i = 0; i < size_t(12 * 9); ++i)
        for (size_t c = 0; c < 3; ++c) {
            CHECK(px[9 * i + c] == plain[3 * i + c]);
            CHECK(px[9 * i + 6 + c] >= 0.0f);
            variance += px[9 * i + 6 + c];
        }
    CHECK(variance > 0);  // the furnace's estimates do vary
}

TEST_CASE("render --aov: unknown layers and other formats are refused", "[cli][aov]") {
    TempDir dir;
    const std::string scene = quote(std::string(BRUME_TEST_DATA) + "/furnace_glowing.gltf");
    struct Case {
        std::string args, message;
    } cases[] = {
        {" -o " + quote(dir / "o.exr") + " --aov albedo,depth", "brume: error: --aov: unknown layer 'depth'"},
        {" -o " + quote(dir / "o.png") + " --aov normal", "brume: error: --aov needs an .exr output"},
    };
    for (const Case& c : cases) {
        INFO(c.args);
        const BrumeResult r = runBrume("render " + scene + " --res 8x8 --spp 1" + c.args);
        CHECK(r.code == 2);
        CHECK(r.err.rfind(c.message, 0) == 0);
    }
    CHECK(dir.files().empty());
}
