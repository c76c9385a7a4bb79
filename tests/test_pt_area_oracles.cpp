// Single scattering from area lights (a sphere light and a one-sided quad) at --max-depth 1,
// for each --connect mode, against nested quadrature: an outer integral along the pixel's ray
// and an inner one over the light.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/integrators/path_tracer.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr double kZ = 4.0;  // every pixel and channel within 4 standard errors (see test_pt_oracles)
void requireAll(const std::vector<PixelEstimate>& px, int W, const std::vector<double>& ref, const std::string& what) {
    double worst = 0;
    int worstI = 0;
    for (size_t i = 0; i < px.size(); ++i) {
        double z = std::abs(px[i].mean(0) - ref[i]) / px[i].stderror(0);
        if (z > worst) worst = z, worstI = int(i);
    }
    INFO(what << ": worst pixel " << worstI % W << "," << worstI / W << ": " << px[worstI].mean(0) << " ± "
              << px[worstI].stderror(0) << " vs " << ref[worstI] << " (z = " << worst << ")");
    CHECK(worst < kZ);
    // Guard: the comparison has the power to see a 3% error in the reference.
    double worstScaled = 0;
    for (size_t i = 0; i < px.size(); ++i)
        worstScaled = std::max(worstScaled, std::abs(px[i].mean(0) - 1.03 * ref[i]) / px[i].stderror(0));
    CHECK(worstScaled > kZ);
}

}  // namespace

TEST_CASE("single scattering from a sphere light matches quadrature", "[oracle][pt][area]") {
    const int W = 8, H = 8;
    auto scene = loadTestScene("area_sphere.gltf");
    std::vector<double> ref(W * H);
    for (int i = 0; i < W * H; ++i)
        ref[i] = sphereReference(referenceCameraDirection(i % W, i / W, W, H, kYfov), Vec3(0.8f, 0.5f, -3), 0.3, 10.0);
    for (ConnectMode mode : kConnectModes) {
        const char* name = connectModeName(mode);
        PathTracer pt(PathTracerOptions{1, true, mode});
        requireAll(estimatePixels(*scene, pt, W, H, 8192, 11), W, ref, std::string("sphere ") + name);
    }
}

TEST_CASE("single scattering from a sphere light in back-scattering fog matches quadrature", "[oracle][pt][area]") {
    // g = −0.7: the product sampler's mirrored case, and the sphere's light point sampled
    // after the distance (towards the centre as the anchor).
    const int W = 8, H = 8;
    auto scene = loadTestScene("area_sphere_back.gltf");
    std::vector<double> ref(W * H);
    for (int i = 0; i < W * H; ++i)
        ref[i] = sphereReference(referenceCameraDirection(i % W, i / W, W, H, kYfov), Vec3(0.8f, 0.5f, -3), 0.3, 10.0, -0.7);
    for (ConnectMode mode : kConnectModes) {
        const char* name = connectModeName(mode);
        PathTracer pt(PathTracerOptions{1, true, mode});
        requireAll(estimatePixels(*scene, pt, W, H, 8192, 17), W, ref, std::string("back-scattering sphere ") + name);
    }
}

TEST_CASE("single scattering from a one-sided quad light matches quadrature", "[oracle][pt][area]") {
    const int W = 8, H = 8;
    auto scene = loadTestScene("area_quad.gltf");
    std::vector<double> ref(W * H);
    for (int i = 0; i < W * H; ++i)
        ref[i] = quadReference(referenceCameraDirection(i % W, i / W, W, H, kYfov), Vec3(0, 2, -3), Vec3(0.5f, 0, 0),
                               Vec3(0, 0, 0.5f), Vec3(0, -1, 0), 5.0);
    for (ConnectMode mode : kConnectModes) {
        const char* name = connectModeName(mode);
        PathTracer pt(PathTracerOptions{1, true, mode});
        requireAll(estimatePixels(*scene, pt, W, H, 8192, 13), W, ref, std::string("quad ") + name);
    }
}

TEST_CASE("single scattering from large rectangles close to the view rays matches quadrature", "[oracle][pt][area]") {
    // A ceiling panel 4 cm above the top of the view and a window just beside it: the light
    // points' 1/r² is nearly singular there; every mode, by area and by solid angle.
    const int W = 8, H = 8;
    auto scene = loadTestScene("area_rectangles_close.gltf");
    std::vector<double> ref(W * H);
    for (int i = 0; i < W * H; ++i) ref[i] = rectanglesCloseReference(referenceCameraDirection(i % W, i / W, W, H, kYfov));
    for (EmitterSampling emitters : {EmitterSampling::SolidAngle, EmitterSampling::Area}) {
        scene->setEmitterSampling(emitters);
        for (ConnectMode mode : kConnectModes) {
            const std::string name = std::string("rectangles ") + connectModeName(mode) +
                                     (emitters == EmitterSampling::Area ? ", by area" : ", by solid angle");
            PathTracer pt(PathTracerOptions{1, true, mode});
            // Free flight alone is noisy close to the panel: more samples, for the power to see 3 %.
            const int spp = mode == ConnectMode::Density ? 65536 : 8192;
            requireAll(estimatePixels(*scene, pt, W, H, spp, 19), W, ref, name);
        }
    }
}

// --connect mis with the solid-angle connection D left out (its share 0, connection_shares.h):
// A and the emitter hit B then make D's paths, and the image still matches quadrature, beside
// the quad and beside the close rectangles (where D is most of the estimate), with A's and C's
// shares below one too. A D left out without raising the others' weights loses light there.
TEST_CASE("single scattering from area lights matches quadrature with the solid-angle connection left out",
          "[oracle][pt][area]") {
    const int W = 8, H = 8;
    auto quad = loadTestScene("area_quad.gltf");
    auto close = loadTestScene("area_rectangles_close.gltf");
    std::vector<double> quadRef(W * H), closeRef(W * H);
    for (int i = 0; i < W * H; ++i) {
        const Vec3 dir = referenceCameraDirection(i % W, i / W, W, H, kYfov);
        quadRef[i] = quadReference(dir, Vec3(0, 2, -3), Vec3(0.5f, 0, 0), Vec3(0, 0, 0.5f), Vec3(0, -1, 0), 5.0);
        closeRef[i] = rectanglesCloseReference(dir);
    }
    for (const ConnectionShares::Shares q : {ConnectionShares::Shares{1.0f, 1.0f, 0.0f}, ConnectionShares::Shares{0.5f, 0.25f, 0.0f},
                                             ConnectionShares::Shares{0.0f, 1.0f, 0.0f}}) {
        PathTracerOptions o{1, true, ConnectMode::Mis};
        o.shares = q;
        const std::string name = " shares " + std::to_string(q.vertex) + ", " + std::to_string(q.segment) + ", 0";
        // (With A left out too only B reaches the far quad, at 8 % per pixel in 65536 samples:
        // that case only beside the rectangles.)
        if (q.vertex > 0) requireAll(estimatePixels(*quad, PathTracer(o), W, H, 8192, 23), W, quadRef, "quad" + name);
        requireAll(estimatePixels(*close, PathTracer(o), W, H, 65536, 29), W, closeRef, "rectangles" + name);
    }
}
