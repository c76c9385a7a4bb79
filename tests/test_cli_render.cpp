// The brume executable, run as a user would: exit codes and one-line errors for bad command
// lines, files and scenes, never a partial or temporary file left behind, the three output
// formats, identical images for 1 and 2 threads, seeds, no non-finite samples in the bundled
// scenes. Also image_io directly.
#include <catch2/catch.hpp>

#include <chrono>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

#include "brume/film/image_io.h"

#include "support/run_brume.h"
#include "support/scratch_files.h"

namespace fs = std::filesystem;

using brume::test::BrumeResult;
using brume::test::quote;
using brume::test::runBrume;
using brume::test::readFile;
using brume::test::TempDir;
using brume::test::writeFile;

namespace {

using Result = BrumeResult;

std::string data(const std::string& name) { return quote(std::string(BRUME_TEST_DATA) + "/" + name); }

// stderr holds exactly one line, "brume: error: ...".
void checkOneLineError(const Result& r) {
    INFO("stderr: " << r.err);
    CHECK(r.err.rfind("brume: error: ", 0) == 0);
    REQUIRE(!r.err.empty());
    CHECK(r.err.back() == '\n');
    CHECK(r.err.find('\n') == r.err.size() - 1);
}

std::vector<float> readBack(const std::string& path, int w, int h) {
    int rw = 0, rh = 0;
    std::vector<float> rgb = brume::readImage(path, &rw, &rh);
    CHECK(rw == w);
    CHECK(rh == h);
    CHECK(rgb.size() == size_t(3 * w * h));
    return rgb;
}

const char* const kTiny = " --res 16x12 --spp 4";

}  // namespace

TEST_CASE("cli: help", "[cli]") {
    Result r = runBrume("--help");
    CHECK(r.code == 0);
    CHECK(r.out.find("render") != std::string::npos);
    r = runBrume("render --help");
    CHECK(r.code == 0);
    CHECK(r.out.find("--spp") != std::string::npos);
    CHECK(r.out.find("--no-nee") != std::string::npos);
    r = runBrume("raybench --help");
    CHECK(r.code == 0);
    r = runBrume("");
    CHECK(r.code == 2);
    r = runBrume("paint x");
    CHECK(r.code == 2);
    checkOneLineError(r);
}

TEST_CASE("cli: usage errors exit with 2 and leave no file", "[cli]") {
    TempDir dir;
    const std::string out = quote(dir / "out.exr");
    struct Case {
        std::string args, mention;
    } cases[] = {
        {data("empty.gltf") + " -o " + out + " --bogus", "--bogus"},
        {data("empty.gltf") + " -o " + out + " --spp 0", "--spp"},
        {data("empty.gltf") + " -o " + out + " --spp -3", "--spp"},
        {data("empty.gltf") + " -o " + out + " --spp 12abc", "--spp"},
        {data("empty.gltf") + " -o " + out + " --res 100000x100000", "--res"},
        {data("empty.gltf") + " -o " + out + " --res 16384x16384", "2^27"},
        {data("empty.gltf") + " -o " + out + " --res 0x10", "--res"},
        {data("empty.gltf") + " -o " + out + " --res 16", "--res"},
        {data("empty.gltf") + " -o " + out + " --threads 0", "--threads"},
        {data("empty.gltf") + " -o " + out + " --time -1", "--time"},
        {data("empty.gltf") + " -o " + out + " --time 1 --spp 4", "--time"},
        {data("empty.gltf") + " -o " + out + " --seed x", "--seed"},
        {data("empty.gltf") + " -o " + out + " --max-depth -2", "--max-depth"},
        {data("empty.gltf") + " -o " + out + " --integrator nope", "bdpt"},
        {data("empty.gltf") + " -o " + out + " --connect sometimes", "sometimes"},
        {data("empty.gltf") + " -o " + out + " --guiding maybe", "--guiding"},
        {data("empty.gltf") + " -o " + out + " --guiding on --integrator bdpt --strategy-images " + quote(dir / "s"), "--guiding"},
        {data("empty.gltf") + " -o " + out + " --guiding on", "--guiding"},  // (auto)
        {data("empty.gltf") + " -o " + out + " --integrator pt --guiding on --guided-distances often", "--guided-distances"},
        {data("empty.gltf") + " -o " + out + " --integrator pt --guided-distances camera", "--guided-distances"},
        {data("empty.gltf") + " -o " + out + " --integrator bdpt --guiding on --guided-distances all", "--guided-distances"},
        {data("empty.gltf") + " -o " + out + " --volume-lights maybe", "--volume-lights: expected on or off, got 'maybe'"},
        {data("empty.gltf") + " -o " + out + " --sampler halton", "halton"},
        {data("empty.gltf") + " -o " + out + " --noise-threshold 0", "--noise-threshold"},
        {data("empty.gltf") + " -o " + out + " --noise-threshold -0.1", "--noise-threshold"},
        {data("empty.gltf") + " -o " + out + " --noise-threshold nan", "--noise-threshold"},
        {data("empty.gltf") + " -o " + out + " --noise-threshold 0.1 --integrator bdpt --strategy-images " + quote(dir / "s"), "--noise-threshold"},
        {data("empty.gltf") + " -o " + out + " --target-error 0", "--target-error"},
        {data("empty.gltf") + " -o " + out + " --target-error 0.1 --noise-threshold 0.1", "exclude each other"},
        {data("empty.gltf") + " -o " + out + " --noise-threshold 0.1 --target-error 0.1", "exclude each other"},
        {data("empty.gltf") + " -o " + out + " --target-error 0.1 --integrator bdpt --strategy-images " + quote(dir / "s"), "--target-error"},
        {data("empty.gltf") + " -o " + out + " --spp", "--spp"},
        {data("empty.gltf") + " -o " + quote(dir / "out.jpg"), "out.jpg"},
        {data("empty.gltf") + " -o " + quote(dir / "out"), "out"},
        {data("empty.gltf"), "-o"},
        {"-o " + out, "scene"},
    };
    for (const Case& c : cases) {
        INFO("brume render " << c.args);
        Result r = runBrume("render " + c.args);
        CHECK(r.code == 2);
        checkOneLineError(r);
        CHECK(r.err.find(c.mention) != std::string::npos);
        CHECK(r.out.empty());
        CHECK(dir.files().empty());
    }
}

TEST_CASE("cli: scene and file errors exit with 1 and leave no file", "[cli]") {
    TempDir dir;
    const std::string out = dir / "out.exr";

    Result r = runBrume("render " + quote(dir / "missing.gltf") + " -o " + quote(out) + kTiny);
    CHECK(r.code == 1);
    checkOneLineError(r);
    CHECK(r.err.find("missing.gltf") != std::string::npos);
    CHECK(dir.files().empty());

    {
        std::ofstream bad(dir / "broken.gltf");
        bad << "{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [ { \"camera\": 7 } ";
    }
    r = runBrume("render " + quote(dir / "broken.gltf") + " -o " + quote(out) + kTiny);
    CHECK(r.code == 1);
    checkOneLineError(r);
    CHECK(r.err.find("broken.gltf") != std::string::npos);
    CHECK(dir.files() == std::vector<std::string>{"broken.gltf"});

    r = runBrume("render " + data("empty.gltf") + " -o /nonexistent-dir/x.exr" + kTiny);
    CHECK(r.code == 1);
    checkOneLineError(r);
    CHECK(r.err.find("/nonexistent-dir/x.exr") != std::string::npos);

    fs::create_directory(dir / "taken.pfm");
    r = runBrume("render " + data("empty.gltf") + " -o " + quote(dir / "taken.pfm") + kTiny);
    CHECK(r.code == 1);
    checkOneLineError(r);
    CHECK(fs::is_directory(dir / "taken.pfm"));
    CHECK(dir.files().size() == 2);
}

TEST_CASE("cli: an unknown field of BRUME_media is a warning naming it, and the render goes on", "[cli]") {
    TempDir dir;
    std::string text = readFile(std::string(BRUME_TEST_DATA) + "/bad/valid_base.gltf");
    const std::string name = "\"name\": \"fog\",";
    REQUIRE(text.find(name) != std::string::npos);
    text.replace(text.find(name), name.size(), name + " \"emision\": [1, 1, 1],");
    { std::ofstream(dir / "misspelt.gltf") << text; }
    Result r = runBrume("render " + quote(dir / "misspelt.gltf") + " -o " + quote(dir / "out.exr") + kTiny);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(r.err.find("brume: warning: " + dir / "misspelt.gltf" +
                     ": extensions.BRUME_media.media[0]: unknown field \"emision\" (ignored)\n") != std::string::npos);
    CHECK(fs::exists(dir / "out.exr"));
}

TEST_CASE("cli: .exr, .pfm and .png are written and read back", "[cli]") {
    TempDir dir;
    for (const char* name : {"fog.exr", "fog.pfm", "fog.png"}) {
        INFO(name);
        Result r = runBrume("render " + data("single_near.gltf") + " -o " + quote(dir / name) + kTiny);
        INFO("stderr: " << r.err);
        REQUIRE(r.code == 0);
        CHECK(r.out.find("4 spp") != std::string::npos);
        CHECK(r.out.find("rays/s") != std::string::npos);
        std::vector<float> rgb = readBack(dir / name, 16, 12);
        float maxValue = 0;
        for (float v : rgb) maxValue = std::max(maxValue, v);
        CHECK(maxValue > 0);
    }
    auto files = dir.files();
    std::sort(files.begin(), files.end());
    CHECK(files == std::vector<std::string>{"fog.exr", "fog.pfm", "fog.png"});  // no temporary files

    // The float formats agree exactly; PNG within its 8-bit sRGB quantisation.
    int w, h;
    std::vector<float> exr = brume::readImage(dir / "fog.exr", &w, &h);
    std::vector<float> pfm = brume::readImage(dir / "fog.pfm", &w, &h);
    std::vector<float> png = brume::readImage(dir / "fog.png", &w, &h);
    CHECK(exr == pfm);
    for (size_t i = 0; i < pfm.size(); ++i) {
        float clamped = std::min(1.0f, std::max(0.0f, pfm[i]));
        REQUIRE(png[i] == Approx(clamped).margin(0.01 + 0.02 * clamped));
    }
}

TEST_CASE("cli: every --connect mode and --no-nee render", "[cli]") {
    TempDir dir;
    for (const char* flags : {"--connect density", "--connect equiangular", "--connect product", "--connect mis",
                              "--connect product --integrator pt", "--connect product --integrator bdpt",
                              "--no-nee --max-depth 3",
                              "--sampler independent", "--sampler sobol --integrator pt",
                              "--integrator pt --guiding on --spp 20 --max-depth 3", "--integrator pt --guiding off",
                              "--integrator pt --guiding on --guided-distances all --spp 20",
                              "--integrator bdpt --guiding on --spp 20 --max-depth 3", "--integrator bdpt --guiding on --spp 20"}) {
        INFO(flags);
        Result r = runBrume("render " + data("single_near.gltf") + " -o " + quote(dir / "m.pfm") + kTiny + " " + flags);
        INFO("stderr: " << r.err);
        CHECK(r.code == 0);
        readBack(dir / "m.pfm", 16, 12);
    }
}

TEST_CASE("cli: 1 and 2 threads give byte-identical images and seeds differ", "[cli]") {
    TempDir dir;
    const std::string scene = data("single_near.gltf");
    REQUIRE(runBrume("render " + scene + " -o " + quote(dir / "t1.pfm") + kTiny + " --threads 1 --seed 5").code == 0);
    REQUIRE(runBrume("render " + scene + " -o " + quote(dir / "t2.pfm") + kTiny + " --threads 2 --seed 5").code == 0);
    REQUIRE(runBrume("render " + scene + " -o " + quote(dir / "s6.pfm") + kTiny + " --threads 2 --seed 6").code == 0);
    std::string t1 = readFile(dir / "t1.pfm"), t2 = readFile(dir / "t2.pfm"), s6 = readFile(dir / "s6.pfm");
    CHECK(t1.size() == 14 + 16 * 12 * 12);  // "PF\n16 12\n-1.0\n" + float RGB
    CHECK(t1 == t2);
    CHECK(t1 != s6);
}

// The default rule (no --spp, --time or threshold, no spp in the scene): every pixel takes
// every pass until the image's estimated relative error is 0.1, decided from the film alone.
TEST_CASE("cli: without --spp or --time a render stops at the default target error with the same bits for 1 and 2 threads", "[cli][adaptive]") {
    TempDir dir;
    const std::string scene = data("single_near.gltf");
    Result one = runBrume("render " + scene + " -o " + quote(dir / "t1.pfm") + " --res 16x12 --integrator pt --threads 1");
    Result two = runBrume("render " + scene + " -o " + quote(dir / "t2.pfm") + " --res 16x12 --integrator pt --threads 2");
    INFO(one.out << one.err);
    REQUIRE(one.code == 0);
    REQUIRE(two.code == 0);
    CHECK(readFile(dir / "t1.pfm") == readFile(dir / "t2.pfm"));
    const size_t at = one.out.find("stopping rule: estimated relative error ");
    REQUIRE(at != std::string::npos);
    const double reached = std::stod(one.out.substr(at + 40));
    CHECK(reached <= 0.1);
    CHECK(one.out.find("not reached") == std::string::npos);
    // It stopped at a decision pass past the first 16 (the summary's spp).
    const size_t spp = one.out.find(" spp, ");
    REQUIRE(spp != std::string::npos);
    const int passes = std::stoi(one.out.substr(one.out.rfind(' ', spp - 1) + 1));
    CHECK(passes >= 16);
    CHECK(passes < 1024);
    // An explicit --target-error ends sooner at a larger error; --spp is a plain count again.
    Result loose = runBrume("render " + scene + " -o " + quote(dir / "l.pfm") + " --res 16x12 --integrator pt --target-error 0.3");
    REQUIRE(loose.code == 0);
    CHECK(loose.out.find("target error: estimated relative error ") != std::string::npos);
    Result counted = runBrume("render " + scene + " -o " + quote(dir / "c.pfm") + " --res 16x12 --integrator pt --spp 3");
    REQUIRE(counted.code == 0);
    CHECK(counted.out.find("16x12, 3 spp") != std::string::npos);
    CHECK(counted.out.find("relative error") == std::string::npos);
}

TEST_CASE("cli: the same render gives the same EXR bytes a second later (no time stamp)", "[cli]") {
    TempDir dir;
    const std::string scene = data("single_near.gltf");
    REQUIRE(runBrume("render " + scene + " -o " + quote(dir / "a.exr") + kTiny).code == 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // header dates have 1 s steps
    REQUIRE(runBrume("render " + scene + " -o " + quote(dir / "b.exr") + kTiny).code == 0);
    CHECK(readFile(dir / "a.exr") == readFile(dir / "b.exr"));
}

TEST_CASE("cli: an empty scene renders black, default size from the aspect ratio", "[cli]") {
    TempDir dir;
    Result r = runBrume("render " + data("empty.gltf") + " -o " + quote(dir / "empty.pfm") + " --spp 1");
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
    std::vector<float> rgb = readBack(dir / "empty.pfm", 640, 640);  // aspectRatio 1
    CHECK(std::count(rgb.begin(), rgb.end(), 0.0f) == long(rgb.size()));

    r = runBrume("render " + data("empty.gltf") + " -o " + quote(dir / "timed.pfm") + " --res 8x8 --time 0.05");
    CHECK(r.code == 0);
    readBack(dir / "timed.pfm", 8, 8);
}

TEST_CASE("image_io: PFM layout, round trips, failures leave nothing", "[cli][io]") {
    TempDir dir;
    const int w = 3, h = 2;
    std::vector<float> rgb(3 * w * h);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.1f * float(i) - 0.3f;
    brume::writeImage(dir / "a.pfm", w, h, rgb);
    std::string bytes = readFile(dir / "a.pfm");
    const std::string header = "PF\n3 2\n-1.0\n";
    REQUIRE(bytes.size() == header.size() + 4 * rgb.size());
    CHECK(bytes.compare(0, header.size(), header) == 0);
    float first;  // bottom row first: pixel (0, 1) red
    std::memcpy(&first, bytes.data() + header.size(), 4);
    CHECK(first == rgb[3 * w]);
    int rw, rh;
    CHECK(brume::readImage(dir / "a.pfm", &rw, &rh) == rgb);

    brume::writeImage(dir / "a.exr", w, h, rgb);
    CHECK(brume::readImage(dir / "a.exr", &rw, &rh) == rgb);

    CHECK_THROWS_AS(brume::writeImage(dir / "a.tiff", w, h, rgb), std::runtime_error);
    CHECK_THROWS_AS(brume::writeImage(dir / "b.pfm", w, h, std::vector<float>(5)), std::runtime_error);
    CHECK_THROWS_AS(brume::writeImage(dir / "nodir/c.exr", w, h, rgb), std::runtime_error);
    fs::create_directory(dir / "d.exr");
    CHECK_THROWS_WITH(brume::writeImage(dir / "d.exr", w, h, rgb), Catch::Contains("d.exr"));
    CHECK_THROWS_AS(brume::readImage(dir / "missing.exr", &rw, &rh), std::runtime_error);
    CHECK_THROWS_AS(brume::checkImageWritable(dir / "x.bmp"), std::invalid_argument);
    CHECK_THROWS_AS(brume::checkImageWritable(dir / "nodir/x.png"), std::runtime_error);
    brume::checkImageWritable(dir / "x.png");

    auto files = dir.files();
    std::sort(files.begin(), files.end());
    CHECK(files == std::vector<std::string>{"a.exr", "a.pfm", "d.exr"});
}

TEST_CASE("cli: every bundled scene renders with no non-finite samples, pt and bdpt", "[cli][scenes]") {
    std::vector<std::string> scenes;
    for (const auto& e : fs::directory_iterator(BRUME_SCENES))
        if (e.path().extension() == ".gltf") scenes.push_back(e.path().string());
    std::sort(scenes.begin(), scenes.end());
    CHECK(scenes.size() >= 6);
    TempDir dir;
    const std::regex summary(R"(64x48, 2 spp, .*, (\d+) non-finite, peak (\d+) MiB)");
    for (const std::string& scene : scenes)
        for (const char* integrator : {"pt", "bdpt"}) {
            INFO(scene << " --integrator " << integrator);
            Result r = runBrume("render " + quote(scene) + " -o " + quote(dir / "s.pfm") +
                                " --res 64x48 --spp 2 --integrator " + integrator);
            INFO("stdout: " << r.out << "stderr: " << r.err);
            REQUIRE(r.code == 0);
            std::smatch m;
            REQUIRE(std::regex_search(r.out, m, summary));
            CHECK(m[1] == "0");
            CHECK(std::stoi(m[2]) > 0);
        }
}

// The default integrator is auto: it says what it chose; --stats lists the candidates;
// --allocation forces one of them on bdpt and names the others when it does not know one.
TEST_CASE("cli: auto reports its choice and --allocation forces a candidate", "[cli][auto]") {
    TempDir dir;
    const std::string scene = data("single_near.gltf");
    Result r = runBrume("render " + scene + " -o " + quote(dir / "a.pfm") + " --res 16x12 --spp 6");
    CHECK(r.code == 0);
    CHECK(r.out.find("\nallocation: ") != std::string::npos);
    // (Decided after the pilot and the duel: 24 passes here.)
    r = runBrume("render " + scene + " -o " + quote(dir / "a.pfm") + " --res 16x12 --spp 24 --stats");
    CHECK(r.code == 0);
    CHECK(r.out.find("chosen") != std::string::npos);
    CHECK(r.out.find("pilot, rays per pass") != std::string::npos);
    r = runBrume("render " + scene + " -o " + quote(dir / "b.pfm") + " --res 16x12 --spp 2 --integrator bdpt --allocation 'pt+ea'");
    CHECK(r.code == 0);
    CHECK(r.out.find("allocation: ") == std::string::npos);
    r = runBrume("render " + scene + " -o " + quote(dir / "c.pfm") + " --res 16x12 --integrator bdpt --allocation nonsense");
    CHECK(r.code == 2);
    CHECK(r.err.find("unknown allocation 'nonsense'") != std::string::npos);
    CHECK(r.err.find("'bdpt lt p=0.25 ea=LC'") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir / "c.pfm"));
    r = runBrume("render " + scene + " -o " + quote(dir / "c.pfm") + " --res 16x12 --allocation pt");
    CHECK(r.code == 2);
    CHECK(r.err.find("--allocation needs --integrator bdpt") != std::string::npos);
}
