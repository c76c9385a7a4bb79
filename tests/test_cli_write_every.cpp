// `brume render --write-every SECONDS`: the image of the passes so far is written while the
// render runs, and the final image is the one a render without the option writes, bit for bit.
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "brume/film/image_io.h"
#include "support/run_brume.h"

using namespace brume::test;

namespace {

const std::string kScene = quote(std::string(BRUME_SCENES) + "/street.gltf");

bool exists(const std::string& path) { return std::ifstream(path).good(); }

}  // namespace

TEST_CASE("render --write-every: an image appears while rendering; the final one is unchanged", "[cli]") {
    TempDir dir;
    const std::string common = kScene + " --res 32x24 --spp 300 --seed 3 --threads 1 --integrator pt";
    // In the background, in a subshell that waits for it and then writes its exit code to
    // `done` (no pid polling: an orphan's zombie may outlive it), so that the image can be
    // seen before the render ends.
    const std::string command = "(" + quote(BRUME_EXE) + " render " + common + " -o " + quote(dir / "watch.exr") +
                                " --write-every 0.2 >/dev/null 2>" + quote(dir / "err") + "; echo $? >" +
                                quote(dir / "done.tmp") + "; mv " + quote(dir / "done.tmp") + " " + quote(dir / "done") +
                                ") </dev/null >/dev/null 2>&1 &";
    REQUIRE(std::system(command.c_str()) == 0);
    bool seenWhileRunning = false;
    for (int i = 0; i < 600 && !seenWhileRunning && !exists(dir / "done"); ++i) {  // up to 60 s
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        if (exists(dir / "watch.exr") && !exists(dir / "done")) seenWhileRunning = true;
    }
    CHECK(seenWhileRunning);
    if (seenWhileRunning) {
        int w = 0, h = 0;
        brume::readImage(dir / "watch.exr", &w, &h);  // a whole image, not a half-written one
        CHECK(w == 32);
        CHECK(h == 24);
    }
    for (int i = 0; i < 1200 && !exists(dir / "done"); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    REQUIRE(exists(dir / "done"));
    int code = -1;
    std::ifstream(dir / "done") >> code;
    CHECK(code == 0);
    CHECK(readFile(dir / "err").empty());
    const BrumeResult plain = runBrume("render " + common + " -o " + quote(dir / "plain.exr"));
    REQUIRE(plain.code == 0);
    CHECK(readFile(dir / "watch.exr") == readFile(dir / "plain.exr"));
}

TEST_CASE("render --write-every: a value that is not a positive number is refused", "[cli]") {
    TempDir dir;
    for (const char* bad : {"0", "-1", "soon"}) {
        INFO(bad);
        const BrumeResult r = runBrume("render " + kScene + " -o " + quote(dir / "o.exr") + " --res 8x8 --spp 1 --write-every " + bad);
        CHECK(r.code == 2);
        CHECK(r.err.rfind("brume: error: --write-every", 0) == 0);
        CHECK(dir.files().empty());
    }
}
