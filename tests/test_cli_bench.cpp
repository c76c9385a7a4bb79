// `brume bench`, run as a user would: the results table, the method images, the cached
// reference being reused on a second run, and usage errors.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
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

namespace {

using Run = BrumeResult;

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::string part;
    std::istringstream in(text);
    while (std::getline(in, part, separator)) parts.push_back(part);
    return parts;
}

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

const std::string kScene = std::string(BRUME_TEST_DATA) + "/single_near.gltf";
const char* const kQuick = " --res 24x24 --budgets 0.2 --reference-spp 16 --methods pt:density,pt:mis";

}  // namespace

TEST_CASE("bench: results table, method images, reference cache", "[cli][bench]") {
    TempDir scratch;
    const std::string dir = (scratch / "results/nested");  // created by brume
    const std::string command = "bench " + quote(kScene) + " --out " + quote(dir) + kQuick;

    Run first = runBrume(command);
    INFO("stdout: " << first.out << "\nstderr: " << first.err);
    REQUIRE(first.code == 0);
    CHECK(contains(first.out, "rel_mse"));
    CHECK(contains(first.out, "(r^2 + 0.01)"));
    CHECK_FALSE(contains(first.out, "reused"));
    CHECK(fs::exists(dir + "/reference.exr"));
    CHECK(fs::exists(dir + "/reference.json"));

    std::vector<std::string> lines = split(readFile(dir + "/results.csv"), '\n');
    REQUIRE(lines.size() == 3);
    CHECK(lines[0] == "scene,method,budget_s,seconds,spp,rel_mse,rmse,efficiency");
    const char* methods[] = {"pt:density", "pt:mis"};
    for (int row = 0; row < 2; ++row) {
        INFO("row: " << lines[row + 1]);
        std::vector<std::string> fields = split(lines[row + 1], ',');
        REQUIRE(fields.size() == 8);
        CHECK(fields[0] == "single_near");
        CHECK(fields[1] == methods[row]);
        for (int column = 2; column < 8; ++column) {
            char* end = nullptr;
            double value = std::strtod(fields[column].c_str(), &end);
            CHECK(*end == '\0');
            CHECK(std::isfinite(value));
            CHECK(value > 0);
        }
        CHECK(std::strtod(fields[2].c_str(), nullptr) == 0.2);
        CHECK(std::strtod(fields[3].c_str(), nullptr) >= 0.2);  // whole passes until the budget is spent
        // The printed table has the same rows.
        CHECK(contains(first.out, methods[row]));
    }
    // The chart and the report page (.ci/setup installs Debian's python3-matplotlib).
    for (const char* file : {"/chart.png", "/chart.svg", "/report.html"}) CHECK(fs::exists(dir + file));
    for (const char* image : {"/pt_density.exr", "/pt_mis.exr"}) {
        int w = 0, h = 0;
        std::vector<float> rgb = brume::readImage(dir + image, &w, &h);
        CHECK(w == 24);
        CHECK(h == 24);
    }

    Run second = runBrume(command);
    INFO("second stdout: " << second.out << "\nsecond stderr: " << second.err);
    CHECK(second.code == 0);
    CHECK(contains(second.out, "reused"));

    // A different reference spp does not match the cache.
    Run third = runBrume("bench " + quote(kScene) + " --out " + quote(dir) +
                      " --res 24x24 --budgets 0.05 --reference-spp 8 --methods pt:mis --no-chart");
    CHECK(third.code == 0);
    CHECK_FALSE(contains(third.out, "reused"));
    CHECK_FALSE(contains(third.out, "chart"));

    // Nor does another reference method; the record names it.
    Run fourth = runBrume("bench " + quote(kScene) + " --out " + quote(dir) +
                          " --res 24x24 --budgets 0.05 --reference-spp 8 --methods pt:mis --no-chart"
                          " --reference-method bdpt:density");
    CHECK(fourth.code == 0);
    CHECK_FALSE(contains(fourth.out, "reused"));
    CHECK(contains(readFile(dir + "/reference.json"), "\"bdpt:density\""));
}

TEST_CASE("bench: usage errors exit with 2", "[cli][bench]") {
    TempDir scratch;
    const std::string dir = (scratch / "out");
    Run run = runBrume("bench " + quote(kScene) + " --out " + quote(dir) + " --methods pt:density,pt:nope");
    CHECK(run.code == 2);
    CHECK(run.err.rfind("brume: error: ", 0) == 0);
    CHECK(contains(run.err, "pt:nope"));
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(dir));

    // Guiding for pt and bdpt methods only.
    Run guided = runBrume("bench " + quote(kScene) + " --out " + quote(dir) + " --methods auto:guided");
    CHECK(guided.code == 2);
    CHECK(contains(guided.err, "auto:guided"));
    CHECK_FALSE(fs::exists(dir));

    CHECK(runBrume("bench " + quote(kScene)).code == 2);  // no --out
    CHECK(runBrume("bench " + quote(kScene) + " --out " + quote(dir) + " --budgets 1,-2").code == 2);
    CHECK(runBrume("bench --help").code == 0);
}

TEST_CASE("bench: a guided method renders with its training passes", "[cli][bench]") {
    TempDir scratch;
    const std::string dir = (scratch / "guided");
    Run run = runBrume("bench " + quote(kScene) + " --out " + quote(dir) +
                       " --res 24x24 --budgets 0.2 --reference-spp 16 --methods pt:mis,pt:mis:guided,bdpt:mis:guided --no-chart");
    INFO("stdout: " << run.out << "\nstderr: " << run.err);
    REQUIRE(run.code == 0);
    const std::string csv = readFile(dir + "/results.csv");
    CHECK(contains(csv, "single_near,pt:mis:guided,"));
    CHECK(contains(csv, "single_near,bdpt:mis:guided,"));
    CHECK(fs::exists(dir + "/pt_mis_guided.exr"));
}

// --noise-threshold: each method once more with adaptive stopping, a row each in the table
// and in threshold.csv (the time limit, 10x the largest budget, ends these at 2 s at most).
TEST_CASE("bench: time to a noise threshold, beside the equal-time rows", "[cli][bench][adaptive]") {
    TempDir scratch;
    const std::string dir = (scratch / "threshold");
    Run run = runBrume("bench " + quote(kScene) + " --out " + quote(dir) +
                       " --res 24x24 --budgets 0.2 --reference-spp 16 --methods pt:mis,bdpt:density --noise-threshold 0.2 --no-chart");
    INFO("stdout: " << run.out << "\nstderr: " << run.err);
    REQUIRE(run.code == 0);
    CHECK(contains(run.out, "time to noise threshold 0.2"));
    const std::string csv = readFile(dir + "/threshold.csv");
    CHECK(contains(csv, "scene,method,threshold,seconds,mean_spp,converged,estimated_rel_mse,rel_mse,efficiency,vs_uniform\n"));
    CHECK(contains(csv, "single_near,pt:mis,0.2,"));
    CHECK(contains(csv, "single_near,bdpt:density,0.2,"));
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 3);
}
