// Shared helpers for the tests: the chi-square distribution, Pearson's chi-square test with
// pooling of sparse bins, histogram tests of sampling routines against their densities
// (directions on the sphere, points in a rectangle, values on an interval), and running
// statistics for Monte Carlo oracle tests.
//
// The histogram tests draw their random numbers from brume::Sampler with a fixed seed, so a
// test gives the same p-value on every run. Expected counts come from integrating the
// density over each bin with nested adaptive Simpson quadrature, accurate to a tolerance far
// below the counting noise; the integral of the density over the whole domain is returned
// as well, so a test can check that the density is normalised.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume::test {

// ---------------------------------------------------------------------------------------
// Chi-square distribution

// Regularised lower and upper incomplete gamma functions P(a, x) and Q(a, x) = 1 − P(a, x),
// for a > 0, x ≥ 0 (series for x < a + 1, Lentz's continued fraction otherwise; double
// precision, relative accuracy ~1e-14).
double gammaP(double a, double x);
double gammaQ(double a, double x);

// Probability that a chi-square variable with `dof` degrees of freedom exceeds chi2.
// dof ≤ 0 gives 1 (nothing was tested); chi2 = +∞ or NaN gives 0.
double chiSquarePValue(double chi2, int dof);

// Pearson correlation of the n pairs pair(0) … pair(n − 1) (each a std::pair of numbers);
// independent uniforms give |r| ~ 1/√n.
template <class Pair>
double pearsonCorrelation(int n, Pair pair) {
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int i = 0; i < n; ++i) {
        auto [x, y] = pair(i);
        sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
    }
    double cov = sxy / n - sx / n * sy / n;
    return cov / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
}

// ---------------------------------------------------------------------------------------
// Pearson's chi-square test

struct ChiSquareResult {
    double chi2 = 0;
    int dof = 0;
    double pValue = 1;
    std::string table;  // human-readable summary and the worst bins, for failure messages
};

// Compares observed counts with expected counts (same length; the expected total should
// equal the observed total). Walking the bins in order, adjacent bins are pooled until the
// pooled expected count reaches minExpected; a trailing group still below it joins the
// previous group. A bin whose expected count is 0 but which has observations fails the test
// outright (chi2 = +∞, p = 0): the sampler produced something its density says is
// impossible. binLabel, if given, names bin i in the table.
ChiSquareResult chiSquareTest(const std::vector<double>& observed, const std::vector<double>& expected,
                              double minExpected = 5.0,
                              const std::function<std::string(int)>& binLabel = nullptr);

// ---------------------------------------------------------------------------------------
// Numerical integration

// ∫_a^b f(x) dx by globally adaptive Simpson quadrature (with Richardson correction): the
// piece with the largest error estimate is bisected until the summed estimate is below
// max(absTol, relTol·|integral|) or maxEvals evaluations are spent. The interval is first
// cut into `initialPieces`, so that narrow features are not stepped over. Jumps in f cost a
// couple of evaluations per halving of the piece that holds them; noise in f (a density
// computed in single precision) only exhausts the budget, it cannot make the cost explode.
double integrate1D(const std::function<double(double)>& f, double a, double b, double absTol = 1e-12,
                   double relTol = 1e-6, int initialPieces = 4, long maxEvals = 100000);

// ∫∫ f(x, y) over [x0, x1] × [y0, y1], nested adaptive Simpson (inner integral over y, run
// ten times tighter than the outer one), each starting from initialPieces pieces (a grid of
// (2·initialPieces + 1)² points); budgets of 1000 inner and 200 outer evaluations plus 8 per
// initial piece.
double integrate2D(const std::function<double(double, double)>& f, double x0, double x1, double y0, double y1,
                   double absTol = 1e-10, double relTol = 1e-5, int initialPieces = 8);

// Number of 1D integrals that stopped on their evaluation budget before meeting their
// tolerance since the last call (a sign of a noisy or discontinuous integrand: harmless when
// the noise averages out, worth a look otherwise); the count is reset.
int takeIntegrationBudgetWarnings();

// Uniformly spaced edges: n + 1 values from lo to hi.
std::vector<double> uniformEdges(int n, double lo, double hi);

// n bins of cosθ for lobes peaked at the pole: edges lo, then 1 − cosθ falling geometrically
// from (1 − lo)·r down to minOneMinusCos, then 1 (so the last bin is [1 − minOneMinusCos, 1]).
std::vector<double> peakedCosThetaEdges(int n, double minOneMinusCos, double lo = -1.0);

// ---------------------------------------------------------------------------------------
// Histogram tests of sampling routines

struct HistogramOptions {
    uint64_t seed = 1;
    double minExpected = 5.0;
    // Samples that fail (nullopt) or land outside the histogram's domain are counted in one
    // extra "outside" bin whose expected probability is outsideProbability (0: any such
    // sample fails the test).
    double outsideProbability = 0.0;
    // Absolute tolerance, in probability, of the integral of the density over each bin.
    double integrationTolerance = 1e-10;
    // Relative tolerance of the same integrals (kept above the noise of float densities).
    double integrationRelTolerance = 1e-5;
};

struct HistogramResult {
    ChiSquareResult chi2;
    double pdfIntegral = 0;    // ∫ pdf over the histogram's domain
    long outside = 0;          // samples that failed or fell outside the domain
    long invalid = 0;          // NaN samples, or non-unit directions (also counted in `outside`)
    int integrationWarnings = 0;  // 1D quadratures that ran out of budget (see above)
    std::vector<double> observed, expected;  // per bin; the "outside" bin is last
};

// Points (x, y) in [x edges] × [y edges] (increasing edge lists); pdf is the density per unit
// of x·y. Bins are ordered row-major (x outer, y inner) for pooling. Each bin's probability
// is integrate2D from a 17 × 17 grid; bins where the density was seen to be both zero and
// non-zero (an edge of its support: a sliver of support may lie between grid points), or
// where none was found but samples landed, are integrated again from a 65 × 65 grid in both
// nesting orders, keeping the larger value (quadrature of a non-negative function can miss
// mass but not invent it).
HistogramResult histogram2DTest(const std::function<std::optional<std::pair<double, double>>(Sample2)>& sampleFn,
                                const std::function<double(double, double)>& pdfFn, const std::vector<double>& xEdges,
                                const std::vector<double>& yEdges, long nSamples, const HistogramOptions& options = {});

// Directions: sampleFn returns a unit vector (or nullopt when sampling fails), pdfFn the
// density per steradian. The histogram has thetaBins × phiBins bins in (cosθ, φ) around
// `axis` (equal solid angle per bin when the cosθ edges are uniform). cosThetaEdges, if not
// empty, replaces the uniform cosθ edges (it must hold thetaBins + 1 increasing values from
// −1 to 1). A sample more than 1e-4 away from unit length counts as invalid.
struct SphereHistogramOptions : HistogramOptions {
    Vec3 axis{0, 0, 1};
    std::vector<double> cosThetaEdges;
};
HistogramResult sphereHistogramTest(const std::function<std::optional<Vec3>(Sample2)>& sampleFn,
                                    const std::function<double(Vec3)>& pdfFn, int thetaBins, int phiBins,
                                    long nSamples, const SphereHistogramOptions& options = {});

// Values on [a, b] with density pdfFn; samples outside [a, b], infinite ones and failures go
// to the "outside" bin (see HistogramOptions::outsideProbability).
HistogramResult intervalHistogramTest(const std::function<std::optional<double>(Sample2)>& sampleFn,
                                      const std::function<double(double)>& pdfFn, double a, double b, int bins,
                                      long nSamples, const HistogramOptions& options = {});
// The same with explicit, increasing bin edges (for peaked densities); [a, b] is
// [edges.front(), edges.back()].
HistogramResult intervalHistogramTest(const std::function<std::optional<double>(Sample2)>& sampleFn,
                                      const std::function<double(double)>& pdfFn, const std::vector<double>& edges,
                                      long nSamples, const HistogramOptions& options = {});

// ---------------------------------------------------------------------------------------
// Monte Carlo estimates

// Streaming mean and variance (Welford).
class RunningStats {
public:
    void add(double x) {
        ++n_;
        double d = x - mean_;
        mean_ += d / double(n_);
        m2_ += d * (x - mean_);
    }
    long count() const { return n_; }
    double mean() const { return mean_; }
    // Unbiased sample variance.
    double variance() const { return n_ > 1 ? m2_ / double(n_ - 1) : 0.0; }
    // Standard error of the mean.
    double standardError() const;

private:
    long n_ = 0;
    double mean_ = 0, m2_ = 0;
};

// (estimate − reference) / standardError; ±∞ if standardError is 0 and the two differ, 0 if they agree.
double zScore(double estimate, double reference, double standardError);

}  // namespace brume::test
