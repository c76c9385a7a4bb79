// `brume bench` keys its cached reference on the build of brume that rendered it (the FNV-1a
// hash of the executable's bytes): a reference.json naming another build is remade, not
// reused. Tiny renders, about a second in all.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "brume/render/fnv1a.h"
#include "support/run_brume.h"
#include "support/scratch_files.h"

using brume::test::BrumeResult;
using brume::test::quote;
using brume::test::runBrume;
using brume::test::readFile;
using brume::test::TempDir;
using brume::test::writeFile;

namespace {

using Run = BrumeResult;

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

std::string hex64(uint64_t value) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
    return text;
}

}  // namespace

TEST_CASE("bench: a reference made by another build of brume is remade, not reused", "[cli][bench]") {
    TempDir scratch;
    const std::string dir = scratch / "out";
    const std::string command = "bench " + quote(std::string(BRUME_TEST_DATA) + "/single_near.gltf") + " --out " +
                                quote(dir) + " --res 8x8 --budgets 0.01 --reference-spp 2 --methods pt:mis --no-chart";

    Run first = runBrume(command);
    INFO("stdout: " << first.out << "\nstderr: " << first.err);
    REQUIRE(first.code == 0);
    const std::string record = readFile(dir + "/reference.json");
    const std::string thisBuild = hex64(brume::fnv1a64File(BRUME_EXE));
    const std::string key = "\"brume_build_fnv1a64\": \"" + thisBuild + "\"";
    REQUIRE(contains(record, key));

    // The cache is reused while nothing changes (so that what follows means something).
    Run second = runBrume(command);
    REQUIRE(second.code == 0);
    CHECK(contains(second.out, "reference: reused"));

    // The same record as another build would have written it.
    std::string otherBuild = thisBuild;
    otherBuild.back() = otherBuild.back() == '0' ? '1' : '0';
    std::string tampered = record;
    tampered.replace(tampered.find(key), key.size(), "\"brume_build_fnv1a64\": \"" + otherBuild + "\"");
    writeFile(dir + "/reference.json", tampered);

    Run third = runBrume(command);
    INFO("third stdout: " << third.out << "\nthird stderr: " << third.err);
    REQUIRE(third.code == 0);
    CHECK_FALSE(contains(third.out, "reused"));
    CHECK(contains(third.out, "made by another build of brume"));
    CHECK(readFile(dir + "/reference.json") == record);  // remade, keyed by this build
}
