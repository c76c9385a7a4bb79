// The film positions drawn by inverse distance where a point light in fog is imaged
// (scene/light_pixels.h, sampling/inverse_distance.h, the renderer): which pixels take them,
// that the pixel values stay the pixel integrals (against 2D × 1D quadrature, which the
// other single-scattering oracles leave out for the light's pixel), and what they save.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "brume/film/film.h"
#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/render/renderer.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_pixels.h"
#include "brume/sampling/inverse_distance.h"
#include "support/pixel_estimates.h"
#include "support/single_scatter_reference.h"

using namespace brume;
using namespace brume::test;

namespace {

const Vec3 kLight(0.3f, 0.2f, -3);  // single_near.gltf's light: 10 W in fog σs 0.2, σa 0.05, g 0.3
constexpr int W = 10;

double radianceAt(double fx, double fy) {
    return singleScatterReference(referenceCameraDirection(fx, fy, W, W, kYfov), kLight, Vec3(10.0f), Vec3(0.2f),
                                  Vec3(0.05f), 0.3, nullptr, 2000)
        .x;
}

// ∫ over the rectangle with corners (cx, cy) and (x, y) of radianceAt, signed by orientation:
// with x = cx + a·s², y = cy + b·t² the 1/|x − c| peak at the corner becomes bounded
// (dA = 4ab·s·t ds dt), then Gauss–Legendre in s and t.
double cornerIntegral(double cx, double cy, double x, double y) {
    const double a = x - cx, b = y - cy;
    if (a == 0 || b == 0) return 0.0;
    static std::vector<double> nodes, weights;
    if (nodes.empty()) gaussLegendre(20, nodes, weights);
    double sum = 0;
    for (size_t i = 0; i < nodes.size(); ++i)
        for (size_t j = 0; j < nodes.size(); ++j) {
            const double s = 0.5 * (nodes[i] + 1), t = 0.5 * (nodes[j] + 1);
            sum += 0.25 * weights[i] * weights[j] * 4.0 * s * t * radianceAt(cx + a * s * s, cy + b * t * t);
        }
    return sum * a * b;  // (the sign of a·b orients it)
}

// The mean of pixel (px, py) over its area: inclusion and exclusion of the four rectangles
// from the light's image c to the pixel's corners.
double pixelIntegral(int px, int py, double cx, double cy) {
    const double x0 = px, y0 = py, x1 = px + 1, y1 = py + 1;
    return cornerIntegral(cx, cy, x1, y1) - cornerIntegral(cx, cy, x0, y1) - cornerIntegral(cx, cy, x1, y0) +
           cornerIntegral(cx, cy, x0, y0);
}

std::vector<PixelEstimate> renders(const Scene& scene, Integrator& integrator, int spp, int batches, bool lightPixels) {
    std::vector<PixelEstimate> px(size_t(W) * W);
    for (int b = 0; b < batches; ++b) {
        Film film(W, W);
        RenderOptions o;
        o.width = o.height = W;
        o.spp = spp;
        o.seed = 4100 + uint64_t(b);
        o.threads = 2;
        o.lightPixels = lightPixels;
        render(scene, integrator, o, film);
        for (size_t i = 0; i < px.size(); ++i) {
            const Spectrum v = film.pixel(int(i) % W, int(i) / W);
            for (int c = 0; c < 3; ++c) {
                px[i].sum[c] += v[c];
                px[i].sum2[c] += double(v[c]) * v[c];
            }
            ++px[i].n;
        }
    }
    return px;
}

}  // namespace

TEST_CASE("light pixels: the light's pixel and its neighbours, for lights in fog in view", "[light-pixels]") {
    auto near = loadTestScene("single_near.gltf");
    CameraConnection cc;
    REQUIRE(connectToCamera(near->camera(), kLight, W, W, &cc));
    const int lx = int(cc.fx), ly = int(cc.fy);
    const LightPixels lp(*near, W, W);
    int found = 0;
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) {
            const LightPixel* p = lp.find(uint32_t(y * W + x));
            const bool expected = std::abs(x - lx) <= 1 && std::abs(y - ly) <= 1;
            INFO("pixel (" << x << ", " << y << ")");
            CHECK((p != nullptr) == expected);
            if (!p) continue;
            ++found;
            // The image in the pixel's own coordinates.
            CHECK(p->cx == Approx(cc.fx - float(x)).margin(1e-5));
            CHECK(p->cy == Approx(cc.fy - float(y)).margin(1e-5));
        }
    CHECK(found == 9);
    // Behind the camera, or outside the view: none.
    CHECK(LightPixels(*loadTestScene("single_behind.gltf"), W, W).empty());
    CHECK(LightPixels(*loadTestScene("single_side.gltf"), W, W).empty());
    // No film, none.
    CHECK(LightPixels(*near, 0, 0).empty());
}

// The light's pixel and its eight neighbours, pt (equi-angular and mis) and bdpt, 24 renders
// of 64 spp each: every pixel within the Bonferroni z bound of its pixel integral. With
// uniform film positions the light's pixel has infinite variance; by inverse distance its
// spread over the renders is a fraction of the uniform one's.
TEST_CASE("light pixels: pixel values are the pixel integrals, with a fraction of the spread", "[light-pixels][oracle][sanitizer-skip]") {
    auto scene = loadTestScene("single_near.gltf");
    CameraConnection cc;
    REQUIRE(connectToCamera(scene->camera(), kLight, W, W, &cc));
    const int lx = int(cc.fx), ly = int(cc.fy);
    std::vector<double> ref(9);
    for (int k = 0; k < 9; ++k) ref[size_t(k)] = pixelIntegral(lx - 1 + k % 3, ly - 1 + k / 3, cc.fx, cc.fy);
    // The quadrature itself: the light's pixel is far above its centre ray, as 1/D makes it.
    CHECK(ref[4] > 1.1 * radianceAt(lx + 0.5, ly + 0.5));

    PathTracer pt(PathTracerOptions{1, true, ConnectMode::Mis});
    PathTracer ea(PathTracerOptions{1, true, ConnectMode::EquiAngular});
    BdptIntegrator bdpt(BdptOptions{1, MisHeuristic::Power});
    struct Method {
        const char* name;
        Integrator* integrator;
    } methods[] = {{"pt mis", &pt}, {"pt equiangular", &ea}, {"bdpt", &bdpt}};
    for (const Method& m : methods) {
        const auto px = renders(*scene, *m.integrator, 64, 24, true);
        for (int k = 0; k < 9; ++k) {
            const PixelEstimate& e = px[size_t((ly - 1 + k / 3) * W + lx - 1 + k % 3)];
            const double z = std::abs(e.mean(0) - ref[size_t(k)]) / e.stderror(0);
            INFO(m.name << ", pixel " << k << " of the 3 x 3: " << e.mean(0) << " +- " << e.stderror(0) << ", integral "
                        << ref[size_t(k)]);
            CHECK(z < zBound(27));
        }
    }
    const auto warped = renders(*scene, ea, 64, 24, true), uniform = renders(*scene, ea, 64, 24, false);
    const size_t centre = size_t(ly * W + lx);
    INFO("light's pixel, spread over renders: inverse distance " << warped[centre].stderror(0) << ", uniform "
                                                                 << uniform[centre].stderror(0));
    CHECK(warped[centre].stderror(0) < 0.25 * uniform[centre].stderror(0));
}

// The camera's density that the one-event split reads (LightPixels::density) is the
// renderer's: relative to uniform, it averages to 1 over each pixel around the image, is what
// the sampler says it draws there, and is 1 elsewhere.
TEST_CASE("light pixels: the film density the weights read is the one the renderer draws", "[light-pixels]") {
    auto scene = loadTestScene("single_near.gltf");
    CameraConnection cc;
    REQUIRE(connectToCamera(scene->camera(), kLight, W, W, &cc));
    const LightPixels lp(*scene, W, W);
    Rng rng(5, 5);
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) {
            const LightPixel* p = lp.find(uint32_t(y * W + x));
            double mean = 0;
            const int n = 4000;
            for (int i = 0; i < n; ++i) {
                const Sample2 u = rng.next2D();
                const float m = lp.density(float(x) + u.u, float(y) + u.v);
                mean += m / n;
                if (p) {
                    INFO("pixel (" << x << ", " << y << "), film position (" << u.u << ", " << u.v << ")");
                    CHECK(m == Approx(inverseDistancePdf(p->cx, p->cy, u.u, u.v)).epsilon(2e-3));
                } else {
                    CHECK(m == 1.0f);
                }
            }
            INFO("pixel (" << x << ", " << y << ")");
            CHECK(mean == Approx(1.0).epsilon(p && x == int(cc.fx) && y == int(cc.fy) ? 0.1 : 0.05));
        }
    CHECK(lp.density(-0.5f, 3.0f) == 1.0f);
    CHECK(lp.density(float(W), 3.0f) == 1.0f);
}
