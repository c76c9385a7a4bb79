// Image files through OpenImageIO: the PNG bytes are the sRGB encoding (not a plain gamma,
// not linear), every format gives the same bytes for the same pixels, and PFM files from
// elsewhere (big-endian, one channel) are read, a truncated one refused.
#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "brume/film/image_io.h"
#include "support/scratch_files.h"

using brume::test::readFile;
using brume::test::TempDir;
using brume::test::writeFile;

namespace {

// IEC 61966-2-1 (sRGB), from its definition.
double srgbEncoded(double linear) {
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}

// The file's 8-bit values as stored, no colour conversion.
std::vector<unsigned char> storedBytes(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    REQUIRE(in);
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<unsigned char> bytes(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    REQUIRE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, bytes.data()));
    return bytes;
}

void putBigEndian(float f, std::string& out) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    for (int shift = 24; shift >= 0; shift -= 8) out += char((bits >> shift) & 0xff);
}

}  // namespace

TEST_CASE("image files: PNG stores the sRGB encoding of the linear values, clamped", "[io]") {
    TempDir dir;
    // 0.001 and 0.002 lie on the sRGB curve's linear segment (bytes 3 and 7; a 2.2 gamma gives
    // 11 and 15), 0.5 on its power segment (188; a 2.2 gamma gives 186).
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> linear = {0.0f, 0.001f, 0.002f, 0.05f, 0.2f, 0.5f, 0.9f, 1.0f, 2.0f, -1.0f, nan, 0.75f};
    brume::writeImage(dir / "ramp.png", 4, 1, linear);
    std::vector<unsigned char> stored = storedBytes(dir / "ramp.png");
    REQUIRE(stored.size() == linear.size());
    for (size_t i = 0; i < linear.size(); ++i) {
        double clamped = std::isnan(linear[i]) ? 0.0 : std::min(1.0, std::max(0.0, double(linear[i])));
        long expected = std::lround(255 * srgbEncoded(clamped));
        INFO("linear " << linear[i] << ": byte " << int(stored[i]) << ", sRGB " << expected);
        CHECK(std::abs(long(stored[i]) - expected) <= 1);  // OpenImageIO's curve is exact to ~1e-5
    }
    CHECK(int(stored[1]) == 3);
    CHECK(int(stored[5]) == 188);

    // Read back: decoded to linear, within the 8-bit quantisation.
    int w = 0, h = 0;
    std::vector<float> back = brume::readImage(dir / "ramp.png", &w, &h);
    CHECK(w == 4);
    CHECK(h == 1);
    CHECK(back[5] == Approx(0.5).margin(0.003));
    CHECK(back[1] == Approx(0.001).margin(0.0002));
}

TEST_CASE("image files: the same pixels give the same bytes a second later, in every format", "[io]") {
    TempDir dir;
    const int w = 5, h = 3;
    std::vector<float> rgb(3 * w * h);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.07f * float(i);
    for (const char* name : {"a.exr", "a.pfm", "a.png"}) brume::writeImage(dir / name, w, h, rgb);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // header dates have 1 s steps
    for (const char* name : {"b.exr", "b.pfm", "b.png"}) brume::writeImage(dir / name, w, h, rgb);
    for (const char* ext : {".exr", ".pfm", ".png"}) {
        INFO(ext);
        std::string a = readFile(dir / (std::string("a") + ext)), b = readFile(dir / (std::string("b") + ext));
        CHECK(!a.empty());
        CHECK(a == b);
    }
}

TEST_CASE("image files: PFM from elsewhere is read, a truncated one refused", "[io]") {
    TempDir dir;
    // One channel, big-endian (positive scale), bottom row first: rows 10 20 30 / 40 50 60.
    std::string gray = "Pf\n3 2\n1.0\n";
    for (float v : {40.0f, 50.0f, 60.0f, 10.0f, 20.0f, 30.0f}) putBigEndian(v, gray);
    writeFile(dir / "gray.pfm", gray);
    int w = 0, h = 0;
    std::vector<float> rgb = brume::readImage(dir / "gray.pfm", &w, &h);
    CHECK(w == 3);
    CHECK(h == 2);
    CHECK(rgb == std::vector<float>{10, 10, 10, 20, 20, 20, 30, 30, 30, 40, 40, 40, 50, 50, 50, 60, 60, 60});

    writeFile(dir / "short.pfm", gray.substr(0, gray.size() - 1));
    CHECK_THROWS_WITH(brume::readImage(dir / "short.pfm", &w, &h),
                      Catch::Contains("short.pfm: ") && Catch::Contains("truncated"));
    // A header promising 2^40 floats is refused before they are allocated.
    writeFile(dir / "huge.pfm", "PF\n1048576 349525\n-1.0\n0000");
    CHECK_THROWS_WITH(brume::readImage(dir / "huge.pfm", &w, &h), Catch::Contains("huge.pfm: PFM file is truncated"));
}
