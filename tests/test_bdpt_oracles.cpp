// The bidirectional path tracer against the closed-form oracles, in each --connect mode:
// the furnace (every pixel exactly 1) and single scattering against 1D quadrature.
// Estimates come from 32 independent renders (batch means, light-tracing splats included);
// with 31 degrees of freedom |z| < 4.5 is missed by a correct estimate with probability ~1e-4
// per comparison, and the seeds are fixed.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "brume/integrators/bdpt.h"
#include "brume/scene/camera_importance.h"
#include "support/block_z.h"
#include "support/film_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr double kZ = 4.5;
constexpr int kBatches = 32;
BdptIntegrator makeBdpt(int maxDepth, ConnectMode mode, float generalConnection = 1) {
    BdptOptions o{maxDepth, MisHeuristic::Power};
    o.connect = mode;
    o.allocation.generalConnection = generalConnection;
    return BdptIntegrator(o);
}


// Per 2×2 block of a W × W image: the quadrature averaged over a 16×16 grid of film
// positions, with anisotropy g; `skip` marks the block holding an in-view point light. (The
// spot's falloff has a kink at its cone edges: a 6×6 grid was 5% off there, 16×16 is within
// 0.5% of 32×32, a tenth of the estimates' standard error.)
std::vector<Vec3> blockReference(const Scene& scene, const SingleCase& sc, int W, double g, std::vector<bool>* skip) {
    const int B = 2, S = 16;
    const Light spot = singleSpotLight();
    const Vec3 I = sc.spot ? Vec3(30.0f) : Vec3(10.0f);
    skip->assign(size_t(W / B) * (W / B), false);
    CameraConnection cc;
    if (connectToCamera(scene.camera(), sc.light, W, W, &cc)) (*skip)[size_t(int(cc.fy) / B) * (W / B) + int(cc.fx) / B] = true;
    std::vector<Vec3> ref(skip->size());
    for (size_t i = 0; i < ref.size(); ++i) {
        if ((*skip)[i]) continue;
        int bx = int(i) % (W / B), by = int(i) / (W / B);
        Vec3 sum(0.0f);
        for (int j = 0; j < S; ++j)
            for (int k = 0; k < S; ++k) {
                Vec3 d = referenceCameraDirection(bx * B + (k + 0.5) * B / S, by * B + (j + 0.5) * B / S, W, W, kYfov);
                sum += singleScatterReference(d, sc.light, I, sc.sigmaS, sc.sigmaA, g, sc.spot ? &spot : nullptr, 2000);
            }
        ref[i] = sum / float(S * S);
    }
    return ref;
}

}  // namespace

TEST_CASE("bdpt furnace in every connect mode: every pixel is 1", "[bdpt][oracle][sanitizer-skip]") {
    for (const char* file : {"furnace_ambient.gltf", "furnace_bounded.gltf", "furnace_albedo.gltf"}) {
        auto scene = loadTestScene(file);
        for (ConnectMode mode : kConnectModes) {
            BdptIntegrator bdpt = makeBdpt(-1, mode);
            auto px = estimateFilm(*scene, bdpt, 8, 8, 8, kBatches, 7, 2);
            std::string where;
            double z = worstZ(px, 4, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, &where);
            INFO(file << " --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
            CHECK(z < kZ);
        }
    }
}

// General connections made with probability 1/4 each (BdptOptions::generalConnection).
TEST_CASE("bdpt furnace with probabilistic general connections: every pixel is 1", "[bdpt][oracle]") {
    for (const char* file : {"furnace_ambient.gltf", "furnace_albedo.gltf"}) {
        auto scene = loadTestScene(file);
        for (ConnectMode mode : {ConnectMode::Density, ConnectMode::Mis}) {
            BdptIntegrator bdpt = makeBdpt(-1, mode, 0.25f);
            auto px = estimateFilm(*scene, bdpt, 8, 8, 8, kBatches, 8, 2);
            std::string where;
            double z = worstZ(px, 4, std::vector<bool>(px.size(), false), [](int, int) { return Vec3(1.0f); }, &where);
            INFO(file << " --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
            CHECK(z < kZ);
        }
    }
}

namespace {

const Vec3 kGrey02(0.2f), kGrey005(0.05f);
const SingleCase kSingleCases[] = {
    {"single_near.gltf", Vec3(0.3f, 0.2f, -3), kGrey02, kGrey005, 0.3, false},
    {"single_behind.gltf", Vec3(0.5f, 0, 2), kGrey02, kGrey005, 0.3, false},
    {"single_chromatic.gltf", Vec3(0.3f, 0.2f, -3), Vec3(0.3f, 0.2f, 0.1f), Vec3(0.02f, 0.05f, 0.1f), -0.4, false},
    // Strongly coloured: extinction 0.12 to 1.3 /m (ratio 11).
    {"single_chromatic_strong.gltf", Vec3(0.3f, 0.2f, -3), Vec3(0.1f, 0.4f, 1.2f), Vec3(0.02f, 0.05f, 0.1f), 0.3, false},
    {"single_spot.gltf", Vec3(0, 1.5f, -3), kGrey02, kGrey005, 0.3, true},
    // Forward-scattering fog, light in view (product sampling's case).
    {"single_forward.gltf", Vec3(0.3f, 0.2f, -3), kGrey02, kGrey005, 0.9, false},
};

bool grey(const SingleCase& sc) { return sc.sigmaS.x == sc.sigmaS.z && sc.sigmaA.x == sc.sigmaA.z; }

// A pixel's value is the average over its area (box filter), so the reference averages the
// quadrature over each 2×2 block of a 10×10 image (smooth there; the block holding an in-view
// point light, where radiance has a 1/angle peak, is skipped).
struct Quadrature {
    static constexpr int W = 10, B = 2;
    std::vector<bool> skip;
    std::vector<Vec3> ref;
    Quadrature(const Scene& scene, const SingleCase& sc) : ref(blockReference(scene, sc, W, sc.g, &skip)) {}
    // The worst block's z of bdpt's estimate.
    double worstZ(const Scene& scene, BdptIntegrator& bdpt, uint64_t seed, std::string* where) const {
        auto px = estimateFilm(scene, bdpt, W, W, 32, kBatches, seed, B);
        return brume::test::worstZ(px, W / B, skip, [&](int x, int y) { return ref[size_t(y) * (W / B) + x]; }, where);
    }
};

}  // namespace

TEST_CASE("bdpt single scattering matches 1D quadrature in every connect mode", "[bdpt][oracle][sanitizer-skip]") {
    for (const SingleCase& sc : kSingleCases) {
        auto scene = loadTestScene(sc.file);
        const Quadrature quadrature(*scene, sc);
        for (ConnectMode mode : kConnectModes) {
            BdptIntegrator bdpt = makeBdpt(1, mode);
            std::string where;
            const double z = quadrature.worstZ(*scene, bdpt, 11, &where);
            INFO(sc.file << " --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
            CHECK(z < kZ);
        }
    }
}

// The one-event split (one_event_split.h) in grey fog beside point and spot lights, with light
// tracing's factor κ set rather than learned: 1 (the plain power heuristic between the two
// families) and 4 (light tracing favoured), where the learned factor leaves it too small a share
// for a wrong light tracing to show (light splats 1.25x too large pass there, and fail here).
// (Not light tracing alone: towards a pinhole its variance diverges, as 1/D for rays passing
// the camera at distance D, and batch means do not settle.)
TEST_CASE("bdpt single scattering by the one-event split matches quadrature with light tracing's share set",
          "[bdpt][oracle][sanitizer-skip]") {
    for (const SingleCase& sc : kSingleCases) {
        if (!grey(sc)) continue;
        auto scene = loadTestScene(sc.file);
        const Quadrature quadrature(*scene, sc);
        for (ConnectMode mode : kConnectModes)
            for (double kappa : {1.0, 4.0}) {
                BdptOptions o{1, MisHeuristic::Power};
                o.connect = mode;
                o.directLightTracing = kappa;
                BdptIntegrator bdpt(o);
                std::string where;
                const double z = quadrature.worstZ(*scene, bdpt, 13, &where);
                REQUIRE(bdpt.splitsOneEvent());
                INFO(sc.file << " --connect " << connectModeName(mode) << ", kappa " << kappa << ": worst " << where
                             << " (z = " << z << ")");
                CHECK(z < kZ);
            }
    }
}

TEST_CASE("bdpt single scattering from large rectangles close to the view rays matches quadrature",
          "[bdpt][oracle][area]") {
    // tests/data/area_rectangles_close.gltf: a panel 4 cm above the top of the view and a window
    // beside the camera. Reference per 2×2 block: the quadrature on a 6×6 grid of film positions.
    const int W = 10, B = 2, S = 6;
    auto scene = loadTestScene("area_rectangles_close.gltf");
    std::vector<Vec3> ref(size_t(W / B) * (W / B));
    for (size_t i = 0; i < ref.size(); ++i) {
        const int bx = int(i) % (W / B), by = int(i) / (W / B);
        double sum = 0;
        for (int j = 0; j < S; ++j)
            for (int k = 0; k < S; ++k)
                sum += rectanglesCloseReference(
                    referenceCameraDirection(bx * B + (k + 0.5) * B / S, by * B + (j + 0.5) * B / S, W, W, kYfov), 1000, 10);
        ref[i] = Vec3(float(sum / (S * S)));
    }
    const std::vector<bool> skip(ref.size(), false);
    for (ConnectMode mode : kConnectModes) {
        BdptIntegrator bdpt = makeBdpt(1, mode);
        auto px = estimateFilm(*scene, bdpt, W, W, 32, kBatches, 23, B);
        std::string where;
        double z = worstZ(px, W / B, skip, [&](int x, int y) { return ref[size_t(y) * (W / B) + x]; }, &where);
        INFO("rectangles --connect " << connectModeName(mode) << ": worst " << where << " (z = " << z << ")");
        CHECK(z < kZ);
    }
}

TEST_CASE("the bdpt single-scattering oracle can fail: a wrong phase sign is detected", "[bdpt][oracle]") {
    const SingleCase sc{"single_near.gltf", Vec3(0.3f, 0.2f, -3), Vec3(0.2f), Vec3(0.05f), 0.3, false};
    auto scene = loadTestScene(sc.file);
    std::vector<bool> skip;
    std::vector<Vec3> wrong = blockReference(*scene, sc, 10, -sc.g, &skip);
    BdptIntegrator bdpt = makeBdpt(1, ConnectMode::Mis);
    auto px = estimateFilm(*scene, bdpt, 10, 10, 32, kBatches, 11, 2);
    std::string where;
    double z = worstZ(px, 5, skip, [&](int x, int y) { return wrong[size_t(y) * 5 + x]; }, &where);
    INFO("against g = -0.3: worst " << where << " (z = " << z << ")");
    CHECK(z > kZ);
}
