// brume render stopped and continued, run as a user would: an interrupted render resumed from
// its checkpoint gives the same bytes as one that ran straight through (pt and bdpt, whose
// light-tracing splats live in a film of their own); SIGINT and SIGTERM give exit codes 130
// and 143 and an image of whole passes; a checkpoint that is damaged or made with other
// settings is a one-line error.
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "brume/render/checkpoint.h"
#include "brume/film/image_io.h"

#include "support/scratch_files.h"

namespace fs = std::filesystem;

using brume::test::quote;
using brume::test::readFile;
using brume::test::TempDir;
using brume::test::writeFile;

namespace {

using Args = std::vector<std::string>;

struct Result {
    int code = -1;  // the exit status, or minus the signal that killed it
    std::string out, err;
};

// `brume render ARGS` as a child process, stdout and stderr into files of its own directory.
class Child {
public:
    explicit Child(const Args& args) {
        std::vector<std::string> argv = {BRUME_EXE, "render"};
        argv.insert(argv.end(), args.begin(), args.end());
        pid_ = ::fork();
        REQUIRE(pid_ >= 0);
        if (pid_ == 0) {
            std::freopen("/dev/null", "r", stdin);
            std::freopen((capture_ / "out").c_str(), "w", stdout);
            std::freopen((capture_ / "err").c_str(), "w", stderr);
            std::vector<char*> cargv;
            for (std::string& a : argv) cargv.push_back(a.data());
            cargv.push_back(nullptr);
            ::execv(cargv[0], cargv.data());
            std::_Exit(127);
        }
    }
    void signal(int sig) { ::kill(pid_, sig); }
    Result wait() {
        int status = 0;
        ::waitpid(pid_, &status, 0);
        Result r;
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
        r.out = readFile(capture_ / "out");
        r.err = readFile(capture_ / "err");
        return r;
    }

private:
    TempDir capture_;
    pid_t pid_ = -1;
};

Result run(const Args& args) { return Child(args).wait(); }

std::string data(const std::string& name) { return std::string(BRUME_TEST_DATA) + "/" + name; }

// The spp of the summary line "OUT: WxH, N spp, ...".
int summarySpp(const std::string& out) {
    std::smatch m;
    REQUIRE(std::regex_search(out, m, std::regex(R"(: \d+x\d+, (\d+) spp,)")));
    return std::stoi(m[1]);
}

void checkOneLineError(const Result& r, const std::string& mention) {
    INFO("stderr: " << r.err);
    CHECK(r.code == 1);
    CHECK(r.err.rfind("brume: error: ", 0) == 0);
    CHECK(r.err.find(mention) != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
}

const Args kSmall = {"--res", "40x30", "--spp", "6"};

Args operator+(Args a, const Args& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

// Each stop: the render `args` stopped by SIGTERM after that many passes with a checkpoint at
// `ckpt`, then resumed on one thread into `out`, gives the bytes of `straight`.
void checkResumes(const Args& args, const std::string& ckpt, const std::string& out, const std::string& straight,
                  std::initializer_list<const char*> stops) {
    for (const char* stop : stops) {
        INFO("stopped after " << stop << " passes");
        REQUIRE(run(args + Args{"-o", out, "--checkpoint", ckpt, "--stop-after-passes", stop}).code == 143);
        const Result r = run(args + Args{"-o", out, "--resume", ckpt, "--threads", "1"});
        CHECK(r.code == 0);
        CHECK(readFile(out) == readFile(straight));
    }
}

}  // namespace

TEST_CASE("cli checkpoint: stopped twice and resumed gives the same bytes as straight through", "[cli][checkpoint]") {
    for (const char* integrator : {"pt", "bdpt", "auto"}) {
        INFO("--integrator " << integrator);
        TempDir dir;
        const Args common = Args{data("bdpt_quad_fogbox.gltf"), "--integrator", integrator} + kSmall;
        const std::string ckpt = dir / "c.ckpt";

        Result r = run(common + Args{"-o", dir / "straight.pfm", "--threads", "2"});
        REQUIRE(r.code == 0);
        REQUIRE(run(common + Args{"-o", dir / "straight.exr"}).code == 0);

        // Stopped after 2 passes: exit code of SIGTERM, an image of 2 whole passes, a checkpoint.
        r = run(common + Args{"-o", dir / "b.pfm", "--checkpoint", ckpt, "--stop-after-passes", "2"});
        INFO("stderr: " << r.err);
        CHECK(r.code == 143);
        CHECK(summarySpp(r.out) == 2);
        CHECK(r.err.find("after 2 of 6 passes") != std::string::npos);
        const Args two = {data("bdpt_quad_fogbox.gltf"), "--integrator", integrator, "--res", "40x30", "--spp", "2"};
        REQUIRE(run(two + Args{"-o", dir / "two.pfm"}).code == 0);
        CHECK(readFile(dir / "b.pfm") == readFile(dir / "two.pfm"));
        CHECK(brume::readCheckpoint(ckpt).film.passes() == 2);

        // Resumed with another thread count, stopped again after one more pass.
        r = run(common + Args{"-o", dir / "b.pfm", "--checkpoint", ckpt, "--resume", ckpt, "--threads", "1",
                              "--stop-after-passes", "1"});
        CHECK(r.code == 143);
        CHECK(summarySpp(r.out) == 3);
        CHECK(r.err.find("resuming") != std::string::npos);

        // Resumed to the end: the same bytes, the checkpoint is gone.
        r = run(common + Args{"-o", dir / "b.pfm", "--checkpoint", ckpt, "--resume", ckpt});
        CHECK(r.code == 0);
        CHECK(summarySpp(r.out) == 6);
        CHECK(readFile(dir / "b.pfm") == readFile(dir / "straight.pfm"));
        CHECK_FALSE(fs::exists(ckpt));

        // EXR files carry a time stamp, so their pixels are compared.
        REQUIRE(run(common + Args{"-o", dir / "b.exr", "--checkpoint", ckpt, "--stop-after-passes", "4"}).code == 143);
        REQUIRE(run(common + Args{"-o", dir / "b.exr", "--resume", ckpt}).code == 0);
        int w, h;
        CHECK(brume::readImage(dir / "b.exr", &w, &h) == brume::readImage(dir / "straight.exr", &w, &h));
        CHECK(brume::readImage(dir / "b.exr", &w, &h) == brume::readImage(dir / "straight.pfm", &w, &h));
        CHECK(fs::exists(ckpt));  // --resume alone leaves it (nothing named it --checkpoint)
    }
}

// bdpt in single scattering beside a sphere light (the one-event split): stopped while light
// tracing's factor is learnt (passes 0–3), while its check and the path tracer's connection
// shares learn (4–11), and after, it resumes to the same bytes.
TEST_CASE("cli checkpoint: bdpt's single-scattering split resumes while its shares learn", "[cli][checkpoint]") {
    TempDir dir;
    const Args args = {data("sphere_light_fog.gltf"), "--integrator", "bdpt", "--max-depth", "1", "--res", "40x30",
                       "--spp", "16", "--seed", "5"};
    REQUIRE(run(args + Args{"-o", dir / "straight.pfm", "--threads", "2"}).code == 0);
    checkResumes(args, dir / "c.ckpt", dir / "b.pfm", dir / "straight.pfm", {"2", "6", "11", "13"});
}

// Adaptive stopping (--noise-threshold) decides from the film alone, whose per-pixel counts
// and squares the checkpoint keeps: stopped before any pixel stopped, while pixels stop, and
// (auto) inside its learning passes, it resumes to the same bytes; the threshold is a setting.
TEST_CASE("cli checkpoint: adaptive stopping resumes to the same bytes", "[cli][checkpoint][adaptive]") {
    for (const char* integrator : {"pt", "bdpt", "auto"}) {
        INFO("--integrator " << integrator);
        TempDir dir;
        const Args common = {data("bdpt_quad_fogbox.gltf"), "--integrator", integrator, "--res", "40x30",
                             "--spp", "64", "--noise-threshold", "0.05"};
        const std::string ckpt = dir / "c.ckpt";
        Result r = run(common + Args{"-o", dir / "straight.pfm"});
        REQUIRE(r.code == 0);
        // Pixels stopped at different passes, the last after the stops below.
        std::smatch m;
        REQUIRE(std::regex_search(r.out, m, std::regex(R"(adaptive: ([0-9.]+) spp on average)")));
        INFO(r.out);
        CHECK(std::stod(m[1]) < summarySpp(r.out));
        CHECK(summarySpp(r.out) > 30);
        checkResumes(common, ckpt, dir / "b.pfm", dir / "straight.pfm", {"10", "18", "30"});
        // Without the threshold, or with another, the checkpoint does not continue.
        Args plain = {data("bdpt_quad_fogbox.gltf"), "--integrator", integrator, "--res", "40x30", "--spp", "64"};
        checkOneLineError(run(plain + Args{"-o", dir / "c.pfm", "--resume", ckpt}), "--noise-threshold");
        Args other = plain + Args{"--noise-threshold", "0.1"};
        checkOneLineError(run(other + Args{"-o", dir / "c.pfm", "--resume", ckpt}), "--noise-threshold is 0.1 here but 0.05 in the checkpoint");
    }
}

// A target error for the whole image (--target-error; brume render's default rule) decides from
// the film alone, and so does the guide it lets start (the render's length predicted from the
// film): stopped before the guide starts, in its training, while it measures its noise and
// after, it resumes to the same bytes; the target is a setting.
TEST_CASE("cli checkpoint: a target error with the guide it starts resumes to the same bytes", "[cli][checkpoint][adaptive]") {
    TempDir dir;
    const Args common = {data("bdpt_quad_fogbox.gltf"), "--integrator", "pt", "--res", "40x30", "--target-error", "0.03"};
    const std::string ckpt = dir / "c.ckpt";
    Result r = run(common + Args{"-o", dir / "straight.pfm", "--stats"});
    REQUIRE(r.code == 0);
    INFO(r.out);
    CHECK(r.out.find("target error: estimated relative error") != std::string::npos);
    CHECK(r.out.find("guiding: ") != std::string::npos);  // a guide started (after the shares' 8 passes)
    CHECK(summarySpp(r.out) > 60);
    checkResumes(common, ckpt, dir / "b.pfm", dir / "straight.pfm", {"6", "20", "36", "50"});
    Args other = {data("bdpt_quad_fogbox.gltf"), "--integrator", "pt", "--res", "40x30", "--target-error", "0.05"};
    checkOneLineError(run(other + Args{"-o", dir / "c.pfm", "--resume", ckpt}), "--target-error is 0.05 here but 0.03 in the checkpoint");
}

// auto's pilot ends after its second pass and its duel after its eighteenth (allocation_planner.h;
// in single scattering the fourth and the twentieth): stopped in the pilot, just after the
// pilot's choice, in the duel, and after a pass of the final choice, it resumes to the same bytes.
TEST_CASE("cli checkpoint: auto resumes to the same bytes across its choice", "[cli][checkpoint][auto]") {
    TempDir dir;
    // (72 passes: its image leaves out the pilot's and the duel loser's, renderer.h finalImage.)
    const Args common = {data("bdpt_quad_fogbox.gltf"), "--res", "40x30", "--spp", "72"};
    const std::string ckpt = dir / "c.ckpt";
    Result r = run(common + Args{"-o", dir / "straight.pfm"});
    REQUIRE(r.code == 0);
    CHECK(r.out.find("allocation: ") != std::string::npos);
    checkResumes(common, ckpt, dir / "b.pfm", dir / "straight.pfm", {"1", "2", "3", "10", "18", "19"});
    // In single scattering it also learns light tracing's share in its pilot passes.
    const Args single = common + Args{"--max-depth", "1"};
    r = run(single + Args{"-o", dir / "single.pfm"});
    REQUIRE(r.code == 0);
    {
        INFO("single scattering");
        checkResumes(single, ckpt, dir / "c.pfm", dir / "single.pfm", {"3", "4", "12", "20", "21"});
    }
}

// Beside two area lights in fog auto probes the path tracer (its distances by the light's solid
// angle, allocation_planner.h), chooses it after the duel, and the path tracer learns its
// connection shares in its 8 duel passes, 10–17 (connection_shares.h). Stopped in the
// pilot, inside and after that learning, it resumes to the same bytes. (Before the planner's state kept whether
// it probes, such a checkpoint resumed to another choice and was refused as malformed.)
TEST_CASE("cli checkpoint: auto resumes to the same bytes where it chooses the path tracer", "[cli][checkpoint][auto]") {
    TempDir dir;
    const Args common = {data("area_rectangles_close.gltf"), "--res", "40x30", "--spp", "40"};
    const std::string ckpt = dir / "c.ckpt";
    Result r = run(common + Args{"-o", dir / "straight.pfm", "--stats"});
    REQUIRE(r.code == 0);
    REQUIRE(r.out.find("allocation: path tracer") != std::string::npos);
    CHECK(r.out.find("connection shares: at medium vertices") != std::string::npos);
    checkResumes(common, ckpt, dir / "b.pfm", dir / "straight.pfm", {"1", "15", "19"});
}

// bdpt learns light tracing's share of one-scattering paths in its first four passes
// (direct_light_tracing.h), which the image leaves out once the others are 4× as many:
// stopped inside the learning, after it, and after a pass with the learned factor, it
// resumes to the same bytes.
TEST_CASE("cli checkpoint: bdpt resumes to the same bytes across its learning passes", "[cli][checkpoint]") {
    TempDir dir;
    const Args common = {data("bdpt_quad_fogbox.gltf"), "--integrator", "bdpt", "--res", "40x30", "--spp", "24"};
    const std::string ckpt = dir / "c.ckpt";
    Result r = run(common + Args{"-o", dir / "straight.pfm", "--stats"});
    REQUIRE(r.code == 0);
    CHECK(r.out.find("light tracing's share of one-scattering paths: factor") != std::string::npos);
    for (const char* stop : {"1", "3", "4", "5"}) {
        INFO("stopped after " << stop << " passes");
        REQUIRE(run(common + Args{"-o", dir / "b.pfm", "--checkpoint", ckpt, "--stop-after-passes", stop}).code == 143);
        r = run(common + Args{"-o", dir / "b.pfm", "--resume", ckpt, "--threads", "1"});
        CHECK(r.code == 0);
        CHECK(readFile(dir / "b.pfm") == readFile(dir / "straight.pfm"));
    }
}

// In single scattering beside a point light bdpt renders by the one-event split
// (one_event_split.h): 4 learning passes, then 8 Sobol passes that check light tracing's factor
// (direct_light_tracing.h). Stopped inside either, at their ends and after, it resumes to the
// same bytes.
TEST_CASE("cli checkpoint: bdpt's single-scattering split resumes to the same bytes across its learning and check",
          "[cli][checkpoint]") {
    TempDir dir;
    const Args common = {data("single_near.gltf"), "--integrator", "bdpt", "--max-depth", "1", "--res", "40x30", "--spp", "20"};
    const std::string ckpt = dir / "c.ckpt";
    Result r = run(common + Args{"-o", dir / "straight.pfm", "--stats"});
    REQUIRE(r.code == 0);
    CHECK(r.out.find("checked with Sobol numbers") != std::string::npos);
    for (const char* stop : {"2", "4", "7", "12", "14"}) {
        INFO("stopped after " << stop << " passes");
        REQUIRE(run(common + Args{"-o", dir / "b.pfm", "--checkpoint", ckpt, "--stop-after-passes", stop}).code == 143);
        r = run(common + Args{"-o", dir / "b.pfm", "--resume", ckpt, "--threads", "1"});
        CHECK(r.code == 0);
        CHECK(readFile(dir / "b.pfm") == readFile(dir / "straight.pfm"));
    }
}

TEST_CASE("cli checkpoint: SIGINT and SIGTERM write whole passes and exit with 130 and 143", "[cli][checkpoint]") {
    for (int sig : {SIGINT, SIGTERM}) {
        INFO("signal " << sig);
        TempDir dir;
        const std::string ckpt = dir / "c.ckpt";
        const Args scene = {data("single_near.gltf"), "--res", "32x24", "--seed", "9"};
        Child child(scene +
                    Args{"-o", dir / "i.pfm", "--spp", "1000000", "--checkpoint", ckpt, "--checkpoint-every", "0.001"});
        // Signalled once a periodic checkpoint exists (so at least one pass is done).
        auto start = std::chrono::steady_clock::now();
        while (!fs::exists(ckpt) && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        child.signal(sig);
        Result r = child.wait();
        INFO("stderr: " << r.err);
        REQUIRE(r.code == 128 + sig);
        CHECK(r.err.find(sig == SIGINT ? "SIGINT" : "SIGTERM") != std::string::npos);
        const int spp = summarySpp(r.out);
        CHECK(spp >= 1);
        CHECK(r.err.find("after " + std::to_string(spp) + " of 1000000 passes") != std::string::npos);

        // The image holds exactly `spp` whole passes, and so does the checkpoint: those of the
        // same render (the same planned length: auto plans by it, e.g. its partial pilot
        // passes, docs/mis.md) stopped after `spp` passes.
        REQUIRE(run(scene + Args{"-o", dir / "ref.pfm", "--spp", "1000000", "--stop-after-passes", std::to_string(spp)}).code ==
                128 + SIGTERM);
        CHECK(readFile(dir / "i.pfm") == readFile(dir / "ref.pfm"));
        brume::Checkpoint c = brume::readCheckpoint(ckpt);
        CHECK(c.film.passes() == spp);
        // The checkpoint resumed, and stopped again before any pass: the same image.
        REQUIRE(run(scene + Args{"-o", dir / "resumed.pfm", "--spp", "1000000", "--resume", ckpt, "--stop-after-passes", "0"})
                    .code == 128 + SIGTERM);
        CHECK(readFile(dir / "resumed.pfm") == readFile(dir / "i.pfm"));
        CHECK(dir.files() == Args{"c.ckpt", "i.pfm", "ref.pfm", "resumed.pfm"});  // no temporary files
    }
}

TEST_CASE("cli checkpoint: stopped before the first pass, nothing is written", "[cli][checkpoint]") {
    TempDir dir;
    Result r = run({data("single_near.gltf"), "-o", dir / "i.pfm", "--checkpoint", dir / "c.ckpt",
                    "--stop-after-passes", "0"});
    CHECK(r.code == 143);
    CHECK(r.err.find("nothing written") != std::string::npos);
    CHECK(r.out.empty());
    CHECK(dir.files().empty());
}

TEST_CASE("cli checkpoint: damaged or mismatched checkpoints are one-line errors", "[cli][checkpoint]") {
    TempDir dir;
    const std::string scene = data("single_near.gltf");
    const std::string ckpt = dir / "c.ckpt";
    const Args base = {"--res", "16x12", "--spp", "4", "--seed", "3"};
    REQUIRE(run(Args{scene, "-o", dir / "a.pfm", "--checkpoint", ckpt, "--stop-after-passes", "1"} + base).code == 143);
    const std::string good = readFile(ckpt);
    const std::string bad = dir / "bad.ckpt";
    auto resume = [&](const std::string& file, const Args& extra) {
        return run(Args{scene, "-o", dir / "out.pfm", "--resume", file} + extra);
    };

    writeFile(bad, good.substr(0, good.size() / 2));
    checkOneLineError(resume(bad, base), "truncated");
    std::string flipped = good;
    flipped[flipped.size() - 100] ^= 0x04;
    writeFile(bad, flipped);
    checkOneLineError(resume(bad, base), "checksum");
    writeFile(bad, "");
    checkOneLineError(resume(bad, base), "not a brume checkpoint");
    checkOneLineError(resume(scene, base), "not a brume checkpoint");
    checkOneLineError(resume(dir / "missing.ckpt", base), "missing.ckpt");

    checkOneLineError(resume(ckpt, {"--res", "16x12", "--spp", "8", "--seed", "3"}), "--spp is 8 here but 4");
    checkOneLineError(resume(ckpt, {"--res", "16x12", "--spp", "4", "--seed", "4"}), "--seed");
    checkOneLineError(resume(ckpt, {"--res", "16x10", "--spp", "4", "--seed", "3"}), "--res");
    checkOneLineError(resume(ckpt, base + Args{"--integrator", "pt"}), "--integrator");
    checkOneLineError(resume(ckpt, base + Args{"--connect", "density"}), "--connect");
    checkOneLineError(resume(ckpt, base + Args{"--max-depth", "3"}), "--max-depth");
    checkOneLineError(resume(ckpt, base + Args{"--mis", "balance"}), "--mis");
    checkOneLineError(resume(ckpt, base + Args{"--no-nee"}), "--no-nee");
    checkOneLineError(resume(ckpt, base + Args{"--sampler", "independent"}), "--sampler");
    // Another scene file, and the same scene edited (one more space) at the same place.
    const Args other = Args{data("single_side.gltf"), "-o", dir / "out.pfm", "--resume", ckpt} + base;
    checkOneLineError(run(other), "scene file");
    fs::copy_file(data("single_near.gltf"), dir / "scene.gltf");
    const Args edited = Args{dir / "scene.gltf"} + base;
    REQUIRE(run(edited + Args{"-o", dir / "m.pfm", "--checkpoint", dir / "m.ckpt", "--stop-after-passes", "1"}).code ==
            143);
    writeFile(dir / "scene.gltf", readFile(dir / "scene.gltf") + " ");
    checkOneLineError(run(edited + Args{"-o", dir / "out.pfm", "--resume", dir / "m.ckpt"}), "scene file");
    CHECK_FALSE(fs::exists(dir / "out.pfm"));

    // The same contents elsewhere is the same scene.
    Result r = run(Args{scene, "-o", dir / "out.pfm", "--resume", dir / "m.ckpt"} + base);
    CHECK(r.code == 0);
    CHECK(summarySpp(r.out) == 4);
}

// Every file a scene reads is part of it (scene_identity.h): a density grid replaced after the
// checkpoint (another grid of the same name) is refused, naming the grid's file; put back, the
// render resumes.
TEST_CASE("cli checkpoint: a grid changed after the checkpoint is refused, naming its file", "[cli][checkpoint]") {
    TempDir dir;
    fs::copy_file(data("single_gradient.gltf"), dir / "scene.gltf");
    fs::copy_file(data("gradient.vdb"), dir / "gradient.vdb");
    const Args base = {dir / "scene.gltf", "--res", "16x12", "--spp", "4", "--seed", "3"};
    REQUIRE(run(base + Args{"-o", dir / "a.pfm", "--checkpoint", dir / "c.ckpt", "--stop-after-passes", "1"}).code == 143);
    fs::copy_file(data("ramp.vdb"), dir / "gradient.vdb", fs::copy_options::overwrite_existing);
    checkOneLineError(run(base + Args{"-o", dir / "out.pfm", "--resume", dir / "c.ckpt"}),
                      "cannot resume this render: the FNV-1a hash of gradient.vdb is ");
    CHECK_FALSE(fs::exists(dir / "out.pfm"));
    fs::copy_file(data("gradient.vdb"), dir / "gradient.vdb", fs::copy_options::overwrite_existing);
    Result r = run(base + Args{"-o", dir / "out.pfm", "--resume", dir / "c.ckpt"});
    CHECK(r.code == 0);
    CHECK(summarySpp(r.out) == 4);
}

TEST_CASE("cli checkpoint: option errors", "[cli][checkpoint]") {
    TempDir dir;
    const std::string scene = data("single_near.gltf");
    const std::string out = dir / "o.pfm";
    struct Case {
        Args args;
        int code;
        std::string mention;
    } cases[] = {
        {{scene, "-o", out, "--checkpoint-every", "5"}, 2, "--checkpoint-every needs --checkpoint"},
        {{scene, "-o", out, "--checkpoint", dir / "c", "--checkpoint-every", "0"}, 2, "--checkpoint-every"},
        {{scene, "-o", out, "--checkpoint", dir / "c", "--time", "1"}, 2, "--checkpoint needs --spp"},
        {{scene, "-o", out, "--resume", dir / "c", "--time", "1"}, 2, "--resume needs --spp"},
        {{scene, "-o", out, "--checkpoint", out}, 2, "same file"},
        {{scene, "-o", out, "--checkpoint", ""}, 2, "--checkpoint"},
        {{scene, "-o", out, "--checkpoint", "/nonexistent-dir/c.ckpt"}, 1, "/nonexistent-dir/c.ckpt"},
        {{scene, "-o", out, "--checkpoint", dir.path().string()}, 1, "is a directory"},
    };
    for (const Case& c : cases) {
        std::string line;
        for (const std::string& a : c.args) line += " " + a;
        INFO("brume render" << line);
        Result r = run(c.args);
        INFO("stderr: " << r.err);
        CHECK(r.code == c.code);
        CHECK(r.err.find(c.mention) != std::string::npos);
        CHECK(dir.files().empty());
    }
    Result help = run({"--help"});
    CHECK(help.out.find("--checkpoint-every") != std::string::npos);
    CHECK(help.out.find("143") != std::string::npos);
}
