// Hostile input: the brume executable on the bad scene files of tests/data/bad/ (written by
// make_bad.py there) and on bad command lines. Each must fail cleanly: exit code 1 or 2 (not a
// signal, not the 124 of `timeout`, not success), one line on stderr naming the file or option
// and the problem, nothing on stdout and no file left in the output directory.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/scratch_files.h"

namespace fs = std::filesystem;

using brume::test::quote;
using brume::test::readFile;
using brume::test::TempDir;
using brume::test::writeFile;

namespace {

const std::string kBad = std::string(BRUME_TEST_DATA) + "/bad";

struct Result {
    bool exited = false;  // false: the shell or timeout itself died of a signal
    int code = -1;
    std::string out, err;
};

// Runs `brume render ARGS` under a 60 s timeout (exit code 124 if it hangs; 128 + N if brume
// dies of signal N), with stdout and stderr captured in a directory of their own.
Result runRender(const std::string& args) {
    TempDir capture;
    std::string command = "timeout -k 5 60 " + quote(BRUME_EXE) + " render " + args + " >" +
                          quote(capture / "out") + " 2>" + quote(capture / "err") + " </dev/null";
    int status = std::system(command.c_str());
    Result r;
    r.exited = WIFEXITED(status);
    r.code = r.exited ? WEXITSTATUS(status) : -1;
    r.out = readFile(capture / "out");
    r.err = readFile(capture / "err");
    return r;
}

// A clean failure with `code`, reported in one line that contains every string of `mentions`.
void checkCleanFailure(const Result& r, int code, const std::vector<std::string>& mentions) {
    INFO("exit code " << r.code << ", stderr: " << r.err << "stdout: " << r.out);
    REQUIRE(r.exited);
    CHECK(r.code != 124);  // timed out: a hang
    CHECK(r.code < 128);   // killed by a signal: a crash
    CHECK(r.code == code);
    CHECK(r.err.rfind("brume: error: ", 0) == 0);
    REQUIRE(!r.err.empty());
    CHECK(r.err.back() == '\n');
    CHECK(r.err.find('\n') == r.err.size() - 1);
    for (const std::string& m : mentions) CHECK(r.err.find(m) != std::string::npos);
    CHECK(r.out.empty());
}

const char* const kTiny = " --res 16x16 --spp 1";

struct BadFile {
    const char* name;
    const char* problem;  // a distinctive part of the message
};

// One case per file in tests/data/bad/ but valid_base.gltf (make_bad.py's docstrings say
// what each breaks).
const BadFile kBadFiles[] = {
    {"truncated.glb", "GLB: truncated: the header declares"},
    {"broken_json.gltf", "JSON: [json.exception.parse_error"},
    {"buffer_view_out_of_range.gltf", "bufferViews[0]: byteOffset 52 + byteLength 48 exceeds the 60 bytes"},
    {"index_out_of_range.gltf", "indices: element 4 of accessors[1] is 7, but there are only 4 vertices"},
    {"nan_position.gltf", "element 1 component 1 is nan (used as meshes[0].primitives[0].attributes.POSITION)"},
    {"missing_texture.gltf", "images[0].uri: cannot load 'no_such_texture.png'"},
    {"orthographic_camera.gltf", "cameras[0].type: orthographic cameras are not supported"},
    {"no_camera.gltf", "cameras: no perspective camera"},
    {"medium_out_of_range.gltf", "BRUME_media.interior: medium 3 out of range (1 in file)"},
    {"cyclic_nodes.gltf", "cycle in the node hierarchy: node 1 -> node 3 -> node 1"},
    {"grid_missing_file.gltf", "density.uri: cannot open '"},
    {"grid_not_vdb.gltf", "not_a_grid.vdb: cannot read the OpenVDB file"},
    {"grid_missing_name.gltf", "smoke_ok.vdb: no grid named \"temperature\""},
    {"grid_vector.gltf", "vector.vdb: grid \"density\" holds vec3s values, not float"},
    {"grid_negative_voxel.gltf", "negative.vdb: grid \"density\" has a negative voxel value -1.000000 at (2, 1, 3)"},
    {"grid_nan_voxel.gltf", "nan.vdb: grid \"density\" has a NaN voxel value"},
    {"grid_infinite_voxel.gltf", "infinite.vdb: grid \"density\" has an infinite voxel value inf at (1, 2, 3)"},
    {"grid_frustum.gltf", "frustum.vdb: grid \"density\" has a non-affine (NonlinearFrustumMap) transform"},
    {"grid_negative_scale.gltf", "density.scale: scale -2 must be finite and >= 0"},
    {"grid_too_dense.gltf", "smoke_ok.vdb: grid \"density\": optical depth 1374999.99 across one voxel"},
    {"emission_negative.gltf", "media[0].emission: negative coefficient -0.5"},
    {"blackbody_intensity.gltf", "media[0].blackbody.intensity: 2 is outside [0, 1]"},
    {"blackbody_and_emission.gltf", "media[0].blackbody: a blackbody temperature grid cannot be combined with \"emission\""},
    {"blackbody_empty.gltf", "media[0].blackbody: expected \"temperature\" (kelvin) or a temperature grid"},
    {"emission_missing_grid.gltf", "media[0].emission.uri: cannot open '"},
    {"emission_ambient_clear.gltf", "media[0].emission: the ambient medium emits in a channel where it has no extinction"},
    {"emission_ambient_grid.gltf", "media[0].emission: the ambient medium has a density grid and emission without a grid"},
    {"camera_invisible_opaque.gltf", "materials[0].extras.cameraVisible: false needs \"transparent\": true"},
    {"transparent_not_bool.gltf", "materials[0].extras.transparent: expected true or false"},
};

// The density grids the grid_*.gltf files point at (make_bad.py).
const char* const kBadGridFiles[] = {"smoke_ok.vdb", "negative.vdb", "nan.vdb", "infinite.vdb", "vector.vdb",
                                     "frustum.vdb", "not_a_grid.vdb"};

}  // namespace

TEST_CASE("bad inputs: every file in tests/data/bad has a case", "[cli][bad]") {
    std::vector<std::string> files, expected{"make_bad.py", "valid_base.gltf"};
    for (const auto& e : fs::directory_iterator(kBad)) files.push_back(e.path().filename().string());
    for (const BadFile& f : kBadFiles) expected.push_back(f.name);
    for (const char* f : kBadGridFiles) expected.push_back(f);
    std::sort(files.begin(), files.end());
    std::sort(expected.begin(), expected.end());
    CHECK(files == expected);
}

TEST_CASE("bad inputs: the scene they are made from renders", "[cli][bad]") {
    TempDir dir;
    Result r = runRender(quote(kBad + "/valid_base.gltf") + " -o " + quote(dir / "out.png") + kTiny);
    INFO("stderr: " << r.err);
    REQUIRE(r.exited);
    CHECK(r.code == 0);
    CHECK(dir.files() == std::vector<std::string>{"out.png"});
}

TEST_CASE("bad inputs: bad scene files fail with one line naming the file and the problem", "[cli][bad]") {
    for (const BadFile& f : kBadFiles) {
        INFO(f.name);
        TempDir dir;
        const std::string scene = kBad + "/" + f.name;
        Result r = runRender(quote(scene) + " -o " + quote(dir / "out.png") + kTiny);
        checkCleanFailure(r, 1, {scene + ": ", f.problem});
        CHECK(dir.files().empty());
    }
}

TEST_CASE("bad inputs: an absurd --res and --spp 0 are refused before anything is done", "[cli][bad]") {
    TempDir dir;
    const std::string start = quote(kBad + "/valid_base.gltf") + " -o " + quote(dir / "out.png");
    Result r = runRender(start + " --spp 1 --res 100000x100000");
    checkCleanFailure(r, 2, {"--res: 100000x100000", "at most 16384", "bytes a pixel"});
    r = runRender(start + " --spp 1 --res 16384x16384");
    checkCleanFailure(r, 2, {"--res: 16384x16384", "2^27 pixels", "bytes a pixel"});
    r = runRender(start + " --res 16x16 --spp 0");
    checkCleanFailure(r, 2, {"--spp: 0 is out of range"});
    CHECK(dir.files().empty());
}

TEST_CASE("bad inputs: an output path that cannot be written fails before rendering", "[cli][bad]") {
    TempDir dir;
    { std::ofstream(dir / "plain") << "a regular file\n"; }
    const std::string scene = quote(kBad + "/valid_base.gltf");
    struct Case {
        std::string output, problem;
    } cases[] = {
        {dir / "missing/out.png", "cannot create a file in " + dir / "missing"},
        {dir / "plain/out.exr", "Not a directory"},
        {"/proc/brume-bad-input.png", "cannot create a file in /proc"},
    };
    for (const Case& c : cases) {
        INFO(c.output);
        // A scene that renders for a long time if it got that far: the check must come first.
        Result r = runRender(scene + " -o " + quote(c.output) + " --res 64x64 --spp 100000");
        checkCleanFailure(r, 1, {c.output + ": ", c.problem});
        CHECK(dir.files() == std::vector<std::string>{"plain"});
        CHECK(readFile(dir / "plain") == "a regular file\n");
        CHECK(!fs::exists(c.output));
    }
}
