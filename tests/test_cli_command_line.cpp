// The command-line conventions every brume command shares (CLI11 underneath): --help,
// "--flag=value", "--flag value", "-o value", "--", the last value of a repeated option, and
// one-line errors with exit code 2 for what the parser itself rejects.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "brume/film/image_io.h"
#include "support/run_brume.h"
#include "support/scratch_files.h"

using brume::test::BrumeResult;
using brume::test::quote;
using brume::test::runBrume;
using brume::test::readFile;
using brume::test::TempDir;

namespace {

using Result = BrumeResult;

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

const std::string kScene = quote(std::string(BRUME_TEST_DATA) + "/single_near.gltf");

}  // namespace

TEST_CASE("command line: each command's --help lists its options and exits 0", "[cli]") {
    struct Case {
        const char* command;
        std::vector<const char*> options;
    } cases[] = {
        {"render", {"-o, --output OUT", "--spp N", "--res WxH", "--no-nee", "--checkpoint-every SECONDS"}},
        {"bench", {"-o, --out DIR", "--methods LIST", "--reference-method M", "--no-chart", "--max-depth N", "bdpt:mis-exact", "bdpt:mis-general"}},
        {"raybench", {"--threads N", "--spp N", "--res WxH"}},
    };
    for (const Case& c : cases) {
        INFO(c.command);
        Result r = runBrume(c.command + std::string(" --help"));
        CHECK(r.code == 0);
        CHECK(r.err.empty());
        CHECK(r.out.rfind(std::string("usage: brume ") + c.command + " SCENE", 0) == 0);
        CHECK(contains(r.out, "-h, --help"));
        for (const char* option : c.options) CHECK(contains(r.out, option));
        CHECK_FALSE(contains(r.out, "--stop-after-passes"));  // a testing aid, not for users
    }
    Result r = runBrume("raybench -h");
    CHECK(r.code == 0);
    CHECK(r.out.rfind("usage: brume raybench", 0) == 0);
}

TEST_CASE("command line: --flag=value, -o value, -- and the last of a repeated option", "[cli]") {
    TempDir dir;
    Result r = runBrume("render --res=8x6 --spp 1 --spp=2 -o " + quote(dir / "x.png") + " -o " +
                        quote(dir / "y.pfm") + " -- " + kScene);
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
    CHECK(contains(r.out, "8x6, 2 spp"));
    CHECK(dir.files() == std::vector<std::string>{"y.pfm"});
    int w = 0, h = 0;
    brume::readImage(dir / "y.pfm", &w, &h);
    CHECK(w == 8);
    CHECK(h == 6);
}

TEST_CASE("command line: what the parser rejects is one line and exit code 2", "[cli]") {
    TempDir dir;
    const std::string render = "render " + kScene + " -o " + quote(dir / "o.pfm") + " --res 8x8 --spp 1";
    struct Case {
        std::string args, message;
    } cases[] = {
        {render + " --spp", "brume: error: --spp needs a value\n"},
        {render + " --no-nee=1", "brume: error: --no-nee takes no value\n"},
        {render + " --bogus 3", "brume: error: unknown option '--bogus'\n"},
        {render + " -q", "brume: error: unknown option '-q'\n"},
        {render + " " + kScene, "brume: error: more than one scene given ("},
        {"raybench " + kScene + " --res", "brume: error: --res needs a value\n"},
        {"bench " + kScene + " --out " + quote(dir / "b") + " --no-chart=yes", "brume: error: --no-chart takes no value\n"},
        {"bench " + kScene + " --out " + quote(dir / "b") + " --budget 1", "brume: error: unknown option '--budget'\n"},
    };
    for (const Case& c : cases) {
        INFO("brume " << c.args);
        Result r = runBrume(c.args);
        CHECK(r.code == 2);
        CHECK(r.err.rfind(c.message, 0) == 0);
        CHECK(r.err.find('\n') == r.err.size() - 1);
        CHECK(r.out.empty());
    }
    CHECK(dir.files().empty());
}
