// Transparent emitters (Material::transparent, emitter_crossing.h): light surfaces that every
// ray crosses, as Cycles' lights, seen or not by the camera (Material::cameraVisible).
//   - In vacuum, against a closed form: a panel of radiance 2 facing the camera in front of a
//     diffuse wall lit through it by a point light. An opaque panel would hide the wall (the
//     image would be 2), a panel that shadows would leave it black, a panel that the camera
//     sees when it should not would add 2.
//   - In fog, the bidirectional tracer (where a crossing is the emitter hit s = 0 among all its
//     strategies) against the path tracer, per 2×2 block, z below zBound (a correct pair fails
//     with probability 1e-3; fixed seeds).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/scene/camera_importance.h"
#include "support/film_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

BdptOptions bdptOptions(int maxDepth) {
    BdptOptions o;
    o.maxDepth = maxDepth;
    o.heuristic = MisHeuristic::Power;
    return o;
}

// make_test_scenes.py: transparent_panel.
constexpr double kYfov = 0.6, kPanel = 2.0, kAlbedo = 0.5, kWallZ = -4.0, kIntensity = 3.0;
const Vec3 kLamp(0.0f, 0.0f, -1.0f);

// The wall's radiance along the ray through film position (fx, fy): albedo/π · I cos θ / d².
double wallRadiance(double fx, double fy, int W) {
    const Vec3 d = referenceCameraDirection(fx, fy, W, W, kYfov);
    const double s = kWallZ / double(d.z);
    const double px = s * d.x - kLamp.x, py = s * d.y - kLamp.y, pz = kWallZ - double(kLamp.z);
    const double d2 = px * px + py * py + pz * pz;
    return kAlbedo / M_PI * kIntensity * (-pz / std::sqrt(d2)) / d2;
}

// A pixel's mean over its area (the box filter), by a 16 × 16 midpoint rule.
double pixelReference(int x, int y, int W, bool seen) {
    double sum = 0;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) sum += wallRadiance(x + (i + 0.5) / 16.0, y + (j + 0.5) / 16.0, W);
    return sum / 256.0 + (seen ? kPanel : 0.0);
}

void checkClosedForm(const char* file, bool seen, Integrator&& integrator, const char* name) {
    const int W = 8;
    auto scene = loadTestScene(file);
    const auto px = estimateFilm(*scene, integrator, W, W, 16, 32, 3, 1, SamplerKind::Independent);
    double worst = 0;
    std::string where;
    for (int i = 0; i < W * W; ++i) {
        const double ref = pixelReference(i % W, i / W, W, seen);
        for (int c = 0; c < 3; ++c) {
            // (Floored at 1e-4 of the value, the midpoint rule's own accuracy being ~1e-6: a
            // pixel that sees only the panel has no variance.)
            const double se = std::hypot(px[size_t(i)].stderror(c), 1e-4 * ref);
            const double z = std::abs(px[size_t(i)].mean(c) - ref) / se;
            if (z > worst) {
                worst = z;
                where = "pixel " + std::to_string(i % W) + "," + std::to_string(i / W) + ": " +
                        std::to_string(px[size_t(i)].mean(c)) + " vs " + std::to_string(ref);
            }
        }
    }
    INFO(name << " on " << file << ": worst " << where << " (z = " << worst << ")");
    CHECK(worst < zBound(3 * W * W));
}

// Blocks showing the point light directly are left out (bdpt images it, pt cannot).
void compareInFog(int maxDepth, int sppPt, int sppBdpt, ConnectMode mode) {
    const int W = 16;
    auto scene = loadTestScene("transparent_panels_fog.gltf");
    PathTracer pt(PathTracerOptions{maxDepth, true, mode});
    BdptIntegrator bdpt(bdptOptions(maxDepth));
    const auto a = estimateFilm(*scene, pt, W, W, sppPt, 16, 1, 2);
    const auto b = estimateFilm(*scene, bdpt, W, W, sppBdpt, 16, 2, 2);
    std::vector<bool> skip(a.size(), false);
    for (const Light& l : scene->lights()) {
        CameraConnection cc;
        if (l.kind == LightKind::Point && connectToCamera(scene->camera(), l.position, W, W, &cc))
            skip[size_t(int(cc.fy) / 2) * (W / 2) + size_t(int(cc.fx) / 2)] = true;
    }
    double worst = 0;
    std::string where;
    int compared = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (skip[i]) continue;
        for (int c = 0; c < 3; ++c) {
            ++compared;
            const double se = std::hypot(a[i].stderror(c), b[i].stderror(c));
            const double z = std::abs(a[i].mean(c) - b[i].mean(c)) / se;
            if (z > worst) {
                worst = z;
                where = "block " + std::to_string(i % (W / 2)) + "," + std::to_string(i / (W / 2)) + ": pt " +
                        std::to_string(a[i].mean(c)) + " ± " + std::to_string(a[i].stderror(c)) + ", bdpt " +
                        std::to_string(b[i].mean(c)) + " ± " + std::to_string(b[i].stderror(c));
            }
        }
    }
    INFO("max-depth " << maxDepth << ", pt --connect " << connectModeName(mode) << ": worst " << where << " (z = " << worst << ")");
    CHECK(worst < zBound(compared));
}

}  // namespace

TEST_CASE("a transparent emitter lets the light and the view through and still emits", "[oracle][transparent]") {
    for (bool seen : {true, false}) {
        const char* file = seen ? "transparent_panel.gltf" : "transparent_panel_unseen.gltf";
        checkClosedForm(file, seen, PathTracer(PathTracerOptions{-1, true, ConnectMode::Mis}), "pt");
        checkClosedForm(file, seen, BdptIntegrator(bdptOptions(-1)), "bdpt");
    }
}

TEST_CASE("bdpt matches pt in fog with transparent emitters, seen and unseen by the camera", "[bdpt][transparent]") {
    compareInFog(1, 64, 64, ConnectMode::Mis);
    compareInFog(-1, 64, 32, ConnectMode::Mis);
    compareInFog(-1, 64, 32, ConnectMode::Density);
}
