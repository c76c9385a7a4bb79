// Checkpoint files: exact round trips (sample and splat sums, passes, settings, non-finite
// count), atomic writes, and every truncation and every flipped byte of a file rejected
// with an error, never accepted or crashed on. Settings comparison.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "brume/render/checkpoint.h"
#include "brume/render/fnv1a.h"

#include "support/scratch_files.h"

using namespace brume;
namespace fs = std::filesystem;

using brume::test::quote;
using brume::test::readFile;
using brume::test::TempDir;
using brume::test::writeFile;

namespace {

const CheckpointSettings kSettings = {{"--spp", "8"}, {"--seed", "3"}};

// Values whose bits a decimal or float round trip would change.
Film sampleFilm(bool splats) {
    Film film(3, 2);
    film.add(0, 0, Spectrum(0.1f, 1e-30f, 3.0e30f));
    film.add(2, 1, Spectrum(-0.0f, 1.0f / 3.0f, 7.0f));
    film.completePass();
    film.add(0, 0, Spectrum(0.2f, 0.3f, 0.7f));
    film.completePass();
    if (splats) film.splat(1, 1, Spectrum(0.123456789f, 2.0f, 1e-7f));
    return film;
}

}  // namespace

TEST_CASE("checkpoint: round trip keeps every bit", "[checkpoint]") {
    TempDir dir;
    for (bool splats : {false, true}) {
        INFO("splats " << splats);
        Film film = sampleFilm(splats);
        writeCheckpoint(dir / "a.ckpt", "/scenes/x.gltf", kSettings, film, 42);
        CHECK(dir.count() == 1);  // no temporary file left
        Checkpoint c = readCheckpoint(dir / "a.ckpt");
        CHECK(c.scenePath == "/scenes/x.gltf");
        CHECK(c.settings == kSettings);
        CHECK(c.nonFinite == 42);
        CHECK(c.film.width() == 3);
        CHECK(c.film.height() == 2);
        CHECK(c.film.passes() == 2);
        CHECK(c.film.hasSplats() == splats);
        CHECK(c.film.sums() == film.sums());
        CHECK(c.film.rgb() == film.rgb());
    }
}

TEST_CASE("checkpoint: a new checkpoint replaces the old one whole", "[checkpoint]") {
    TempDir dir;
    writeCheckpoint(dir / "a.ckpt", "s", kSettings, sampleFilm(false), 1);
    Film bigger(5, 4);
    bigger.completePass();
    writeCheckpoint(dir / "a.ckpt", "s", kSettings, bigger, 2);
    CHECK(dir.count() == 1);
    Checkpoint c = readCheckpoint(dir / "a.ckpt");
    CHECK(c.film.width() == 5);
    CHECK(c.nonFinite == 2);

    CHECK_THROWS_WITH(writeCheckpoint(dir / "nodir/a.ckpt", "s", kSettings, bigger, 0),
                      Catch::Contains("nodir/a.ckpt") && Catch::Contains("cannot write checkpoint"));
    fs::create_directory(dir / "d.ckpt");
    CHECK_THROWS_AS(writeCheckpoint(dir / "d.ckpt", "s", kSettings, bigger, 0), std::runtime_error);
    CHECK_THROWS_WITH(checkCheckpointWritable(dir / "d.ckpt"), Catch::Contains("is a directory"));
    CHECK_THROWS_AS(checkCheckpointWritable(dir / "nodir/x.ckpt"), std::runtime_error);
    checkCheckpointWritable(dir / "x.ckpt");
    CHECK(dir.count() == 2);  // a.ckpt and d.ckpt only
}

TEST_CASE("checkpoint: the integrator's state comes back byte for byte", "[checkpoint]") {
    TempDir dir;
    const char raw[] = "state\0with a zero and \xff";
    const std::string state(raw, sizeof raw - 1);
    writeCheckpoint(dir / "s.ckpt", "/s.gltf", kSettings, sampleFilm(true), 5, state);
    CHECK(readCheckpoint(dir / "s.ckpt").integratorState == state);
    writeCheckpoint(dir / "e.ckpt", "/s.gltf", kSettings, sampleFilm(false), 5);
    CHECK(readCheckpoint(dir / "e.ckpt").integratorState.empty());
}

TEST_CASE("checkpoint: every truncation and every flipped byte is an error", "[checkpoint]") {
    TempDir dir;
    writeCheckpoint(dir / "good.ckpt", "/s.gltf", kSettings, sampleFilm(true), 5, "some state");
    const std::string good = readFile(dir / "good.ckpt");
    REQUIRE(good.size() > 100);
    const std::string bad = dir / "bad.ckpt";
    for (size_t n = 0; n < good.size(); ++n) {
        writeFile(bad, good.substr(0, n));
        INFO("first " << n << " bytes");
        REQUIRE_THROWS_AS(readCheckpoint(bad), std::runtime_error);
    }
    for (size_t i = 0; i < good.size(); ++i)
        for (unsigned char mask : {0x01, 0x80}) {
            std::string flipped = good;
            flipped[i] = char(flipped[i] ^ mask);
            writeFile(bad, flipped);
            INFO("byte " << i << " ^ " << int(mask));
            REQUIRE_THROWS_AS(readCheckpoint(bad), std::runtime_error);
        }
    writeFile(bad, good + "x");
    CHECK_THROWS_WITH(readCheckpoint(bad), Catch::Contains("trailing bytes"));
    writeFile(bad, good.substr(0, good.size() - 1));
    CHECK_THROWS_WITH(readCheckpoint(bad), Catch::Contains("truncated"));
    std::string sums = good;
    sums[sums.size() - 20] ^= 0x10;  // inside the sums
    writeFile(bad, sums);
    CHECK_THROWS_WITH(readCheckpoint(bad), Catch::Contains("checksum"));
    writeFile(bad, "P6\n3 2\n255\n............................");
    CHECK_THROWS_WITH(readCheckpoint(bad), Catch::StartsWith(bad) && Catch::Contains("not a brume checkpoint"));
    std::string version = good;
    version[8] = 2;  // a checkpoint from before the sums were exact
    writeFile(bad, version);
    CHECK_THROWS_WITH(readCheckpoint(bad), Catch::Contains("checkpoint version 2, this brume reads versions 3 and 4"));
    CHECK_THROWS_WITH(readCheckpoint(dir / "missing.ckpt"), Catch::Contains("missing.ckpt"));
    CHECK_THROWS_WITH(readCheckpoint(dir.path().string()), Catch::Contains("directory"));
}

TEST_CASE("checkpoint: a damaged size field cannot ask for a huge film", "[checkpoint]") {
    TempDir dir;
    Film film(2, 2);
    writeCheckpoint(dir / "a.ckpt", "", {}, film, 0);
    std::string bytes = readFile(dir / "a.ckpt");
    // Header: magic 8, version 4, empty path 4, no settings 4, then width at offset 20.
    for (int i = 0; i < 4; ++i) bytes[20 + size_t(i)] = char(i == 3 ? 0x7f : 0xff);
    writeFile(dir / "a.ckpt", bytes);
    CHECK_THROWS_WITH(readCheckpoint(dir / "a.ckpt"), Catch::Contains("truncated"));
}

TEST_CASE("checkpoint: settings must match to resume", "[checkpoint]") {
    CHECK(checkpointMismatch(kSettings, kSettings).empty());
    CHECK(checkpointMismatch(kSettings, {{"--seed", "3"}, {"--spp", "8"}}).empty());  // order is free
    CHECK(checkpointMismatch(kSettings, {{"--spp", "16"}, {"--seed", "3"}}) ==
          "--spp is 16 here but 8 in the checkpoint");
    CHECK(checkpointMismatch(kSettings, {{"--spp", "8"}, {"--seed", "3"}, {"--mis", "power"}}) ==
          "--mis is not recorded in the checkpoint");
    CHECK(checkpointMismatch(kSettings, {{"--spp", "8"}}) == "the checkpoint has --seed 3, unknown here");
}

TEST_CASE("checkpoint: FNV-1a of files", "[checkpoint]") {
    TempDir dir;
    writeFile(dir / "a", "a");
    writeFile(dir / "empty", "");
    CHECK(fnv1a64File(dir / "empty") == 0xcbf29ce484222325ull);  // the offset basis
    CHECK(fnv1a64File(dir / "a") == 0xaf63dc4c8601ec8cull);      // published test vector
    CHECK_THROWS_WITH(fnv1a64File(dir / "missing"), Catch::Contains("missing"));
}
