// A method's render against the reference render, in the numbers the stability table shows:
//  - maxZ: the largest |z| over blocks and channels, z = (m − r) / sqrt(se_m² + se_r²) from the
//    two runs' batch means (independent seeds);
//  - zMean, relBias: the same for the mean over the whole image (one number, so no multiple
//    comparisons: the sharpest test of a bias), and that mean's relative difference;
//  - relRmse: sqrt(Σ (m − r)²) / sqrt(Σ r²) over blocks and channels, noise and bias together;
//  - outliers: the fraction of (pixel, batch) values above 10 × the reference pixel (floored at
//    10⁻³ of the reference image mean, so black reference pixels do not count every speck);
//  - relMedianOfMeans: the median over kGroups groups of consecutive batches of each group's
//    image mean, over the same of the reference, minus 1. A mean z divides by a standard error
//    that grows with the tail (a −58 % mean once passed at z = −1.06), and a reference's rare
//    large value moves every row's bias (g_forward: −60 % for all in one seed set); the median
//    of the groups' means ignores the few groups such a value lands in, on both sides, so a
//    biased image fails it however heavy the tails.
// Masked blocks (a point light imaged directly, which only light tracing can show) and their
// pixels are left out of every number.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "stability/stability_render.h"

namespace brume::test {

constexpr int kGroups = 8;

struct Comparison {
    double maxZ = 0, zMean = 0, relBias = 0, relRmse = 0, outliers = 0, relMedianOfMeans = 0;
    double relSeMean = 0;  // standard error of the image mean relative to it (the test's resolution)
    std::string worst;     // where maxZ is, for failure messages
};

inline double combinedZ(double a, double seA, double b, double seB) {
    double se = std::sqrt(seA * seA + seB * seB), diff = a - b;
    if (se > 0) return diff / se;
    return std::abs(diff) > 1e-12 * std::max(1.0, std::abs(b)) ? INFINITY : 0.0;
}

// The image mean over unmasked pixels of batch b.
inline double batchImageMean(const StabilityRun& run, int b, const std::vector<bool>& maskedBlock) {
    double sum = 0;
    long n = 0;
    for (int i = 0; i < run.width * run.height; ++i) {
        int bx = (i % run.width) / run.block, by = (i / run.width) / run.block;
        if (bx >= run.blocksX() || maskedBlock[size_t(by) * run.blocksX() + bx]) continue;
        sum += run.pixel(b, i);
        ++n;
    }
    return n > 0 ? sum / double(n) : 0.0;
}

// The median over kGroups groups of consecutive batches of each group's image mean.
inline double medianOfMeans(const StabilityRun& run, const std::vector<bool>& maskedBlock) {
    std::vector<double> means(kGroups, 0.0);
    const int per = run.batches / kGroups;
    for (int g = 0; g < kGroups; ++g) {
        for (int b = g * per; b < (g + 1) * per; ++b) means[size_t(g)] += batchImageMean(run, b, maskedBlock);
        means[size_t(g)] /= per;
    }
    std::sort(means.begin(), means.end());
    return 0.5 * (means[kGroups / 2 - 1] + means[kGroups / 2]);
}

// Batch means of the image mean over unmasked pixels.
inline PixelEstimate imageMean(const StabilityRun& run, const std::vector<bool>& maskedBlock) {
    PixelEstimate e;
    for (int b = 0; b < run.batches; ++b) {
        const double v = batchImageMean(run, b, maskedBlock);
        for (int c = 0; c < 3; ++c) e.sum[c] += v, e.sum2[c] += v * v;
        ++e.n;
    }
    return e;
}

inline Comparison compareRuns(const StabilityRun& m, const StabilityRun& r, const std::vector<bool>& maskedBlock) {
    Comparison out;
    double sq = 0, refSq = 0;
    for (size_t i = 0; i < m.blocks.size(); ++i) {
        if (maskedBlock[i]) continue;
        for (int c = 0; c < 3; ++c) {
            double a = m.blocks[i].mean(c), b = r.blocks[i].mean(c);
            double z = combinedZ(a, m.blocks[i].stderror(c), b, r.blocks[i].stderror(c));
            sq += (a - b) * (a - b);
            refSq += b * b;
            if (!(std::abs(z) <= out.maxZ)) {
                out.maxZ = std::abs(z);
                out.worst = "block (" + std::to_string(int(i) % m.blocksX()) + "," + std::to_string(int(i) / m.blocksX()) +
                            ") channel " + std::to_string(c) + ": " + std::to_string(a) + " ± " +
                            std::to_string(m.blocks[i].stderror(c)) + " vs reference " + std::to_string(b) + " ± " +
                            std::to_string(r.blocks[i].stderror(c));
            }
        }
    }
    out.relRmse = refSq > 0 ? std::sqrt(sq / refSq) : (sq > 0 ? INFINITY : 0.0);
    PixelEstimate em = imageMean(m, maskedBlock), er = imageMean(r, maskedBlock);
    out.zMean = combinedZ(em.mean(0), em.stderror(0), er.mean(0), er.stderror(0));
    out.relBias = er.mean(0) != 0 ? em.mean(0) / er.mean(0) - 1.0 : 0.0;
    const double refMedian = medianOfMeans(r, maskedBlock);
    out.relMedianOfMeans = refMedian != 0 ? medianOfMeans(m, maskedBlock) / refMedian - 1.0 : 0.0;
    out.relSeMean = er.mean(0) != 0 ? std::sqrt(em.stderror(0) * em.stderror(0) + er.stderror(0) * er.stderror(0)) /
                                          std::abs(er.mean(0))
                                    : 0.0;
    // Outliers against the reference's per-pixel mean over all its batches.
    const int np = m.width * m.height;
    double floor = 1e-3 * std::abs(er.mean(0));
    long count = 0, total = 0;
    for (int i = 0; i < np; ++i) {
        int bx = (i % m.width) / m.block, by = (i / m.width) / m.block;
        if (bx >= m.blocksX() || maskedBlock[size_t(by) * m.blocksX() + bx]) continue;
        double ref = 0;
        for (int b = 0; b < r.batches; ++b) ref += r.pixel(b, i);
        ref = std::max(ref / r.batches, floor);
        for (int b = 0; b < m.batches; ++b, ++total)
            if (m.pixel(b, i) > 10.0 * ref) ++count;
    }
    out.outliers = total > 0 ? double(count) / double(total) : 0.0;
    return out;
}

}  // namespace brume::test
