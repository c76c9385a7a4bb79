// A 10-million-triangle scene (tests/data/make_big_mesh.py, written to a temporary directory)
// loads and renders in under 4 GiB, by the peak memory that brume render reports. Long: the
// scene is ~240 MB and takes seconds to write and to build.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "support/scratch_files.h"

namespace fs = std::filesystem;

using brume::test::quote;
using brume::test::readFile;
using brume::test::TempDir;
using brume::test::writeFile;

namespace {

// Runs a shell command with stdout into `out`; the exit status, or -1 if it did not exit.
int shell(const std::string& command, const std::string& out) {
    int status = std::system((command + " >'" + out + "' 2>&1 </dev/null").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("cli: a 10-million-triangle scene renders in under 4 GiB", "[cli][long]") {
    TempDir dir;
    const std::string scene = dir / "big.glb";
    int code = shell("/usr/bin/python3 '" + std::string(BRUME_TEST_DATA) + "/make_big_mesh.py' '" + scene + "'",
                     dir / "gen.txt");
    const std::string generated = readFile(dir / "gen.txt");
    INFO(generated);
    REQUIRE(code == 0);
    CHECK(generated.find("10000000 triangles") != std::string::npos);

    auto start = std::chrono::steady_clock::now();
    code = shell(std::string("'") + BRUME_EXE + "' render '" + scene + "' -o '" + (dir / "big.pfm") +
                     "' --res 160x120 --spp 4",
                 dir / "render.txt");
    double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string out = readFile(dir / "render.txt");
    INFO(out);
    REQUIRE(code == 0);
    std::smatch m;
    const std::regex summary(R"(160x120, 4 spp, ([0-9.]+) s, .* (\d+) non-finite, peak (\d+) MiB)");
    REQUIRE(std::regex_search(out, m, summary));
    const double renderSeconds = std::stod(m[1]);
    const int peakMiB = std::stoi(m[3]);
    WARN("10M triangles: " << wall - renderSeconds << " s to load and build (and write the image), "
                           << renderSeconds << " s to render 160x120 at 4 spp, peak " << peakMiB << " MiB");
    CHECK(m[2] == "0");
    CHECK(peakMiB > 0);
    CHECK(peakMiB < 4096);
}
