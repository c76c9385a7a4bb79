#include "support/test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace brume::test {

// ---------------------------------------------------------------------------------------
// Incomplete gamma function

namespace {

constexpr double kGammaEps = 1e-15;
constexpr int kGammaMaxIter = 100000;

// P(a, x) by its power series, for x < a + 1:
//   P = e^{−x} x^a / Γ(a) · Σ_{n≥0} x^n / (a (a+1) ... (a+n)).
double gammaSeriesP(double a, double x) {
    double term = 1.0 / a, sum = term, ap = a;
    for (int n = 0; n < kGammaMaxIter; ++n) {
        ap += 1.0;
        term *= x / ap;
        sum += term;
        if (std::abs(term) < std::abs(sum) * kGammaEps) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by the continued fraction
//   Q = e^{−x} x^a / Γ(a) · 1/(x+1−a− 1·(1−a)/(x+3−a− 2·(2−a)/(x+5−a− ...))),
// evaluated with the modified Lentz method, for x ≥ a + 1.
double gammaContinuedFractionQ(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1.0 - a;
    double c = 1.0 / tiny;
    double d = 1.0 / b;
    double h = d;
    for (int i = 1; i < kGammaMaxIter; ++i) {
        double an = -double(i) * (double(i) - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < kGammaEps) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double gammaP(double a, double x) {
    if (!(a > 0) || !(x >= 0)) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0) return 0.0;
    if (std::isinf(x)) return 1.0;
    return x < a + 1.0 ? gammaSeriesP(a, x) : 1.0 - gammaContinuedFractionQ(a, x);
}

double gammaQ(double a, double x) {
    if (!(a > 0) || !(x >= 0)) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0) return 1.0;
    if (std::isinf(x)) return 0.0;
    return x < a + 1.0 ? 1.0 - gammaSeriesP(a, x) : gammaContinuedFractionQ(a, x);
}

double chiSquarePValue(double chi2, int dof) {
    if (dof <= 0) return 1.0;
    if (std::isnan(chi2) || std::isinf(chi2)) return 0.0;
    if (chi2 <= 0) return 1.0;
    return gammaQ(0.5 * dof, 0.5 * chi2);
}

// ---------------------------------------------------------------------------------------
// Chi-square test

namespace {

std::string formatDouble(double v, int precision = 6) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    return buf;
}

std::string defaultLabel(int i) { return "bin " + std::to_string(i); }

}  // namespace

ChiSquareResult chiSquareTest(const std::vector<double>& observed, const std::vector<double>& expected,
                              double minExpected, const std::function<std::string(int)>& binLabel) {
    if (observed.size() != expected.size()) throw std::invalid_argument("chiSquareTest: size mismatch");
    auto label = [&](int i) { return binLabel ? binLabel(i) : defaultLabel(i); };
    const int n = int(observed.size());

    struct Group {
        int first, last;
        double obs, exp;
    };
    std::vector<Group> groups;
    std::vector<int> impossible;  // bins with expected 0 but observations
    double totalObs = 0, totalExp = 0;
    Group open{-1, -1, 0, 0};
    for (int i = 0; i < n; ++i) {
        totalObs += observed[i];
        totalExp += expected[i];
        if (!(expected[i] > 0)) {
            if (observed[i] > 0) impossible.push_back(i);
            continue;  // contributes nothing when empty
        }
        if (open.first < 0) open.first = i;
        open.last = i;
        open.obs += observed[i];
        open.exp += expected[i];
        if (open.exp >= minExpected) {
            groups.push_back(open);
            open = Group{-1, -1, 0, 0};
        }
    }
    if (open.first >= 0) {
        if (groups.empty()) {
            groups.push_back(open);
        } else {
            Group& g = groups.back();
            g.last = open.last;
            g.obs += open.obs;
            g.exp += open.exp;
        }
    }

    ChiSquareResult r;
    std::vector<double> contribution(groups.size());
    for (size_t k = 0; k < groups.size(); ++k) {
        double diff = groups[k].obs - groups[k].exp;
        contribution[k] = diff * diff / groups[k].exp;
        r.chi2 += contribution[k];
    }
    r.dof = int(groups.size()) - 1;
    if (!impossible.empty()) {
        r.chi2 = std::numeric_limits<double>::infinity();
        r.pValue = 0.0;
    } else {
        r.pValue = chiSquarePValue(r.chi2, r.dof);
    }

    std::ostringstream t;
    t << "chi2 = " << formatDouble(r.chi2) << ", dof = " << r.dof << ", p = " << formatDouble(r.pValue, 4) << "  ("
      << n << " bins pooled into " << groups.size() << " groups of expected count >= " << minExpected
      << "; observed total " << formatDouble(totalObs, 10) << ", expected total " << formatDouble(totalExp, 10)
      << ")\n";
    if (!impossible.empty()) {
        t << "samples in bins whose expected count is 0:\n";
        for (size_t k = 0; k < impossible.size() && k < 20; ++k)
            t << "  " << label(impossible[k]) << ": observed " << formatDouble(observed[impossible[k]], 10) << "\n";
        if (impossible.size() > 20) t << "  ... and " << impossible.size() - 20 << " more\n";
    }
    // The groups that contribute most, listed in bin order.
    const size_t kShow = 30;
    std::vector<size_t> order(groups.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return contribution[a] > contribution[b]; });
    if (order.size() > kShow) order.resize(kShow);
    std::sort(order.begin(), order.end());
    if (!order.empty()) {
        t << (groups.size() > kShow ? "largest contributions" : "all groups") << " (bins: observed / expected -> (O-E)^2/E):\n";
        for (size_t k : order) {
            const Group& g = groups[k];
            t << "  " << label(g.first);
            if (g.last != g.first) t << " .. " << label(g.last);
            t << ": " << formatDouble(g.obs, 10) << " / " << formatDouble(g.exp, 8) << " -> "
              << formatDouble(contribution[k], 4) << "\n";
        }
    }
    r.table = t.str();
    return r;
}

// ---------------------------------------------------------------------------------------
// Quadrature

namespace {

int gBudgetWarnings = 0;

// Globally adaptive Simpson quadrature: the piece with the largest error estimate is
// bisected until the summed estimate meets the tolerance or the evaluation budget is spent.
// Unlike recursive adaptive Simpson, noise in f (single-precision densities) cannot make the
// cost explode: the budget is spread over the pieces that need it most, and jumps (which
// have one large-error piece per level) are still resolved cheaply.
struct Piece {
    double a, b;
    double fa, flm, fm, frm, fb;
    double whole, left, right;
    double err() const { return std::abs(left + right - whole); }
    double value() const { return left + right + (left + right - whole) / 15.0; }
    bool operator<(const Piece& o) const { return err() < o.err(); }
};

Piece makePiece(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb,
                double whole, long* evals) {
    double m = 0.5 * (a + b);
    double flm = f(0.5 * (a + m)), frm = f(0.5 * (m + b));
    *evals += 2;
    double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    return Piece{a, b, fa, flm, fm, frm, fb, whole, left, right};
}

}  // namespace

double integrate1D(const std::function<double(double)>& f, double a, double b, double absTol, double relTol,
                   int initialPieces, long maxEvals) {
    if (!(b > a)) return 0.0;
    initialPieces = std::max(1, initialPieces);
    long evals = 0;
    std::vector<Piece> heap;
    double x0 = a, f0 = f(a);
    ++evals;
    for (int i = 1; i <= initialPieces; ++i) {
        double x1 = i == initialPieces ? b : a + (b - a) * double(i) / initialPieces;
        double fm = f(0.5 * (x0 + x1)), f1 = f(x1);
        evals += 2;
        double whole = (x1 - x0) / 6.0 * (f0 + 4.0 * fm + f1);
        heap.push_back(makePiece(f, x0, x1, f0, fm, f1, whole, &evals));
        x0 = x1;
        f0 = f1;
    }
    std::make_heap(heap.begin(), heap.end());
    double finished = 0;        // pieces too narrow to split
    double total = 0, err = 0;  // running sums: values (heap + finished) and error estimates
    for (const Piece& p : heap) {
        total += p.value();
        err += p.err();
    }
    const double minWidth = (b - a) * 1e-13;
    for (int iter = 1;; ++iter) {
        if (iter % 256 == 0) {  // refresh the running sums against drift
            double t = 0, e = 0;
            for (const Piece& p : heap) {
                t += p.value();
                e += p.err();
            }
            total = finished + t;
            err = e;
        }
        if (heap.empty() || err <= std::max(absTol, relTol * std::abs(total))) return total;
        if (evals >= maxEvals) {
            ++gBudgetWarnings;
            return total;
        }
        std::pop_heap(heap.begin(), heap.end());
        Piece p = heap.back();
        heap.pop_back();
        err -= p.err();
        double m = 0.5 * (p.a + p.b);
        if (m - p.a < minWidth) {  // its value stays in total; its error is dropped
            finished += p.value();
            continue;
        }
        total -= p.value();
        Piece l = makePiece(f, p.a, m, p.fa, p.flm, p.fm, p.left, &evals);
        Piece r = makePiece(f, m, p.b, p.fm, p.frm, p.fb, p.right, &evals);
        total += l.value() + r.value();
        err += l.err() + r.err();
        heap.push_back(l);
        std::push_heap(heap.begin(), heap.end());
        heap.push_back(r);
        std::push_heap(heap.begin(), heap.end());
    }
}

double integrate2D(const std::function<double(double, double)>& f, double x0, double x1, double y0, double y1,
                   double absTol, double relTol, int initialPieces) {
    if (!(x1 > x0) || !(y1 > y0)) return 0.0;
    double innerAbs = 0.1 * absTol / (x1 - x0);
    double innerRel = 0.1 * relTol;
    // The budgets grow with the initial grid, so that a finer start does not starve the
    // refinement.
    long innerBudget = 1000 + 8L * initialPieces, outerBudget = 200 + 8L * initialPieces;
    auto inner = [&](double x) {
        return integrate1D([&](double y) { return f(x, y); }, y0, y1, innerAbs, innerRel, initialPieces, innerBudget);
    };
    return integrate1D(inner, x0, x1, absTol, relTol, initialPieces, outerBudget);
}

int takeIntegrationBudgetWarnings() {
    int w = gBudgetWarnings;
    gBudgetWarnings = 0;
    return w;
}

std::vector<double> uniformEdges(int n, double lo, double hi) {
    std::vector<double> e(size_t(n) + 1);
    for (int i = 0; i <= n; ++i) e[i] = i == n ? hi : lo + (hi - lo) * double(i) / n;
    return e;
}

std::vector<double> peakedCosThetaEdges(int n, double minOneMinusCos, double lo) {
    if (n < 2) return {lo, 1.0};
    std::vector<double> e(size_t(n) + 1);
    e[0] = lo;
    e[n] = 1.0;
    // 1 − e[k] = (1 − lo)·r^k for k = 1 .. n−1, with (1 − lo)·r^{n−1} = minOneMinusCos.
    double span = 1.0 - lo;
    double r = std::pow(minOneMinusCos / span, 1.0 / double(n - 1));
    for (int k = 1; k < n; ++k) e[k] = 1.0 - span * std::pow(r, double(k));
    return e;
}

// ---------------------------------------------------------------------------------------
// Histogram tests

namespace {

// Bin of v among increasing edges; the top edge belongs to the last bin; -1 outside.
constexpr int kInitialPieces = 8;
constexpr int kRefinedPieces = 32;

int findBin(const std::vector<double>& edges, double v) {
    if (!(v >= edges.front()) || !(v <= edges.back())) return -1;
    int i = int(std::upper_bound(edges.begin(), edges.end(), v) - edges.begin()) - 1;
    return std::min(i, int(edges.size()) - 2);
}

std::string rangeLabel(const char* name, const std::vector<double>& e, int i) {
    return std::string(name) + "[" + formatDouble(e[i], 7) + ", " + formatDouble(e[i + 1], 7) + "]";
}

// Appends the "outside" bin, runs the test.
HistogramResult finish(std::vector<double> observed, std::vector<double> expected, long outside, long invalid,
                       double pdfIntegral, long nSamples, const HistogramOptions& options,
                       const std::function<std::string(int)>& label) {
    HistogramResult r;
    int nBins = int(observed.size());
    observed.push_back(double(outside));
    expected.push_back(double(nSamples) * options.outsideProbability);
    auto fullLabel = [&](int i) { return i == nBins ? std::string("outside/failed") : label(i); };
    r.chi2 = chiSquareTest(observed, expected, options.minExpected, fullLabel);
    r.pdfIntegral = pdfIntegral;
    r.outside = outside;
    r.invalid = invalid;
    r.integrationWarnings = takeIntegrationBudgetWarnings();
    std::ostringstream extra;
    extra << "pdf integral = " << formatDouble(pdfIntegral, 10) << ", outside/failed samples = " << outside
          << " (expected " << formatDouble(double(nSamples) * options.outsideProbability, 8) << ")"
          << ", invalid samples = " << invalid << ", quadrature budget warnings = " << r.integrationWarnings << "\n";
    r.chi2.table = extra.str() + r.chi2.table;
    r.observed = std::move(observed);
    r.expected = std::move(expected);
    return r;
}

// Probability of bin (i, j) of a grid, and whether the density was seen to be both zero and
// non-zero there (part of the bin lies outside its support).
double binIntegral(const std::function<double(double, double)>& pdf, const std::vector<double>& xe,
                   const std::vector<double>& ye, int i, int j, const HistogramOptions& o, int initialPieces,
                   bool* mixed) {
    bool zero = false, nonzero = false;
    auto f = [&](double x, double y) {
        double v = pdf(x, y);
        (v != 0 ? nonzero : zero) = true;
        return v;
    };
    double p = integrate2D(f, xe[i], xe[i + 1], ye[j], ye[j + 1], o.integrationTolerance, o.integrationRelTolerance,
                           initialPieces);
    if (mixed) *mixed = zero && nonzero;
    return p;
}

// The same with x as the inner variable.
double binIntegralSwapped(const std::function<double(double, double)>& pdf, const std::vector<double>& xe,
                          const std::vector<double>& ye, int i, int j, const HistogramOptions& o, int initialPieces) {
    return integrate2D([&](double y, double x) { return pdf(x, y); }, ye[j], ye[j + 1], xe[i], xe[i + 1],
                       o.integrationTolerance, o.integrationRelTolerance, initialPieces);
}

void checkEdges(const std::vector<double>& e, const char* what) {
    if (e.size() < 2) throw std::invalid_argument(std::string(what) + ": need at least two edges");
    for (size_t i = 1; i < e.size(); ++i)
        if (!(e[i] > e[i - 1])) throw std::invalid_argument(std::string(what) + ": edges must increase");
}

// An orthonormal basis around a unit axis, in double precision, independent of brume::Frame.
struct Basis {
    double s[3], t[3], n[3];
    explicit Basis(Vec3 axis) {
        double a[3] = {axis.x, axis.y, axis.z};
        double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (double& c : a) c /= len;
        // Helper vector: the world axis least aligned with n.
        int k = 0;
        for (int i = 1; i < 3; ++i)
            if (std::abs(a[i]) < std::abs(a[k])) k = i;
        double h[3] = {0, 0, 0};
        h[k] = 1;
        double d = h[0] * a[0] + h[1] * a[1] + h[2] * a[2];
        double sv[3] = {h[0] - d * a[0], h[1] - d * a[1], h[2] - d * a[2]};
        double sl = std::sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]);
        for (int i = 0; i < 3; ++i) {
            n[i] = a[i];
            s[i] = sv[i] / sl;
        }
        t[0] = n[1] * s[2] - n[2] * s[1];
        t[1] = n[2] * s[0] - n[0] * s[2];
        t[2] = n[0] * s[1] - n[1] * s[0];
    }
    Vec3 toWorld(double x, double y, double z) const {
        return Vec3(float(x * s[0] + y * t[0] + z * n[0]), float(x * s[1] + y * t[1] + z * n[1]),
                    float(x * s[2] + y * t[2] + z * n[2]));
    }
};

}  // namespace

namespace {

HistogramResult histogram2D(const std::function<std::optional<std::pair<double, double>>(Sample2)>& sampleFn,
                            const std::function<double(double, double)>& pdfFn, const std::vector<double>& xEdges,
                            const std::vector<double>& yEdges, long nSamples, const HistogramOptions& options,
                            const char* xName, const char* yName) {
    checkEdges(xEdges, "histogram2DTest x");
    checkEdges(yEdges, "histogram2DTest y");
    int nx = int(xEdges.size()) - 1, ny = int(yEdges.size()) - 1;
    takeIntegrationBudgetWarnings();

    std::vector<double> observed(size_t(nx) * ny, 0.0);
    long outside = 0, invalid = 0;
    Sampler sampler(options.seed, 0, 0);
    for (long k = 0; k < nSamples; ++k) {
        std::optional<std::pair<double, double>> s = sampleFn(sampler.next2D());
        if (!s) {
            ++outside;
            continue;
        }
        if (std::isnan(s->first) || std::isnan(s->second)) {
            ++invalid;
            ++outside;
            continue;
        }
        int i = findBin(xEdges, s->first), j = findBin(yEdges, s->second);
        if (i < 0 || j < 0) {
            ++outside;
            continue;
        }
        observed[size_t(i) * ny + j] += 1;
    }

    // Quadrature starts on a 17 × 17 grid per bin. Where the density has an edge (a bin partly
    // outside its support) a sliver of support can fall between the grid points; quadrature
    // can only miss density, never invent it (the pdf is non-negative), so such bins, and bins
    // where no density was found but samples landed, are integrated again from a 65 × 65 grid
    // in both nesting orders and the larger result is kept.
    std::vector<double> expected(observed.size());
    double integral = 0;
    int refined = 0;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) {
            size_t b = size_t(i) * ny + j;
            bool mixed = false;
            double p = binIntegral(pdfFn, xEdges, yEdges, i, j, options, kInitialPieces, &mixed);
            if (mixed || (p == 0 && observed[b] > 0)) {
                p = std::max(p, binIntegral(pdfFn, xEdges, yEdges, i, j, options, kRefinedPieces, nullptr));
                p = std::max(p, binIntegralSwapped(pdfFn, xEdges, yEdges, i, j, options, kRefinedPieces));
                ++refined;
            }
            integral += p;
            expected[b] = p * double(nSamples);
        }
    auto label = [&](int b) { return rangeLabel(xName, xEdges, b / ny) + " " + rangeLabel(yName, yEdges, b % ny); };
    HistogramResult r =
        finish(std::move(observed), std::move(expected), outside, invalid, integral, nSamples, options, label);
    if (refined > 0)
        r.chi2.table = std::to_string(refined) + " bin(s) at edges of the support were integrated again on a finer "
                       "grid\n" + r.chi2.table;
    return r;
}

}  // namespace

HistogramResult histogram2DTest(const std::function<std::optional<std::pair<double, double>>(Sample2)>& sampleFn,
                                const std::function<double(double, double)>& pdfFn, const std::vector<double>& xEdges,
                                const std::vector<double>& yEdges, long nSamples, const HistogramOptions& options) {
    return histogram2D(sampleFn, pdfFn, xEdges, yEdges, nSamples, options, "x", "y");
}

HistogramResult sphereHistogramTest(const std::function<std::optional<Vec3>(Sample2)>& sampleFn,
                                    const std::function<double(Vec3)>& pdfFn, int thetaBins, int phiBins,
                                    long nSamples, const SphereHistogramOptions& options) {
    std::vector<double> cosEdges = options.cosThetaEdges;
    if (cosEdges.empty()) cosEdges = uniformEdges(thetaBins, -1.0, 1.0);
    if (int(cosEdges.size()) != thetaBins + 1 || cosEdges.front() != -1.0 || cosEdges.back() != 1.0)
        throw std::invalid_argument("sphereHistogramTest: cosThetaEdges must hold thetaBins + 1 values from -1 to 1");
    checkEdges(cosEdges, "sphereHistogramTest cosθ");
    const double twoPi = 2.0 * 3.14159265358979323846;
    std::vector<double> phiEdges = uniformEdges(phiBins, 0.0, twoPi);
    const Basis basis(options.axis);

    // Directions → (cosθ, φ) about the axis, in double precision.
    auto toLocal = [&](Vec3 w, double* len) {
        double x = w.x * basis.s[0] + w.y * basis.s[1] + w.z * basis.s[2];
        double y = w.x * basis.t[0] + w.y * basis.t[1] + w.z * basis.t[2];
        double z = w.x * basis.n[0] + w.y * basis.n[1] + w.z * basis.n[2];
        *len = std::sqrt(x * x + y * y + z * z);
        double cosTheta = std::clamp(z / *len, -1.0, 1.0);
        double phi = std::atan2(y, x);
        if (phi < 0) phi += twoPi;
        if (phi >= twoPi) phi = 0;
        return std::make_pair(cosTheta, phi);
    };
    auto sample2 = [&](Sample2 u) -> std::optional<std::pair<double, double>> {
        std::optional<Vec3> w = sampleFn(u);
        if (!w) return std::nullopt;
        if (!isFinite(*w)) return std::make_pair(std::nan(""), 0.0);
        double len;
        auto local = toLocal(*w, &len);
        if (!(std::abs(len - 1.0) <= 1e-4)) return std::make_pair(std::nan(""), 0.0);
        return local;
    };
    // Density per unit of cosθ·φ equals the density per steradian.
    auto pdf2 = [&](double cosTheta, double phi) {
        double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        return pdfFn(basis.toWorld(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
    };

    return histogram2D(sample2, pdf2, cosEdges, phiEdges, nSamples, options, "cos", "phi");
}

HistogramResult intervalHistogramTest(const std::function<std::optional<double>(Sample2)>& sampleFn,
                                      const std::function<double(double)>& pdfFn, double a, double b, int bins,
                                      long nSamples, const HistogramOptions& options) {
    return intervalHistogramTest(sampleFn, pdfFn, uniformEdges(bins, a, b), nSamples, options);
}

HistogramResult intervalHistogramTest(const std::function<std::optional<double>(Sample2)>& sampleFn,
                                      const std::function<double(double)>& pdfFn, const std::vector<double>& edges,
                                      long nSamples, const HistogramOptions& options) {
    checkEdges(edges, "intervalHistogramTest");
    const int bins = int(edges.size()) - 1;
    takeIntegrationBudgetWarnings();
    std::vector<double> observed(size_t(bins), 0.0);
    long outside = 0, invalid = 0;
    Sampler sampler(options.seed, 0, 0);
    for (long k = 0; k < nSamples; ++k) {
        std::optional<double> s = sampleFn(sampler.next2D());
        if (!s) {
            ++outside;
            continue;
        }
        if (std::isnan(*s)) {
            ++invalid;
            ++outside;
            continue;
        }
        int i = findBin(edges, *s);
        if (i < 0) {
            ++outside;
            continue;
        }
        observed[i] += 1;
    }
    std::vector<double> expected(static_cast<size_t>(bins));
    double integral = 0;
    for (int i = 0; i < bins; ++i) {
        double p = integrate1D(pdfFn, edges[i], edges[i + 1], options.integrationTolerance, 0.1 * options.integrationRelTolerance, 4);
        integral += p;
        expected[i] = p * double(nSamples);
    }
    auto label = [&](int i) { return rangeLabel("x", edges, i); };
    return finish(std::move(observed), std::move(expected), outside, invalid, integral, nSamples, options, label);
}

// ---------------------------------------------------------------------------------------
// Monte Carlo estimates

double RunningStats::standardError() const { return n_ > 1 ? std::sqrt(variance() / double(n_)) : 0.0; }

double zScore(double estimate, double reference, double standardError) {
    double diff = estimate - reference;
    if (standardError > 0) return diff / standardError;
    if (diff == 0) return 0.0;
    return diff > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
}

}  // namespace brume::test
