// Von Mises–Fisher lobes and mixtures (brume/sampling/vmf.h): chi-square tests of the
// samplers against their densities (single lobes, mixtures, and the product of a mixture with
// a Henyey–Greenstein lobe fitted as a vMF lobe), the product identity, normalisation, and the
// mean cosine and its inverse. Significance 0.01 per test case, Bonferroni-corrected when a
// case runs several parameter sets. Seeds are fixed, so the p-values are reproducible.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "brume/math/frame.h"
#include "brume/sampling/sampler.h"
#include "brume/sampling/vmf.h"
#include "brume/sampling/warp.h"
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
    std::printf("[chi2] %-48s chi2 = %9.2f  dof = %4d  p = %.4f  integral = %.7f  (quadrature warnings %d)\n",
                name.c_str(), r.chi2.chi2, r.chi2.dof, r.chi2.pValue, r.pdfIntegral, r.integrationWarnings);
}

void checkHistogram(const std::string& name, const HistogramResult& r, double alpha) {
    report(name, r);
    INFO(name << "\n" << r.chi2.table);
    CHECK(r.invalid == 0);
    CHECK(r.chi2.pValue > alpha);
    CHECK(r.pdfIntegral == Approx(1.0).epsilon(kIntegralTol));
}

Vec3 unit(Vec3 v) { return normalize(v); }

std::string str(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

// A histogram of sampled directions about `axis` against `pdf`. For a lobe of concentration
// kappa peaked at the axis, the cosθ bins shrink geometrically towards the pole down to
// 1 − cosθ = 0.05/κ (a twentieth of the lobe's width; the last bin holds ~5% of the lobe);
// broad lobes get equal solid-angle bins.
HistogramResult sphereTest(const std::function<Vec3(Sample2)>& sample, const std::function<double(Vec3)>& pdf,
                           Vec3 axis, double kappa, uint64_t seed, long n = kSamples) {
    SphereHistogramOptions opt;
    opt.axis = axis;
    opt.seed = seed;
    int thetaBins = 20;
    if (kappa >= 5) {
        thetaBins = 24;
        opt.cosThetaEdges = peakedCosThetaEdges(thetaBins, std::max(1e-4, 0.05 / kappa));
    }
    return sphereHistogramTest([&](Sample2 u) -> std::optional<Vec3> { return sample(u); }, pdf, thetaBins, 24, n,
                               opt);
}

VmfLobe lobe(Vec3 mu, float kappa) {
    VmfLobe l;
    l.mu = unit(mu);
    l.kappa = kappa;
    return l;
}

struct WeightedLobe {
    float weight;
    VmfLobe lobe;
};

VmfMixture mixture(std::initializer_list<WeightedLobe> lobes) {
    VmfMixture m;
    for (const WeightedLobe& l : lobes) {
        m.weight[m.count] = l.weight;
        m.lobe[m.count] = l.lobe;
        ++m.count;
    }
    return m;
}

// Three lobes of unequal weights and concentrations, none on a coordinate axis.
VmfMixture threeLobes() {
    return mixture({{0.55f, lobe(Vec3(0.3f, 0.5f, 0.8f), 3.0f)},
                    {0.3f, lobe(Vec3(-0.7f, 0.2f, -0.1f), 25.0f)},
                    {0.15f, lobe(Vec3(0.1f, -0.9f, 0.35f), 150.0f)}});
}

// The heaviest lobe of a mixture: the histogram's pole.
int heaviest(const VmfMixture& m) { return int(std::max_element(m.weight, m.weight + m.count) - m.weight); }

// ∫ f over the sphere in (cosθ, φ) about `axis`, cosθ split at edges shrinking towards the pole
// down to 1 − cosθ = minOneMinusCos (for densities peaked at the axis).
double sphereIntegral(const std::function<double(Vec3)>& f, Vec3 axis, double minOneMinusCos) {
    const Frame frame(axis);
    std::vector<double> mu = peakedCosThetaEdges(24, minOneMinusCos);
    double total = 0;
    for (size_t i = 0; i + 1 < mu.size(); ++i)
        total += integrate2D(
            [&](double c, double phi) {
                double s = std::sqrt(std::max(0.0, 1 - c * c));
                return f(frame.toWorld(Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c))));
            },
            mu[i], mu[i + 1], 0, 2 * M_PI, 1e-12, 1e-7);
    return total;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Chi-square tests

TEST_CASE("sampleVmf matches vmfPdf", "[chi2][vmf]") {
    struct Case {
        Vec3 mu;
        float kappa;
        Vec3 axis;  // the histogram's pole
    };
    const Vec3 oblique = unit(Vec3(0.36f, -0.48f, 0.8f));
    const Vec3 other = unit(Vec3(-0.62f, 0.17f, -0.3f));
    const Case cases[] = {
        {Vec3(0, 0, 1), 0.0f, Vec3(0, 0, 1)},  //
        {oblique, 0.5f, oblique},
        {oblique, 5.0f, oblique},
        {oblique, 5.0f, other},  // the lobe seen from a pole elsewhere: the φ bins matter
        {oblique, 50.0f, oblique},
        {Vec3(0, 0, -1), 50.0f, Vec3(0, 0, -1)},  // the other branch of Frame
        {other, 500.0f, other},
    };
    const double alpha = kAlpha / (sizeof cases / sizeof cases[0]);
    int k = 0;
    for (const Case& c : cases) {
        const VmfLobe l = lobe(c.mu, c.kappa);
        const bool atPole = dot(c.axis, l.mu) > 0.999f;
        HistogramResult r = sphereTest([&](Sample2 u) { return sampleVmf(l, u); },
                                       [&](Vec3 w) { return double(vmfPdf(l, w)); }, c.axis, atPole ? c.kappa : 0.0,
                                       101 + k);
        checkHistogram("vMF kappa = " + str(c.kappa) + ", case " + std::to_string(k), r, alpha);
        ++k;
    }
}

TEST_CASE("vmf mixture sampling matches VmfMixture::pdf", "[chi2][vmf]") {
    // Prepared, as the guiding field's mixtures are (the product-identity test below checks
    // that prepare() leaves the density unchanged).
    VmfMixture m = threeLobes();
    m.prepare();
    // One histogram with its pole on each lobe, so that each is resolved by fine bins.
    const double alpha = kAlpha / m.count;
    for (int i = 0; i < m.count; ++i) {
        HistogramResult r = sphereTest([&](Sample2 u) { return m.sample(u); }, [&](Vec3 w) { return double(m.pdf(w)); },
                                       m.lobe[i].mu, m.lobe[i].kappa, 121 + i);
        checkHistogram("3-lobe mixture, pole on lobe " + std::to_string(i), r, alpha);
    }
}

TEST_CASE("vmfProduct of a mixture and an HG lobe samples its density", "[chi2][vmf]") {
    const VmfMixture m = threeLobes();
    const Vec3 d = unit(Vec3(-0.5f, 0.3f, -0.2f));  // near the second lobe: g > 0 sharpens it
    const float gs[] = {0.9f, -0.5f, 0.0f};
    const double alpha = kAlpha / 3;
    int k = 0;
    for (float g : gs) {
        VmfMixture out;
        REQUIRE(vmfProduct(m, hgAsVmf(d, g), &out));
        REQUIRE(out.count == m.count);
        float sum = 0;
        for (int i = 0; i < out.count; ++i) sum += out.weight[i];
        CHECK(sum == Approx(1.0f).epsilon(1e-6));
        const int top = heaviest(out);
        HistogramResult r = sphereTest([&](Sample2 u) { return out.sample(u); },
                                       [&](Vec3 w) { return double(out.pdf(w)); }, out.lobe[top].mu,
                                       out.lobe[top].kappa, 131 + k++);
        checkHistogram("mixture x HG lobe, g = " + str(g), r, alpha);
    }
}

// The tests above reject densities a little off the sampled one.
TEST_CASE("the vmf chi-square tests have power against wrong densities", "[chi2][vmf]") {
    const Vec3 mu = unit(Vec3(0.36f, -0.48f, 0.8f));
    // A lobe of κ = 50 against the density of κ = 52.
    const VmfLobe l = lobe(mu, 50.0f), wrong = lobe(mu, 52.0f);
    HistogramResult r = sphereTest([&](Sample2 u) { return sampleVmf(l, u); },
                                   [&](Vec3 w) { return double(vmfPdf(wrong, w)); }, mu, 50.0, 141);
    report("power: vMF 50 vs pdf 52", r);
    CHECK(r.chi2.pValue < 1e-6);
    // The mixture against one whose weights moved by 0.02.
    const VmfMixture m = threeLobes();
    VmfMixture mw = m;
    mw.weight[0] -= 0.02f;
    mw.weight[2] += 0.02f;
    r = sphereTest([&](Sample2 u) { return m.sample(u); }, [&](Vec3 w) { return double(mw.pdf(w)); }, m.lobe[0].mu,
                   m.lobe[0].kappa, 142);
    report("power: mixture vs weights off by 0.02", r);
    CHECK(r.chi2.pValue < 1e-6);
    // The product's samples against the mixture's own density (the phase factor left out).
    VmfMixture out;
    REQUIRE(vmfProduct(m, hgAsVmf(unit(Vec3(-0.5f, 0.3f, -0.2f)), 0.5f), &out));
    r = sphereTest([&](Sample2 u) { return out.sample(u); }, [&](Vec3 w) { return double(m.pdf(w)); },
                   out.lobe[heaviest(out)].mu, out.lobe[heaviest(out)].kappa, 143);
    report("power: product vs the mixture alone", r);
    CHECK(r.chi2.pValue < 1e-6);
}

// ---------------------------------------------------------------------------------------
// The product identity

TEST_CASE("vmfProduct is the mixture times the lobe up to a constant", "[vmf]") {
    // out.pdf(w) / (m.pdf(w) · vmfPdf(lobe, w)) = 1 / ∫ m·lobe dω, the same for every w.
    const Vec3 a = unit(Vec3(0.2f, 0.9f, -0.3f)), b = unit(Vec3(-0.8f, -0.1f, 0.5f)), c = unit(Vec3(0.1f, -0.4f, -0.9f));
    const VmfMixture mixtures[] = {
        mixture({{0.5f, lobe(a, 200.0f)}, {0.3f, lobe(b, 20.0f)}, {0.2f, lobe(c, 0.5f)}}),
        mixture({{0.7f, lobe(b, 0.0f)}, {0.2f, lobe(c, 1e-5f)}, {0.1f, lobe(a, 60.0f)}}),
        mixture({{1.0f, lobe(c, 120.0f)}}),
    };
    const Vec3 d = unit(Vec3(0.4f, 0.5f, -0.6f));
    // The sixth lobe cancels the first mixture's sharp lobe (κ = 0 exactly), the seventh
    // doubles it (κ = 400).
    const VmfLobe lobes[] = {lobe(d, 0.0f),    lobe(d, 0.5f),
                             lobe(d, 5.0f),    lobe(d, 50.0f),
                             lobe(d, 200.0f),  VmfLobe{-mixtures[0].lobe[0].mu, 200.0f},
                             lobe(a, 200.0f),  hgAsVmf(d, 0.9f),
                             hgAsVmf(d, -0.5f)};
    Rng rng(17, 3);
    int mi = 0;
    for (const VmfMixture& m : mixtures) {
        VmfMixture prepared = m;
        prepared.prepare();
        int li = 0;
        for (const VmfLobe& l : lobes) {
            VmfMixture out, fromPrepared;
            REQUIRE(vmfProduct(m, l, &out));
            // The product of the prepared mixture is the same.
            REQUIRE(vmfProduct(prepared, l, &fromPrepared));
            REQUIRE(fromPrepared.count == out.count);
            for (int i = 0; i < out.count; ++i) {
                INFO("mixture " << mi << ", lobe " << li << ", product lobe " << i);
                CHECK(fromPrepared.weight[i] == Approx(out.weight[i]).epsilon(1e-5).margin(1e-30));
                CHECK(fromPrepared.lobe[i].kappa == out.lobe[i].kappa);
            }
            // Directions uniform on the sphere and from the product itself (which finds its
            // peaks); those where a factor underflows float are skipped.
            double lo = 1e300, hi = -1e300, sum = 0, worstPrepared = 0;
            int used = 0;
            for (int i = 0; i < 4000; ++i) {
                const Vec3 w = i % 2 ? sampleUniformSphere(rng.next2D()) : out.sample(rng.next2D());
                const double pm = m.pdf(w), pl = vmfPdf(l, w), po = out.pdf(w);
                // prepare() changes how the density is evaluated, not its value.
                if (pm > 1e-30) worstPrepared = std::max(worstPrepared, std::abs(prepared.pdf(w) - pm) / pm);
                if (pm < 1e-30 || pl < 1e-30 || po < 1e-30) continue;
                const double ratio = po / (pm * pl);
                lo = std::min(lo, ratio);
                hi = std::max(hi, ratio);
                sum += ratio;
                ++used;
            }
            // The constant is 1 / ∫ m·lobe dω = 1 / Σ w_i C(κ_i) C(κ) / C(|κ_i μ_i + κ μ|), here in
            // double precision.
            double integral = 0;
            for (int i = 0; i < m.count; ++i) {
                const Vec3 mi3 = m.lobe[i].mu, l3 = l.mu;
                const double vx = double(m.lobe[i].kappa) * mi3.x + double(l.kappa) * l3.x,
                             vy = double(m.lobe[i].kappa) * mi3.y + double(l.kappa) * l3.y,
                             vz = double(m.lobe[i].kappa) * mi3.z + double(l.kappa) * l3.z;
                integral += m.weight[i] * std::exp(vmfLogNorm(m.lobe[i].kappa) + vmfLogNorm(l.kappa) -
                                                   vmfLogNorm(std::sqrt(vx * vx + vy * vy + vz * vz)));
            }
            INFO("mixture " << mi << ", lobe " << li << " (kappa " << l.kappa << "): " << used << " directions, ratio in ["
                            << lo << ", " << hi << "], expected " << 1 / integral);
            REQUIRE(used >= 1000);
            CHECK((hi - lo) / (sum / used) < 1e-3);
            CHECK(sum / used == Approx(1 / integral).epsilon(1e-3));
            CHECK(worstPrepared < 1e-4);  // the prepared mixture's density, relative to the unprepared one
            ++li;
        }
        ++mi;
    }
    // A product multiplied again: (m·a)·b is m·a·b, renormalised.
    {
        const VmfMixture& m = mixtures[0];
        const VmfLobe la = lobe(d, 30.0f), lb = hgAsVmf(unit(Vec3(0.9f, 0.1f, 0.3f)), 0.7f);
        VmfMixture ma, mab;
        REQUIRE(vmfProduct(m, la, &ma));
        REQUIRE(vmfProduct(ma, lb, &mab));
        double lo = 1e300, hi = -1e300, sum = 0;
        int used = 0;
        for (int i = 0; i < 4000; ++i) {
            const Vec3 w = i % 2 ? sampleUniformSphere(rng.next2D()) : mab.sample(rng.next2D());
            const double pm = m.pdf(w), pa = vmfPdf(la, w), pb = vmfPdf(lb, w), po = mab.pdf(w);
            if (pm < 1e-30 || pa < 1e-30 || pb < 1e-30 || po < 1e-30) continue;
            const double ratio = po / (pm * pa * pb);
            lo = std::min(lo, ratio);
            hi = std::max(hi, ratio);
            sum += ratio;
            ++used;
        }
        INFO("(m a) b: " << used << " directions, ratio in [" << lo << ", " << hi << "]");
        REQUIRE(used >= 1000);
        CHECK((hi - lo) / (sum / used) < 1e-3);
    }
    // With no weight anywhere there is no product.
    VmfMixture none = mixture({{0.0f, lobe(a, 5.0f)}});
    VmfMixture out;
    CHECK_FALSE(vmfProduct(none, lobe(d, 5.0f), &out));
}

// ---------------------------------------------------------------------------------------
// Normalisation, mean cosine

TEST_CASE("vmfPdf integrates to one over the sphere", "[vmf]") {
    const Vec3 mu = unit(Vec3(-0.3f, 0.64f, 0.7f));
    for (float kappa : {0.0f, 1e-5f, 0.3f, 10.0f, 1000.0f}) {
        const VmfLobe l = lobe(mu, kappa);
        // About the lobe's axis, bins shrinking towards it down to a thousandth of its width.
        double total = sphereIntegral([&](Vec3 w) { return double(vmfPdf(l, w)); }, mu,
                                      std::min(1e-2, 1e-3 / std::max(1.0, double(kappa))));
        int warnings = takeIntegrationBudgetWarnings();
        INFO("kappa = " << kappa << ": integral = " << total << " (quadrature warnings " << warnings << ")");
        // 1e-4 forgives the float rounding of μ·w near the peak (κ = 1000 integrates to 1 + 2e-5).
        CHECK(total == Approx(1.0).epsilon(1e-4));
    }
}

TEST_CASE("vmfKappaForMeanCosine inverts vmfMeanCosine and hgAsVmf keeps g", "[vmf]") {
    for (float k : {0.01f, 0.5f, 2.0f, 20.0f, 200.0f}) {
        const float r = vmfMeanCosine(k);
        // The mean cosine is ∫ cosθ vMF dω, by quadrature of vmfPdf about the z axis.
        const VmfLobe l = lobe(Vec3(0, 0, 1), k);
        const double mean = integrate1D(
            [&](double c) {
                const double s = std::sqrt(std::max(0.0, 1 - c * c));
                return 2 * M_PI * c * double(vmfPdf(l, Vec3(float(s), 0.0f, float(c))));
            },
            -1, 1, 1e-13, 1e-9, 64);
        INFO("kappa = " << k << ": mean cosine " << r << ", by quadrature " << mean << ", inverse "
                        << vmfKappaForMeanCosine(r));
        CHECK(r == Approx(mean).epsilon(1e-5));
        CHECK(vmfKappaForMeanCosine(r) == Approx(k).epsilon(1e-3));
    }
    CHECK(vmfMeanCosine(0.0f) == 0.0f);
    CHECK(vmfKappaForMeanCosine(0.0f) == 0.0f);
    // The HG lobe has the mean cosine |g| about d (g ≥ 0) or −d (g < 0).
    const Vec3 d = unit(Vec3(0.2f, -0.7f, 0.4f));
    for (float g : {0.1f, 0.5f, 0.9f}) {
        const VmfLobe fwd = hgAsVmf(d, g), back = hgAsVmf(d, -g);
        INFO("g = " << g << ": kappa " << fwd.kappa);
        CHECK(vmfMeanCosine(fwd.kappa) == Approx(g).epsilon(1e-3));
        CHECK(back.kappa == fwd.kappa);
        CHECK(fwd.kappa == vmfKappaForMeanCosine(g));  // (hgAsVmf keeps the last κ: never a stale one)
        CHECK(dot(fwd.mu, d) == Approx(1.0f));
        CHECK(dot(back.mu, d) == Approx(-1.0f));
    }
    CHECK(hgAsVmf(d, 0.0f).kappa == 0.0f);
}
