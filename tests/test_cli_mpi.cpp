// One render over several MPI ranks (`mpirun -np N brume render ...`, docs/mpi.md), on this
// machine (--oversubscribe): the image is the single-process image bit for bit, for pt, bdpt
// and auto on 2 and 3 ranks; a checkpoint made on 3 ranks resumes on 2 to the same bits; a
// rank started with other arguments is refused before rendering; a killed rank fails the job
// and leaves the last checkpoint readable. Tagged [mpi] (CTest label "mpi"); without an MPI
// build (BRUME_TEST_MPI 0) or without mpirun they pass with a warning that they did not run.
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "brume/render/checkpoint.h"
#include "support/run_brume.h"
#include "support/scratch_files.h"

using namespace brume;
using namespace brume::test;
namespace fs = std::filesystem;

namespace {

const std::string kScene = std::string(BRUME_SCENES) + "/bench_fog_room.gltf";

bool mpiAvailable() {
    if (!BRUME_TEST_MPI) return false;
    return std::system("command -v mpirun >/dev/null 2>&1") == 0;
}

// mpirun as root (CI) and with more ranks than cores.
std::string mpirun(int ranks) {
    return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
           "mpirun --oversubscribe -np " +
           std::to_string(ranks) + " ";
}

struct Run {
    int code = -1;
    std::string out, err;
};

Run shell(const std::string& command) {
    TempDir capture;
    const std::string full = "(" + command + ") >" + quote(capture / "out") + " 2>" + quote(capture / "err") +
                             " </dev/null";
    const int status = std::system(full.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(capture / "out"), readFile(capture / "err")};
}

const std::string kRender = " render " + quote(kScene) + " --res 48x36 --threads 1 ";

}  // namespace

TEST_CASE("mpi: 2 and 3 ranks give the single-process image, bit for bit", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    for (const char* integrator : {"pt", "bdpt", "auto"}) {
        const std::string flags = kRender + "--spp 9 --seed 5 --integrator " + integrator;
        const std::string single = dir / (std::string(integrator) + "_1.exr");
        BrumeResult one = runBrume(flags + " -o " + quote(single));
        REQUIRE(one.code == 0);
        for (int ranks : {2, 3}) {
            const std::string out = dir / (std::string(integrator) + "_" + std::to_string(ranks) + ".exr");
            Run r = shell(mpirun(ranks) + quote(BRUME_EXE) + flags + " -o " + quote(out));
            INFO(integrator << " on " << ranks << " ranks: " << r.err);
            REQUIRE(r.code == 0);
            CHECK(r.out.find("ranks: " + std::to_string(ranks)) != std::string::npos);
            CHECK(readFile(out) == readFile(single));
        }
    }
}

// bdpt in single scattering beside a point light renders by the one-event split, which checks
// light tracing's share over its first 8 Sobol passes after 4 learning passes and may turn light
// tracing off (direct_light_tracing.h): every rank renders those 12 passes itself, so all decide
// alike. (Before, the ranks shared the check's passes and each decided from its own part: the
// images differed.)
TEST_CASE("mpi: bdpt in single scattering, its check of light tracing included, gives the single-process image",
          "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string flags = kRender + "--spp 16 --seed 5 --integrator bdpt --max-depth 1 --stats";
    const std::string single = dir / "single.exr", out = dir / "ranks.exr";
    BrumeResult one = runBrume(flags + " -o " + quote(single));
    REQUIRE(one.code == 0);
    CHECK(one.out.find("checked with Sobol numbers") != std::string::npos);
    Run r = shell(mpirun(2) + quote(BRUME_EXE) + flags + " -o " + quote(out));
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("checked with Sobol numbers") != std::string::npos);
    CHECK(readFile(out) == readFile(single));
}

// --guiding auto (the default) with 72 passes: the path tracer starts its guide after its
// shares (pass 4); every rank renders the training passes itself and starts the same guide,
// so 2 ranks give the single-process image, which differs from the unguided one.
TEST_CASE("mpi: --guiding auto guides as one process does", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string flags = kRender + "--spp 72 --seed 5 --integrator pt";
    const std::string single = dir / "single.exr", off = dir / "off.exr", out = dir / "two.exr";
    REQUIRE(runBrume(flags + " -o " + quote(single)).code == 0);
    REQUIRE(runBrume(flags + " --guiding off -o " + quote(off)).code == 0);
    CHECK(readFile(off) != readFile(single));
    Run r = shell(mpirun(2) + quote(BRUME_EXE) + flags + " -o " + quote(out));
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(readFile(out) == readFile(single));
}

TEST_CASE("mpi: a checkpoint made on 3 ranks resumes on 2 to the same bits", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    for (const char* integrator : {"pt", "auto"}) {
        const std::string flags = kRender + "--spp 12 --integrator " + integrator;
        const std::string single = dir / "single.exr", out = dir / "out.exr", ckpt = dir / "state.ckpt";
        REQUIRE(runBrume(flags + " -o " + quote(single)).code == 0);
        // Stopped (as by SIGTERM) after rank 0's second pass: the ranks agree, write the
        // passes done so far and the checkpoint, and exit with 143.
        Run first = shell(mpirun(3) + quote(BRUME_EXE) + flags + " -o " + quote(out) + " --checkpoint " + quote(ckpt) +
                          " --stop-after-passes 2");
        INFO(integrator << ": " << first.err);
        CHECK(first.code != 0);
        REQUIRE(fs::exists(ckpt));
        const int saved = readCheckpoint(ckpt).film.passes();
        CHECK(saved > 0);
        CHECK(saved < 12);
        Run second = shell(mpirun(2) + quote(BRUME_EXE) + flags + " -o " + quote(out) + " --checkpoint " + quote(ckpt) +
                           " --resume " + quote(ckpt));
        INFO(second.err);
        REQUIRE(second.code == 0);
        CHECK(readFile(out) == readFile(single));
        CHECK_FALSE(fs::exists(ckpt));  // complete: removed
    }
}

// A checkpoint that rank 0 refuses (another seed here) fails the job with rank 0's message; the
// other ranks, which do not read it, do not wait for its passes (before, every rank waited: the
// job hung with no word; `timeout` turns a hang into exit code 124).
TEST_CASE("mpi: a checkpoint rank 0 refuses fails the job with its message", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string flags = kRender + "--spp 8", out = dir / "out.exr", ckpt = dir / "state.ckpt";
    BrumeResult first = runBrume(flags + " -o " + quote(out) + " --checkpoint " + quote(ckpt) + " --stop-after-passes 2");
    CHECK(first.code != 0);
    REQUIRE(fs::exists(ckpt));
    fs::remove(out);
    Run r = shell("timeout 120 env " + mpirun(2) + quote(BRUME_EXE) + flags + " --seed 7 -o " + quote(out) + " --resume " +
                  quote(ckpt));
    INFO(r.err);
    CHECK(r.code != 0);
    CHECK(r.code != 124);
    CHECK(r.err.find("cannot resume this render") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("mpi: a rank started with other arguments is refused before rendering", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string out = dir / "out.exr";
    const std::string a = quote(BRUME_EXE) + kRender + "--spp 2 -o " + quote(out);
    Run r = shell("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 1 " + a +
                  " --seed 1 : -np 1 " + a + " --seed 2");
    INFO(r.err);
    CHECK(r.code != 0);
    CHECK(r.err.find("rank 1 started with other arguments or another scene file than rank 0") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
}

// A rank whose own set-up fails where rank 0's does not (here: its scene file is missing where it
// runs) says so itself, naming itself: rank 0 has nothing to report.
TEST_CASE("mpi: a rank that alone fails to load its scene reports it", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string out = dir / "out.exr", missing = dir / "missing.gltf";
    const std::string a = quote(BRUME_EXE) + kRender + "--spp 2 -o " + quote(out);
    const std::string b = quote(BRUME_EXE) + " render " + quote(missing) + " --res 48x36 --threads 1 --spp 2 -o " + quote(out);
    Run r = shell("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 1 " + a +
                  " : -np 1 " + b);
    INFO(r.err);
    CHECK(r.code != 0);
    CHECK(r.err.find("brume: rank 1: ") != std::string::npos);
    CHECK(r.err.find("missing.gltf") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
}

// A pass that throws on one rank (a fault made for tests, as running out of memory would)
// ends the job on every rank with that rank's message, and nothing is written. Before, the
// rank left the render loop and the others waited for it in a collective: the job hung, silent
// (timeout's 124 here).
TEST_CASE("mpi: a pass that fails on one rank ends the job with its message", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string out = dir / "out.exr";
    for (const char* fault : {"1:0", "1:5", "0:5", "2:6"}) {
        INFO(fault);
        Run r = shell("timeout 120 env " + mpirun(3) + quote(BRUME_EXE) + kRender + "--spp 12 -o " + quote(out) +
                      " --fail-at-pass " + fault);
        INFO(r.err);
        CHECK(r.code == 1);
        CHECK(r.err.find("brume: rank " + std::string(1, fault[0]) + ": a fault made for tests at pass " +
                         std::string(fault + 2)) != std::string::npos);
        if (fault[0] != '0') CHECK(r.err.find("brume: the render failed on another rank; nothing written") != std::string::npos);
        CHECK_FALSE(fs::exists(out));
    }
    // A fault at a pass the render never reaches changes nothing.
    Run r = shell("timeout 120 env " + mpirun(2) + quote(BRUME_EXE) + kRender + "--spp 4 -o " + quote(out) +
                  " --fail-at-pass 1:40");
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(fs::exists(out));
}

// Adaptive stopping decides after every pass from the whole film: not over several processes.
TEST_CASE("mpi: --noise-threshold is refused under mpirun", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string out = dir / "out.exr";
    Run r = shell(mpirun(2) + quote(BRUME_EXE) + kRender + "--noise-threshold 0.1 -o " + quote(out));
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.find("--noise-threshold needs a single process") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("mpi: a killed rank fails the job and the last checkpoint stays valid", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    const std::string out = dir / "out.exr", ckpt = dir / "state.ckpt", marker = dir / "rank1.pid";
    // A long render that saves every 0.2 s; rank 1 writes its pid for the test to kill.
    const std::string job = mpirun(2) + "sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then echo $$ > " + quote(marker) +
                            "; fi; exec " + quote(BRUME_EXE) + kRender + "--spp 100000 --integrator pt -o " + quote(out) +
                            " --checkpoint " + quote(ckpt) + " --checkpoint-every 0.2'";
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        const std::string full = job + " >" + quote(dir / "job.out") + " 2>" + quote(dir / "job.err") + " </dev/null";
        ::execl("/bin/sh", "sh", "-c", full.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!(fs::exists(ckpt) && fs::exists(marker)) && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    REQUIRE(fs::exists(ckpt));
    const pid_t rank1 = pid_t(std::stol(readFile(marker)));
    ::kill(rank1, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    INFO(readFile(dir / "job.err"));
    CHECK((!WIFEXITED(status) || WEXITSTATUS(status) != 0));
    CHECK_FALSE(fs::exists(out));
    Checkpoint c = readCheckpoint(ckpt);  // throws if damaged
    CHECK(c.film.passes() > 0);
}

// A build without MPI under mpirun would render the whole image in every process, to the same
// file: it refuses, with one line naming the cause, and writes nothing. (In an MPI build there
// is nothing to check.)
TEST_CASE("mpi: a build without MPI refuses to run as one of several processes", "[mpi][cli]") {
    if (BRUME_TEST_MPI) {
        WARN("an MPI build: nothing to check");
        return;
    }
    TempDir dir;
    const std::string out = dir / "a.pfm";
    Run r = shell("OMPI_COMM_WORLD_SIZE=2 " + quote(BRUME_EXE) + kRender + "--spp 1 -o " + quote(out));
    CHECK(r.code == 1);
    CHECK(r.err.find("built without MPI") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
    r = shell("PMI_SIZE=3 " + quote(BRUME_EXE) + kRender + "--spp 1 -o " + quote(out));
    CHECK(r.code == 1);
    // One process under a launcher is a plain render.
    r = shell("OMPI_COMM_WORLD_SIZE=1 " + quote(BRUME_EXE) + kRender + "--spp 1 -o " + quote(out));
    CHECK(r.code == 0);
    CHECK(fs::exists(out));
}

TEST_CASE("mpi: the scene's warnings are printed once, by rank 0", "[mpi][cli]") {
    if (!mpiAvailable()) {
        WARN("no MPI build or no mpirun: not run");
        return;
    }
    TempDir dir;
    std::string text = readFile(std::string(BRUME_TEST_DATA) + "/bad/valid_base.gltf");
    const std::string name = "\"name\": \"fog\",";
    REQUIRE(text.find(name) != std::string::npos);
    text.replace(text.find(name), name.size(), name + " \"emision\": [1, 1, 1],");
    writeFile(dir / "misspelt.gltf", text);
    Run r = shell(mpirun(3) + quote(BRUME_EXE) + " render " + quote(dir / "misspelt.gltf") + " --res 16x12 --spp 2 --threads 1 -o " +
                  quote(dir / "out.exr"));
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string warning = "unknown field \"emision\"";
    const size_t first = r.err.find(warning);
    CHECK(first != std::string::npos);
    CHECK(r.err.find(warning, first + 1) == std::string::npos);
}
