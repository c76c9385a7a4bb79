// The BRUME_render root extension (written by src/blender/brume_export.py): the loader reads
// width, height, spp and maxDepth, refuses bad values with the field named, and `brume render`
// takes them as the defaults of --res, --spp and --max-depth.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "brume/scene/gltf_loader.h"
#include "support/run_brume.h"
#include "support/scratch_files.h"

using namespace brume;
using Catch::Matchers::Contains;

namespace {

// A camera and nothing else, with `extensions` as the root's extensions object.
std::string sceneWith(const std::string& extensions) {
    return R"({"asset": {"version": "2.0"}, "extensionsUsed": ["BRUME_render"], "extensions": )" + extensions +
           R"(, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"camera": 0}],
             "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]})";
}

SceneDescription load(const test::TempDir& dir, const std::string& extensions) {
    const std::string path = dir / "s.gltf";
    test::writeFile(path, sceneWith(extensions));
    return loadGltf(path);
}

}  // namespace

TEST_CASE("BRUME_render: the loader reads the render settings", "[gltf]") {
    test::TempDir dir;
    SECTION("all of them") {
        RenderSettings r = load(dir, R"({"BRUME_render": {"width": 96, "height": 64, "spp": 200, "maxDepth": 9}})").render;
        CHECK(r.width == 96);
        CHECK(r.height == 64);
        CHECK(r.spp == 200);
        CHECK(r.maxDepth == 9);
    }
    SECTION("none: not given") {
        RenderSettings r = load(dir, R"({})").render;
        CHECK(r.width == 0);
        CHECK(r.height == 0);
        CHECK(r.spp == 0);
        CHECK(r.maxDepth == -2);
    }
    SECTION("unlimited depth") { CHECK(load(dir, R"({"BRUME_render": {"maxDepth": -1}})").render.maxDepth == -1); }
    SECTION("bad values name the field") {
        CHECK_THROWS_WITH(load(dir, R"({"BRUME_render": {"width": 96}})"),
                          Contains("extensions.BRUME_render: width and height go together"));
        CHECK_THROWS_WITH(load(dir, R"({"BRUME_render": {"spp": 0}})"),
                          Contains("extensions.BRUME_render.spp: 0 is not in [1, 16777216]"));
        CHECK_THROWS_WITH(load(dir, R"({"BRUME_render": {"maxDepth": 2.5}})"),
                          Contains("extensions.BRUME_render.maxDepth: expected an integer"));
        CHECK_THROWS_WITH(load(dir, R"({"BRUME_render": {"width": 20000, "height": 2}})"),
                          Contains("extensions.BRUME_render.width: 20000 is not in [1, 16384]"));
        CHECK_THROWS_WITH(load(dir, R"({"BRUME_render": {"spp": "many"}})"),
                          Contains("extensions.BRUME_render.spp: expected an integer"));
    }
}

TEST_CASE("BRUME_render: brume render takes the settings as defaults of its options", "[gltf]") {
    REQUIRE(std::filesystem::exists(BRUME_EXE));  // built with the rest (cmake --build without --target)
    test::TempDir dir;
    const std::string scene = dir / "s.gltf";
    test::writeFile(scene, sceneWith(R"({"BRUME_render": {"width": 12, "height": 8, "spp": 3, "maxDepth": 2}})"));
    const std::string out = test::quote(dir / "o.pfm");
    SECTION("from the file") {
        test::BrumeResult r = test::runBrume("render " + test::quote(scene) + " -o " + out + " --threads 1");
        REQUIRE(r.code == 0);
        CHECK_THAT(r.out, Contains("12x8, 3 spp"));
    }
    SECTION("the command line wins") {
        test::BrumeResult r =
            test::runBrume("render " + test::quote(scene) + " -o " + out + " --threads 1 --res 6x4 --spp 2");
        REQUIRE(r.code == 0);
        CHECK_THAT(r.out, Contains("6x4, 2 spp"));
    }
    SECTION("--time replaces the file's spp") {
        test::BrumeResult r = test::runBrume("render " + test::quote(scene) + " -o " + out + " --threads 1 --time 0.05");
        REQUIRE(r.code == 0);
        CHECK_THAT(r.out, Contains("12x8"));
    }
}
