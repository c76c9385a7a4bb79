// Product sampling (equi-angular × Henyey–Greenstein phase): chi-square of the sampled angle
// against the sampler's density for g from −0.99 to 0.99, the density integrates to 1, each
// part's cdf inverts its sample, g = 0 is plain equi-angular bit for bit, the density follows
// the target product (variance factor near 1 where plain equi-angular is far off), and the
// edge cases (light on the ray, g = ±0.9999, unbounded and tiny spans) stay finite.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/sampling/equiangular.h"
#include "brume/sampling/hg.h"
#include "brume/scene/gltf_loader.h"
#include "support/pixel_estimates.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

struct Case {
    const char* name;
    Vec3 c;      // light position; the ray is the +z axis from the origin
    float a, b;  // segment
};

const Case kCases[] = {
    {"light in view ahead, long segment past it", Vec3(0.3f, 0, 6), 0, 20},
    {"light beside the middle", Vec3(0.5f, 0, 2), 0, 4},
    {"segment wholly before the closest approach", Vec3(0.2f, 0, 10), 0, 3},
    {"segment wholly behind the closest approach", Vec3(0.3f, 0.1f, -2), 1, 6},
    {"unbounded, light close to the ray", Vec3(0.02f, 0, 3), 0, INFINITY},
};

const double kGs[] = {0.3, 0.9, 0.99, -0.6, -0.99};

// The angle u = atan((t − Δ)/D) of a distance, and the density per unit u.
double angleOf(const EquiAngular& ea, double t) { return std::atan((t - ea.delta) / ea.D); }
double pdfPerAngle(const EquiAngular& ea, double u) {
    double x = std::tan(u) * ea.D;
    // (t rounded to float may leave [a, b] at the ends, where the density is 0)
    float t = std::min(std::max(float(ea.delta + x), float(ea.a)), float(ea.b));
    return double(equiAngularPdf(ea, t)) * (ea.D * ea.D + x * x) / ea.D;
}

// The target per unit u: the phase at x(t) between the ray and the direction to c.
double target(const EquiAngular& ea, double u, double g) {
    return hgPhase(float(-std::sin(u)), float(g));
}

EquiAngular productFor(const Case& c, double g) {
    return makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), c.c, c.a, c.b, float(g));
}

}  // namespace

TEST_CASE("product samples follow their density (chi-square over the angle, p > 0.01 / tests)",
          "[sampling][equiangular][product]") {
    const double alpha = 0.01 / double(std::size(kCases) * std::size(kGs));
    for (const Case& c : kCases)
        for (double g : kGs) {
            EquiAngular ea = productFor(c, g);
            REQUIRE(ea.phase.alpha < 1);
            auto result = intervalHistogramTest(
                [&](Sample2 u) { return std::optional<double>(angleOf(ea, sampleEquiAngular(ea, u.u))); },
                [&](double u) { return pdfPerAngle(ea, u); }, ea.thetaA, ea.thetaB, 60, 400000);
            INFO(c.name << ", g = " << g << "\n" << result.chi2.table);
            CHECK(result.chi2.pValue > alpha);
            CHECK(result.outside == 0);
            CHECK(result.pdfIntegral == Approx(1.0).epsilon(2e-3));
        }
}

TEST_CASE("product density integrates to 1, each part's cdf inverts its sample, and t turns back at α without a jump",
          "[sampling][equiangular][product]") {
    for (const Case& c : kCases)
        for (double g : kGs) {
            EquiAngular ea = productFor(c, g);
            INFO(c.name << ", g = " << g);
            double integral = integrate1D([&](double u) { return pdfPerAngle(ea, u); }, ea.thetaA, ea.thetaB, 1e-10, 1e-8);
            CHECK(integral == Approx(1.0).epsilon(1e-3));
            // One number picks the part (u < α: the uniform angle, forwards) and, rescaled,
            // samples it (the phase part backwards along the ray: its cdf along the ray falls),
            // so both meet at the far end at u = α, each at its own cdf's 1 (no jump there: a
            // jump costs what Owen-scrambled Sobol numbers give, equiangular.cpp).
            const double a = ea.phase.alpha;
            for (double xi : {0.0, 0.13, 0.37, 0.5, 0.81, 0.999, 0.9999}) {
                float uUniform = float(a * xi), uPhase = float(a + (1 - a) * xi);
                double tU = sampleEquiAngular(ea, uUniform), tP = sampleEquiAngular(ea, uPhase);
                CHECK((angleOf(ea, tU) - ea.thetaA) / (ea.thetaB - ea.thetaA) == Approx(double(uUniform) / a).margin(1e-4));
                double cdf = hgAnglePhaseCdf(ea.phase, halfAngleAt(tP - ea.delta, ea.D));
                if (ea.phase.mirror) cdf = 1 - cdf;  // (S falls along the ray for g < 0)
                CHECK(cdf == Approx(1 - (double(uPhase) - a) / (1 - a)).margin(2e-4));
            }
        }
}

TEST_CASE("product sampling follows the target phase: variance factor near 1", "[sampling][equiangular][product]") {
    // V = ∫ f²/p du / (∫ f du)², f the phase along the angle: 1 for a perfect sampler; plain
    // equi-angular has V = (θb − θa)∫f²/(∫f)². The phase part ignores a factor 1/cos(θ'/2) that
    // only matters away from the peak, and the uniform part bounds the rest (hg_angle.h).
    double worstProduct = 0, worstPlain = 0;
    for (const Case& c : kCases)
        for (double g : {0.9, 0.99, -0.9}) {
            EquiAngular ea = productFor(c, g);
            auto f = [&](double u) { return target(ea, u, g); };
            double I = integrate1D(f, ea.thetaA, ea.thetaB, 1e-12, 1e-9);
            double V = integrate1D([&](double u) { return f(u) * f(u) / pdfPerAngle(ea, u); }, ea.thetaA, ea.thetaB,
                                   1e-12, 1e-9) / (I * I);
            double Vplain = integrate1D([&](double u) { return f(u) * f(u); }, ea.thetaA, ea.thetaB, 1e-12, 1e-9) *
                            (ea.thetaB - ea.thetaA) / (I * I);
            INFO(c.name << ", g = " << g << ": V product " << V << ", plain " << Vplain);
            CHECK(V >= 1 - 1e-6);
            CHECK(V < 1.6);
            worstProduct = std::max(worstProduct, V);
            worstPlain = std::max(worstPlain, Vplain);
        }
    INFO("worst V: product " << worstProduct << ", plain " << worstPlain);
    CHECK(worstPlain > 20 * worstProduct);  // the cases include forward peaks that plain misses
}

TEST_CASE("g = 0 is plain equi-angular, bit for bit", "[sampling][equiangular][product]") {
    for (const Case& c : kCases) {
        EquiAngular plain = makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), c.c, c.a, c.b);
        EquiAngular zero = productFor(c, 0.0);
        CHECK(zero.phase.alpha == 1);
        for (float u : {0.0f, 0.2f, 0.5f, 0.77f, 0.9999f}) {
            float t = sampleEquiAngular(zero, u);
            CHECK(t == sampleEquiAngular(plain, u));
            CHECK(equiAngularPdf(zero, t) == equiAngularPdf(plain, t));
        }
        CHECK(equiAngularStandInPdf(Vec3(0, 0, 0), Vec3(0, 0, 1), c.c, 1.5f, 0.0f) ==
              equiAngularStandInPdf(Vec3(0, 0, 0), Vec3(0, 0, 1), c.c, 1.5f));
    }
}

TEST_CASE("product sampling edge cases stay finite and positive", "[sampling][equiangular][product]") {
    struct Edge {
        const char* name;
        Vec3 c;
        float a, b;
    };
    const Edge edges[] = {
        {"light exactly on the ray ahead (D = 0)", Vec3(0, 0, 2), 0, 4},
        {"light exactly on the ray behind", Vec3(0, 0, -2), 0, 4},
        {"unbounded", Vec3(1, 0, 3), 0, INFINITY},
        {"short far segment", Vec3(0, 1000, 0), 5.0f, 5.0f + 1e-3f},
    };
    for (const Edge& e : edges)
        for (double g : {0.9999, -0.9999, 0.999, -0.999, 1.0, -1.0, 0.5}) {
            EquiAngular ea = makeEquiAngular(Vec3(0, 0, 0), Vec3(0, 0, 1), e.c, e.a, e.b, float(g));
            INFO(e.name << ", g = " << g);
            for (float u : {0.0f, 0.05f, 0.0999f, 0.1f, 0.25f, 0.5f, 0.75f, 0.99f, 0.9999999f}) {
                float t = sampleEquiAngular(ea, u);
                float pdf = equiAngularPdf(ea, t);
                CHECK(std::isfinite(t));
                CHECK(t >= e.a);
                CHECK(t <= e.b);
                CHECK(std::isfinite(pdf));
                CHECK(pdf > 0);
            }
            float standIn = equiAngularStandInPdf(Vec3(0, 0, 0), Vec3(0, 0, 1), e.c, 1.0f, float(g));
            CHECK(std::isfinite(standIn));
            CHECK(standIn > 0);
        }
}

TEST_CASE("g = 0: --connect product renders the bits of --connect equiangular (pt and bdpt)", "[equiangular][product]") {
    // bench_fog_room: isotropic fog, a point light, walls; full transport.
    Scene scene(loadGltf(std::string(BRUME_SCENES) + "/bench_fog_room.gltf"));
    PathTracer ptPlain(PathTracerOptions{-1, true, ConnectMode::EquiAngular});
    PathTracer ptProduct(PathTracerOptions{-1, true, ConnectMode::Product});
    BdptOptions o;
    o.connect = ConnectMode::EquiAngular;
    BdptIntegrator bdptPlain(o);
    o.connect = ConnectMode::Product;
    BdptIntegrator bdptProduct(o);
    const std::pair<const Integrator*, const Integrator*> pairs[] = {{&ptPlain, &ptProduct}, {&bdptPlain, &bdptProduct}};
    for (const auto& [plain, product] : pairs) {
        auto a = estimatePixels(scene, *plain, 12, 9, 8, 3);
        auto b = estimatePixels(scene, *product, 12, 9, 8, 3);
        int differ = 0;
        for (size_t i = 0; i < a.size(); ++i)
            for (int c = 0; c < 3; ++c) differ += a[i].sum[c] != b[i].sum[c] || a[i].sum2[c] != b[i].sum2[c];
        CHECK(differ == 0);
    }
}
