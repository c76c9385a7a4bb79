// Chi-square tests of every sampling routine against its density, plus checks that each
// density integrates to one. Significance 0.01 per test case, Bonferroni-corrected when a
// case runs several parameter sets. Seeds are fixed, so the p-values are reproducible.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "brume/sampling/distribution1d.h"
#include "brume/sampling/free_flight.h"
#include "brume/sampling/ggx.h"
#include "brume/sampling/hg.h"
#include "brume/sampling/sampler.h"
#include "brume/sampling/warp.h"
#include "brume/scene/medium.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr long kSamples = 1000000;
// The densities are normalised analytically; the quadrature is accurate to ~1e-6, so 1e-3
// only forgives float rounding in the densities themselves.
constexpr double kIntegralTol = 1e-3;

void report(const std::string& name, const HistogramResult& r) {
    std::printf("[chi2] %-40s chi2 = %9.2f  dof = %4d  p = %.4f  integral = %.7f  (quadrature warnings %d)\n",
                name.c_str(), r.chi2.chi2, r.chi2.dof, r.chi2.pValue, r.pdfIntegral, r.integrationWarnings);
}

// The common checks of one histogram run: valid samples, p above the (corrected) level.
void checkHistogram(const std::string& name, const HistogramResult& r, double alpha) {
    report(name, r);
    INFO(name << "\n" << r.chi2.table);
    CHECK(r.invalid == 0);
    CHECK(r.chi2.pValue > alpha);
}

Vec3 unit(Vec3 v) { return normalize(v); }

}  // namespace

// ---------------------------------------------------------------------------------------
// The statistics support itself

TEST_CASE("chi-square p-values match known quantiles", "[support]") {
    // 95% quantiles of the chi-square distribution.
    CHECK(chiSquarePValue(3.841458820694124, 1) == Approx(0.05).epsilon(1e-9));
    CHECK(chiSquarePValue(18.307038053275146, 10) == Approx(0.05).epsilon(1e-9));
    CHECK(chiSquarePValue(124.34211340400407, 100) == Approx(0.05).epsilon(1e-9));
    // Even dof 2k: Q(k, x) = e^{−x} Σ_{i<k} x^i / i!, summed here in logs (large a, both
    // sides of the switch between series and continued fraction).
    for (double chi2 : {900.0, 1000.0, 1107.0, 1300.0}) {
        const int k = 500;
        double x = 0.5 * chi2, sum = 0, logTerm = -x;  // log(e^{−x} x^i / i!) at i = 0
        for (int i = 0; i < k; ++i) {
            sum += std::exp(logTerm);
            logTerm += std::log(x) - std::log(double(i + 1));
        }
        CHECK(chiSquarePValue(chi2, 2 * k) == Approx(sum).epsilon(1e-10));
    }
    // Two degrees of freedom: Q = exp(−x/2).
    for (double x : {0.01, 0.5, 3.0, 20.0, 200.0}) CHECK(chiSquarePValue(x, 2) == Approx(std::exp(-0.5 * x)).epsilon(1e-12));
    // Q(1/2, x) = erfc(√x), both sides of the series / continued-fraction switch.
    for (double x : {0.05, 0.7, 1.4, 5.0, 30.0}) CHECK(gammaQ(0.5, x) == Approx(std::erfc(std::sqrt(x))).epsilon(1e-12));
    for (double a : {0.5, 3.0, 47.5})
        for (double x : {0.1, a, a + 2, 3 * a}) CHECK(gammaP(a, x) + gammaQ(a, x) == Approx(1.0).epsilon(1e-13));
    CHECK(chiSquarePValue(0.0, 5) == 1.0);
    CHECK(chiSquarePValue(std::numeric_limits<double>::infinity(), 5) == 0.0);
}

TEST_CASE("chiSquareTest pools sparse neighbours and rejects impossible samples", "[support]") {
    // Bins 0..2 pool into one group (expected 0.5 + 2 + 10 = 12.5), bin 3 stays alone; the
    // trailing bin 4 (expected 1) joins bin 3.
    std::vector<double> obs = {1, 3, 8, 12, 0};
    std::vector<double> exp = {0.5, 2, 10, 9.5, 1};
    ChiSquareResult r = chiSquareTest(obs, exp, 5.0);
    double g1 = (12 - 12.5) * (12 - 12.5) / 12.5, g2 = (12 - 10.5) * (12 - 10.5) / 10.5;
    CHECK(r.dof == 1);
    CHECK(r.chi2 == Approx(g1 + g2));
    CHECK(r.pValue == Approx(chiSquarePValue(g1 + g2, 1)));
    // An observation where the expected count is exactly zero fails outright.
    ChiSquareResult bad = chiSquareTest({1, 50, 49}, {0, 50, 50});
    CHECK(bad.pValue == 0.0);
    CHECK(bad.table.find("expected count is 0") != std::string::npos);
    // Empty zero-expected bins are ignored.
    ChiSquareResult ok = chiSquareTest({0, 50, 50}, {0, 50, 50});
    CHECK(ok.dof == 1);
    CHECK(ok.chi2 == 0.0);
}

TEST_CASE("the histogram tests have power against wrong densities", "[support]") {
    // Uniform sphere samples against a density tilted by 5%: must be rejected.
    auto sample = [](Sample2 u) -> std::optional<Vec3> { return sampleUniformSphere(u); };
    HistogramResult tilted = sphereHistogramTest(
        sample, [](Vec3 w) { return (1.0 + 0.05 * w.z) / (4 * M_PI); }, 20, 20, kSamples);
    report("power: sphere vs 5% tilted pdf", tilted);
    CHECK(tilted.pdfIntegral == Approx(1.0).epsilon(1e-6));
    CHECK(tilted.chi2.pValue < 1e-6);
    // Samples outside the support of the density are caught.
    HistogramResult cone = sphereHistogramTest(
        sample, [](Vec3 w) { return w.z > 0 ? 1.0 / (2 * M_PI) : 0.0; }, 20, 20, 10000);
    CHECK(cone.chi2.pValue == 0.0);
    // HG with g = 0.3 tested against g = 0.32.
    Vec3 d = unit(Vec3(0.2f, 0.5f, -0.7f));
    SphereHistogramOptions opt;
    opt.axis = d;
    HistogramResult hg = sphereHistogramTest(
        [&](Sample2 u) -> std::optional<Vec3> { return sampleHG(d, 0.3f, u); },
        [&](Vec3 w) { return hgPhase(dot(d, w), 0.32f); }, 20, 20, kSamples, opt);
    report("power: HG g=0.3 vs pdf g=0.32", hg);
    CHECK(hg.chi2.pValue < 1e-6);
    // Free flight with σt = 1 against a density with σt = 1.02.
    HistogramOptions fo;
    fo.outsideProbability = std::exp(-1.02 * 3.0);
    HistogramResult ff = intervalHistogramTest(
        [](Sample2 u) -> std::optional<double> { return sampleFreeFlight(1.0f, u.u); },
        [](double t) { return 1.02 * std::exp(-1.02 * t); }, 0.0, 3.0, 40, kSamples, fo);
    report("power: free flight 1 vs pdf 1.02", ff);
    CHECK(ff.chi2.pValue < 1e-6);
}

TEST_CASE("quadrature handles smooth, peaked and discontinuous integrands", "[support]") {
    // Default tolerances (relative 1e-6), then tight ones.
    CHECK(integrate1D([](double x) { return std::sin(x); }, 0, M_PI) == Approx(2.0).epsilon(1e-6));
    CHECK(integrate1D([](double x) { return std::sin(x); }, 0, M_PI, 1e-14, 1e-12) == Approx(2.0).epsilon(1e-11));
    // A jump inside the interval.
    CHECK(integrate1D([](double x) { return x < 0.3141 ? 2.0 : 0.0; }, 0, 1) == Approx(0.6282).epsilon(1e-6));
    CHECK(integrate1D([](double x) { return x < 0.3141 ? 2.0 : 0.0; }, 0, 1, 1e-14, 1e-11) ==
          Approx(0.6282).epsilon(1e-10));
    // Sharply peaked: ∫_{-1}^{1} ε/(π(x²+ε²)) dx = 2 atan(1/ε)/π.
    double eps = 1e-4;
    CHECK(integrate1D([&](double x) { return eps / (M_PI * (x * x + eps * eps)); }, -1, 1) ==
          Approx(2 * std::atan(1 / eps) / M_PI).epsilon(1e-6));
    // Disk of radius 0.7: area π·0.49.
    CHECK(integrate2D([](double x, double y) { return x * x + y * y < 0.49 ? 1.0 : 0.0; }, -1, 1, -1, 1) ==
          Approx(M_PI * 0.49).epsilon(1e-6));
    CHECK(takeIntegrationBudgetWarnings() == 0);
}

TEST_CASE("RunningStats and zScore", "[support]") {
    RunningStats s;
    for (int i = 1; i <= 10; ++i) s.add(i);
    CHECK(s.count() == 10);
    CHECK(s.mean() == Approx(5.5));
    CHECK(s.variance() == Approx(55.0 / 6.0));
    CHECK(s.standardError() == Approx(std::sqrt(55.0 / 6.0 / 10.0)));
    CHECK(zScore(1.2, 1.0, 0.1) == Approx(2.0));
    CHECK(zScore(1.0, 1.0, 0.0) == 0.0);
    CHECK(std::isinf(zScore(1.1, 1.0, 0.0)));
}

// ---------------------------------------------------------------------------------------
// Warps

TEST_CASE("uniform sphere sampling matches its density", "[chi2][warp]") {
    const Vec3 axes[] = {Vec3(0, 0, 1), unit(Vec3(0.6f, -0.3f, 0.4f))};
    const double alpha = kAlpha / 2;
    int k = 0;
    for (Vec3 axis : axes) {
        SphereHistogramOptions opt;
        opt.axis = axis;
        opt.seed = 11 + k;
        HistogramResult r = sphereHistogramTest([](Sample2 u) -> std::optional<Vec3> { return sampleUniformSphere(u); },
                                                [](Vec3) { return double(uniformSpherePdf()); }, 20, 40, kSamples, opt);
        checkHistogram("uniform sphere, axis " + std::to_string(k++), r, alpha);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
}

TEST_CASE("concentric disk sampling is uniform on the disk", "[chi2][warp]") {
    HistogramOptions opt;
    opt.seed = 21;
    HistogramResult r = histogram2DTest(
        [](Sample2 u) -> std::optional<std::pair<double, double>> {
            Sample2 d = sampleConcentricDisk(u);
            return std::make_pair(double(d.u), double(d.v));
        },
        [](double x, double y) { return x * x + y * y <= 1.0 ? 1.0 / M_PI : 0.0; }, uniformEdges(24, -1, 1),
        uniformEdges(24, -1, 1), kSamples, opt);
    checkHistogram("concentric disk", r, kAlpha);
    CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
}

TEST_CASE("cosine hemisphere sampling matches its density", "[chi2][warp]") {
    SphereHistogramOptions opt;
    opt.seed = 31;
    // One bin for the lower hemisphere (expected 0), 20 for the upper one.
    opt.cosThetaEdges = uniformEdges(20, 0.0, 1.0);
    opt.cosThetaEdges.insert(opt.cosThetaEdges.begin(), -1.0);
    HistogramResult r = sphereHistogramTest([](Sample2 u) -> std::optional<Vec3> { return sampleCosineHemisphere(u); },
                                            [](Vec3 w) { return double(cosineHemispherePdf(w.z)); }, 21, 32, kSamples,
                                            opt);
    checkHistogram("cosine hemisphere", r, kAlpha);
    CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
}

TEST_CASE("uniform cone sampling matches its density", "[chi2][warp]") {
    const float cosMaxes[] = {-0.6f, 0.0f, 0.5f, 0.95f, 0.999f};
    const double alpha = kAlpha / 5;
    int k = 0;
    for (float cosMax : cosMaxes) {
        SphereHistogramOptions opt;
        opt.seed = 41 + k++;
        // Everything below the cone in one bin (expected 0). The lowest cone bin starts a
        // little below cosMax, so float rounding of samples at the rim cannot push them into
        // the empty bin; the pdf jump inside that bin is resolved by the quadrature.
        double lo = cosMax - 0.01 * (1.0 - cosMax);
        opt.cosThetaEdges = uniformEdges(20, lo, 1.0);
        opt.cosThetaEdges.insert(opt.cosThetaEdges.begin(), -1.0);
        float pdf = uniformConePdf(cosMax);
        HistogramResult r = sphereHistogramTest(
            [&](Sample2 u) -> std::optional<Vec3> { return sampleUniformCone(u, cosMax); },
            [&](Vec3 w) { return w.z >= cosMax ? double(pdf) : 0.0; }, 21, 24, kSamples, opt);
        checkHistogram("uniform cone, cosMax " + std::to_string(cosMax), r, alpha);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
}

TEST_CASE("uniform cone sampling resolves small polar angles in a narrow cone", "[warp]") {
    // A 0.5° cone: the fraction of directions within 0.01·θmax of the axis is 1e-4 (solid
    // angle ∝ θ²). Taking sinθ from a rounded cosθ put 1 in ~600 samples exactly on the axis.
    const float thetaMax = float(0.5 * M_PI / 180.0);
    const float cosMax = std::cos(thetaMax);
    const long n = 1000000;
    Sampler sampler(7, 0, 0);
    long near = 0, onAxis = 0;
    for (long i = 0; i < n; ++i) {
        Vec3 w = sampleUniformCone(sampler.next2D(), cosMax);
        float sinTheta = std::sqrt(w.x * w.x + w.y * w.y);
        onAxis += sinTheta == 0.0f;
        near += sinTheta < 0.01f * std::sin(thetaMax);
    }
    const double p = 1e-4, expected = p * n, sigma = std::sqrt(n * p * (1 - p));
    INFO("within 0.01 thetaMax: " << near << " (expected " << expected << " +- " << sigma << "), on the axis: " << onAxis);
    CHECK(std::abs(near - expected) < 5 * sigma);
    CHECK(onAxis == 0);
}

TEST_CASE("uniform triangle sampling is uniform in area", "[chi2][warp]") {
    // Barycentrics (b0, b1) of the triangle b0, b1 ≥ 0, b0 + b1 ≤ 1 (area 1/2): the area
    // density of any triangle maps affinely to the constant 2 here.
    long outsideTriangle = 0;
    HistogramOptions opt;
    opt.seed = 51;
    HistogramResult r = histogram2DTest(
        [&](Sample2 u) -> std::optional<std::pair<double, double>> {
            Sample2 b = sampleUniformTriangle(u);
            if (b.u < 0 || b.v < 0 || 1.0f - b.u - b.v < -1e-6f) ++outsideTriangle;
            return std::make_pair(double(b.u), double(b.v));
        },
        [](double b0, double b1) { return b0 + b1 <= 1.0 ? 2.0 : 0.0; }, uniformEdges(20, 0, 1),
        uniformEdges(20, 0, 1), kSamples, opt);
    checkHistogram("uniform triangle (barycentrics)", r, kAlpha);
    CHECK(outsideTriangle == 0);
    CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
}

// ---------------------------------------------------------------------------------------
// Henyey–Greenstein

TEST_CASE("HG sampling matches hgPhase", "[chi2][hg]") {
    const float gs[] = {-0.9f, -0.3f, 0.0f, 0.3f, 0.9f, 0.99f};
    const double alpha = kAlpha / 6;
    const Vec3 d = unit(Vec3(0.36f, -0.48f, 0.8f));
    int k = 0;
    for (float g : gs) {
        SphereHistogramOptions opt;
        opt.seed = 61 + k++;
        // The histogram's pole sits on the peak of the lobe (d for g > 0, −d for g < 0), in a
        // frame of the test's own, not brume::Frame. Strongly peaked lobes get bins that
        // shrink geometrically towards the pole, down to 1 − cosθ = 1e-4 (a thousand times
        // the float resolution of cosθ near 1).
        opt.axis = g < 0 ? -d : d;
        int thetaBins = 20;
        if (std::abs(g) >= 0.9f) {
            thetaBins = 24;
            opt.cosThetaEdges = peakedCosThetaEdges(thetaBins, 1e-4);
        }
        HistogramResult r = sphereHistogramTest([&](Sample2 u) -> std::optional<Vec3> { return sampleHG(d, g, u); },
                                                [&](Vec3 w) { return double(hgPhase(dot(d, w), g)); }, thetaBins, 24,
                                                kSamples, opt);
        checkHistogram("HG g = " + std::to_string(g), r, alpha);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
}

// ---------------------------------------------------------------------------------------
// Free-flight sampling

// Through Medium::sampleDistance, as the integrators sample: the channel driving the
// distance drawn with probabilities w (uniform, skewed, one-hot as a hero channel), the
// density the mixture Σ_c w_c·σt_c·exp(−σt_c·t), and passing the piece's end the rest.
namespace {

struct FreeFlightCase {
    Spectrum sigmaT;
    Spectrum w;
    float tmax;
    const char* name;
};

void checkFreeFlight(const FreeFlightCase& c, const std::vector<double>& edges, uint64_t seed, double alpha) {
    Medium m;
    m.sigmaS = c.sigmaT;
    m.sigmaA = Spectrum(0.0f);
    const Ray ray{Vec3(0.0f), Vec3(0, 0, 1)};
    auto mix = [&](double t, bool pass) {
        double p = 0;
        for (int k = 0; k < 3; ++k)
            p += c.w[k] * (pass ? freeFlightPdfPass(c.sigmaT[k], float(t)) : freeFlightPdfScatter(c.sigmaT[k], float(t)));
        return p;
    };
    HistogramOptions opt;
    opt.seed = seed;
    // Flights past tmax (including t = +∞ from a channel with σt = 0) form one extra bin
    // whose probability is the pass probability.
    opt.outsideProbability = mix(c.tmax, true);
    long negative = 0, badPdf = 0;
    HistogramResult r = intervalHistogramTest(
        [&](Sample2 u) -> std::optional<double> {
            MediumSample ms = m.sampleDistance(ray, 0.0f, c.tmax, u.u, u.v, c.w, false);
            if (ms.t < 0) ++negative;
            if (std::abs(ms.pdf - mix(ms.t, !ms.scattered)) > 1e-6 * ms.pdf) ++badPdf;  // (float weights)
            return ms.scattered ? double(ms.t) : std::numeric_limits<double>::infinity();
        },
        [&](double t) { return mix(t, false); }, edges, kSamples, opt);
    checkHistogram(std::string("free flight, ") + c.name, r, alpha);
    CHECK(negative == 0);
    CHECK(badPdf == 0);  // the density it reports is the one it samples
    INFO("scatter integral " << r.pdfIntegral << " + pass " << opt.outsideProbability);
    CHECK(r.pdfIntegral + opt.outsideProbability == Approx(1.0).epsilon(kIntegralTol));
}

std::vector<double> uniformEdges(double tmax, int n) {
    std::vector<double> e;
    for (int i = 0; i <= n; ++i) e.push_back(tmax * i / n);
    return e;
}

}  // namespace

TEST_CASE("free-flight sampling matches its scatter density and pass probability", "[chi2][free_flight]") {
    const Spectrum third(1.0f / 3.0f);
    const FreeFlightCase cases[] = {
        {Spectrum(1.0f), third, 3.0f, "grey 1"},
        {Spectrum(0.5f, 2.0f, 8.0f), third, 4.0f, "chromatic (0.5, 2, 8), uniform channels"},
        {Spectrum(0.5f, 2.0f, 8.0f), Spectrum(0.7f, 0.25f, 0.05f), 4.0f, "chromatic (0.5, 2, 8), weights (0.7, 0.25, 0.05)"},
        {Spectrum(0.0f, 1.5f, 4.0f), third, 3.0f, "chromatic (0, 1.5, 4)"},
        {Spectrum(0.5f, 2.0f, 8.0f), heroChannel(1), 3.0f, "chromatic (0.5, 2, 8), hero green"},
        {Spectrum(0.02f, 0.02f, 0.02f), third, 10.0f, "grey 0.02 (mostly passes)"},
    };
    int k = 0;
    for (const FreeFlightCase& c : cases) checkFreeFlight(c, uniformEdges(c.tmax, 40), 71 + k++, kAlpha / 6);
    // Channel picks follow the weights, never a channel of weight 0.
    const Spectrum w(0.2f, 0.0f, 0.8f);
    int counts[3] = {0, 0, 0};
    Rng rng(5, 6);
    for (int i = 0; i < 100000; ++i) ++counts[pickChannel(w, rng.next1D())];
    CHECK(counts[1] == 0);
    CHECK(counts[0] / 1e5 == Approx(0.2).margin(5 * std::sqrt(0.16 / 1e5)));
    CHECK(pickChannel(w, 0.99999994f) == 2);
    CHECK(pickChannel(heroChannel(1), 0.0f) == 1);
    CHECK(freeFlightPdfPass(0.0f, std::numeric_limits<float>::infinity()) == Approx(1.0));
    CHECK(freeFlightPdfPass(1.0f, 0.0f) == Approx(1.0));
}

TEST_CASE("free-flight sampling in a dense medium, bins spaced geometrically", "[chi2][free_flight]") {
    // σt = 8: bins from 1e-3 growing geometrically to 3 (plus [0, 1e-3]) resolve both the
    // start of the exponential and its tail.
    std::vector<double> edges = {0.0};
    for (int i = 0; i <= 30; ++i) edges.push_back(1e-3 * std::pow(3000.0, i / 30.0));
    checkFreeFlight({Spectrum(8.0f), Spectrum(1.0f / 3.0f), float(edges.back()), "grey 8, geometric bins"}, edges, 79, kAlpha);
}

// ---------------------------------------------------------------------------------------
// GGX

TEST_CASE("GGX normal sampling matches D(h) cos(theta_h)", "[chi2][ggx]") {
    const float alphas[] = {0.05f, 0.3f, 0.8f};
    const double alpha = kAlpha / 3;
    int k = 0;
    for (float a : alphas) {
        SphereHistogramOptions opt;
        opt.seed = 81 + k++;
        // One bin for the lower hemisphere (expected 0); the upper one in bins shrinking
        // towards the normal down to 1 − cosθ = max(1e-4, α²/20), a twentieth of the lobe's
        // width in 1 − cosθ.
        opt.cosThetaEdges = peakedCosThetaEdges(20, std::max(1e-4, double(a) * a / 20), 0.0);
        opt.cosThetaEdges.insert(opt.cosThetaEdges.begin(), -1.0);
        HistogramResult r = sphereHistogramTest([&](Sample2 u) -> std::optional<Vec3> { return sampleGgxNormal(a, u); },
                                                [&](Vec3 h) { return double(ggxNormalPdf(h, a)); }, 21, 24, kSamples,
                                                opt);
        checkHistogram("GGX alpha = " + std::to_string(a), r, alpha);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
    }
}

TEST_CASE("GGX D(h) cos(theta_h) integrates to one over the hemisphere", "[ggx]") {
    for (float a : {0.01f, 0.05f, 0.3f, 0.5f, 0.8f, 1.0f}) {
        // ∫ D cosθ dω = ∫_0^{2π} ∫_0^1 D(μ) μ dμ dφ; D is evaluated through ggxD on a
        // direction at azimuth φ, so the full 2D integral is taken. The μ range is split at
        // geometrically spaced points towards the peak at μ = 1.
        std::vector<double> mu = peakedCosThetaEdges(24, std::max(1e-6, double(a) * a * 1e-3), 0.0);
        double total = 0;
        for (size_t i = 0; i + 1 < mu.size(); ++i)
            total += integrate2D(
                [&](double m, double phi) {
                    double s = std::sqrt(std::max(0.0, 1 - m * m));
                    Vec3 h(float(s * std::cos(phi)), float(s * std::sin(phi)), float(m));
                    return double(ggxD(h, a)) * m;
                },
                mu[i], mu[i + 1], 0, 2 * M_PI, 1e-10, 1e-6);
        INFO("alpha = " << a << ": integral = " << total);
        CHECK(total == Approx(1.0).epsilon(kIntegralTol));
    }
}

// ---------------------------------------------------------------------------------------
// Distribution1D

TEST_CASE("Distribution1D samples in proportion to its weights", "[chi2][distribution]") {
    std::vector<std::vector<float>> weightSets;
    // Zeros at the start, in a run in the middle and at the end.
    weightSets.push_back({0, 3, 0, 0, 1, 5, 0.5f, 0, 2, 1e-3f, 0});
    // Many weights spanning four orders of magnitude, every seventh one zero.
    {
        std::vector<float> w(500);
        Sampler s(5, 0, 0);
        for (size_t i = 0; i < w.size(); ++i) w[i] = i % 7 == 3 ? 0.0f : std::pow(10.0f, 4.0f * s.next1D());
        weightSets.push_back(w);
    }
    const double alpha = kAlpha / double(weightSets.size());
    int k = 0;
    for (const std::vector<float>& w : weightSets) {
        Distribution1D dist(w);
        double sum = 0;
        for (float x : w) sum += x;
        REQUIRE(dist.size() == int(w.size()));
        CHECK(dist.total() == Approx(sum));
        std::vector<double> expected(w.size()), observed(w.size(), 0.0);
        for (size_t i = 0; i < w.size(); ++i) {
            expected[i] = kSamples * w[i] / sum;
            CHECK(dist.pmf(int(i)) == Approx(w[i] / sum).epsilon(1e-6));
        }
        Sampler sampler(91 + k, 0, 0);
        long badProb = 0;
        for (long n = 0; n < kSamples; ++n) {
            float prob;
            int i = dist.sample(sampler.next1D(), &prob);
            REQUIRE(i >= 0);
            REQUIRE(i < dist.size());
            if (prob != dist.pmf(i)) ++badProb;
            observed[i] += 1;
        }
        CHECK(badProb == 0);
        for (size_t i = 0; i < w.size(); ++i)
            if (w[i] == 0) CHECK(observed[i] == 0);
        ChiSquareResult r = chiSquareTest(observed, expected);
        std::printf("[chi2] %-48s chi2 = %10.2f  dof = %4d  p = %.4f\n",
                    ("Distribution1D set " + std::to_string(k)).c_str(), r.chi2, r.dof, r.pValue);
        INFO(r.table);
        CHECK(r.pValue > alpha);

        // Every float the Sampler can return (all 2^24 of them): each index is hit by a
        // number of them within one of its share, and zero weights never.
        std::vector<long> counts(w.size(), 0);
        float prob;
        for (uint32_t j = 0; j < (1u << 24); ++j) ++counts[dist.sample(float(j) * 0x1p-24f, &prob)];
        long worst = 0;
        for (size_t i = 0; i < w.size(); ++i) {
            if (w[i] == 0) CHECK(counts[i] == 0);
            double share = double(dist.pmf(int(i))) * double(1u << 24);
            worst = std::max(worst, long(std::ceil(std::abs(counts[i] - share))));
        }
        // The float pmf carries a relative error of 6e-8, i.e. ≤ 1 count per 2^24 (here).
        CHECK(worst <= 2);
        ++k;
    }
}
