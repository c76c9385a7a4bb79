#include "brume/integrators/connection_shares.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "brume/integrators/sample_cost.h"
#include "brume/integrators/state_bytes.h"

namespace brume {

namespace {

// A record's weight under shares q: the power heuristic the path tracer weighs with, over the
// strategies' densities with A's, C's and D's times their shares.
double weightUnder(const ConnectionShares::Record& r, ConnectionShares::Shares q) {
    q = ConnectionShares::madeWith(q, r.p);
    const StrategyDensities p{r.p.a * q.vertex, r.p.b, r.p.c * q.segment, r.p.d * q.solidAngle};
    switch (r.technique) {
        case ConnectionShares::Technique::Vertex: return powerWeight(p.a, p);
        case ConnectionShares::Technique::Emitter: return powerWeight(p.b, p);
        case ConnectionShares::Technique::Segment: return powerWeight(p.c, p);
        case ConnectionShares::Technique::SolidAngle: return powerWeight(p.d, p);
    }
    return 0;
}

}  // namespace

int ConnectionShares::stride(int width, int height) {
    int k = 1;
    while (int64_t((width + k - 1) / k) * int64_t((height + k - 1) / k) > kMaxLearningPixels) ++k;
    return k;
}

int ConnectionShares::slotOf(int width, int height, uint32_t pixel) {
    const int k = stride(width, height);
    const int x = int(pixel % uint32_t(width)), y = int(pixel / uint32_t(width));
    if (x % k != 0 || y % k != 0) return -1;
    return (y / k) * ((width + k - 1) / k) + x / k;
}

bool ConnectionShares::learnsAt(int width, int height, uint32_t pixel) { return slotOf(width, height, pixel) >= 0; }

void ConnectionShares::ensure(int width, int height) {
    std::lock_guard<std::mutex> lock(sizing_);
    if (width_ == width && height_ == height && !values_.empty()) {
        sized_.store(true, std::memory_order_release);
        return;
    }
    width_ = width;
    height_ = height;
    const int k = stride(width, height);
    const size_t slots = size_t((width + k - 1) / k) * size_t((height + k - 1) / k);
    const size_t n = size_t(width) * size_t(height);
    batches_.assign(slots * kCandidates * kFields, 0.0f);
    values_.assign(slots * kLearningPasses, 0.0f);
    vertexCalls_.assign(n, 0);
    passingCalls_.assign(n, 0);
    sized_.store(true, std::memory_order_release);
}

void ConnectionShares::addSample(int width, int height, uint32_t pixel, double L, const Record* records, int n,
                                 uint32_t mediumVertexCalls, uint32_t passingSegmentCalls) {
    if (!sized_.load(std::memory_order_acquire)) ensure(width, height);  // (the first samples of a render)
    vertexCalls_[pixel] += mediumVertexCalls;
    passingCalls_[pixel] += passingSegmentCalls;
    const int slot = slotOf(width, height, pixel);
    if (slot < 0) return;
    // A non-finite sample counts as 0 (as the film drops it), so that every pass has its value.
    if (!std::isfinite(L)) L = 0, n = 0;
    // The rest of the sample: L without the records' estimates as weighted now (q = 1).
    double rest = L;
    for (int i = 0; i < n; ++i) rest -= records[i].value * weightUnder(records[i], Shares{});
    const int k = passes_;  // this pass's place among the learning passes
    values_[size_t(slot) * kLearningPasses + size_t(k)] = float(L);
    float* b = &batches_[size_t(slot) * kCandidates * kFields];
    for (int j = 0; j < kCandidates; ++j, b += kFields) {
        const Shares q = candidate(j);
        double s = rest;
        for (int i = 0; i < n; ++i) s += records[i].value * weightUnder(records[i], q);
        if (!std::isfinite(s)) s = 0;
        // Aligned batches: passes (2i, 2i + 1) make a 2-pass batch, (4i … 4i + 3) a 4-pass one.
        b[0] = k % 2 == 0 ? float(s) : b[0] + float(s);
        if (k % 2 == 0) continue;
        if ((k / 2) % 2 == 0) {
            b[1] = b[0];
            continue;
        }
        const float d2 = (b[1] - b[0]) / 2, four = b[1] + b[0];
        b[3] += d2 * d2;
        if ((k / 4) % 2 == 0) {
            b[2] = four;
        } else {
            const float d4 = (b[2] - four) / 4;
            b[4] += d4 * d4;
            b[0] = b[2] + four;  // (the last pass: the sum of all eight)
        }
    }
}

void ConnectionShares::endPass(const PassSummary& summary) {
    if (decided_ || !summary.complete || !summary.radiance) return;
    ensure(summary.width, summary.height);
    counts_.add(summary.totals.counts);
    if (++passes_ >= kLearningPasses) decide();
}

void ConnectionShares::decide() {
    // E(2) and E(4) per candidate (connection_shares.h), summed in pixel order: with a, b the
    // means of the halves, (a − b)²/2 per pair.
    double e2[kCandidates] = {}, e4[kCandidates] = {};
    const size_t slots = values_.size() / kLearningPasses;
    for (size_t slot = 0; slot < slots; ++slot) {
        // The pixel's weight from the mean of its passes without the largest: where a bright
        // emitter covers a sliver of the pixel, the one pass in eight that hits it makes the
        // mean many times the pixel's value, and its weight a small part of what bench gives
        // it (the median errs the other way where the emitter covers half the pixel).
        float v[kLearningPasses];
        std::copy_n(&values_[slot * kLearningPasses], kLearningPasses, v);
        std::sort(v, v + kLearningPasses);
        double typical = 0;
        for (int i = 0; i + 1 < kLearningPasses; ++i) typical += double(v[i]);
        typical /= kLearningPasses - 1;
        const double w = 1.0 / (typical * typical + 0.01);
        const float* b = &batches_[slot * kCandidates * kFields];
        const double all = double(b[0]) / passes_;  // the all-made mean of the pixel
        for (int j = 0; j < kCandidates; ++j, b += kFields) {
            // Plus the candidate's mean against the all-made one, as a variance of 8 passes
            // (twice that at 4): where the candidate's light is in events too rare for 8
            // passes, its batches spread little while its mean falls short of the image.
            const double off = double(b[0]) / passes_ - all;
            e2[j] += w * (double(b[3]) / 4.0 + 4.0 * off * off);
            e4[j] += w * (double(b[4]) / 2.0 + 2.0 * off * off);
        }
    }
    uint64_t vertexCalls = 0, passingCalls = 0;
    for (size_t p = 0; p < vertexCalls_.size(); ++p) {
        vertexCalls += vertexCalls_[p];
        passingCalls += passingCalls_[p];
    }
    // Cost of the learning passes' samples, less what the connections a candidate would skip
    // save (sample_cost.h: A's calls with their rays; on segments only the calls that trace:
    // the others return at once, path_stats.h; with qC = 0 not those where the walk passes
    // through, which C alone makes: madeWith; D's rays, which qD = 0 skips all of: D is never
    // made where the walk passes through).
    const double base = pathTracerCost(counts_.pt);
    const double segmentCalls = double(counts_.pt.segmentTracingCalls);
    const double solidAngleRays = double(counts_.pt.solidAngleRays);
    // What a call of A at a medium vertex saves: its call and its rays (as many per call as
    // all of A's calls traced, surfaces included).
    const double vertexCall =
        pt_cost::kVertexCall + (counts_.pt.vertexCalls > 0 ? pt_cost::kVertexRaySaved * double(counts_.pt.vertexRays) /
                                                                  double(counts_.pt.vertexCalls)
                                                            : 0.0);
    for (int j = 0; j < kCandidates; ++j) {
        const Shares q = candidate(j);
        cost_[j] = base - vertexCall * (1.0 - q.vertex) * double(vertexCalls) -
                   pt_cost::kSegmentCallSaved *
                       (q.segment > 0 ? (1.0 - q.segment) * segmentCalls : segmentCalls - double(passingCalls)) -
                   pt_cost::kSolidAngleRaySaved * (1.0 - q.solidAngle) * solidAngleRays;
        variance_[j] = e4[j];
    }
    // The rate, from the all-made estimator's batches (one rate for all: a rate per candidate
    // from 8 passes differs by its noise, which over 16× more passes outweighs the variances'
    // differences).
    const double E2 = e2[0];
    rate_ = E2 > 0 && variance_[0] > 0 ? std::min(3.0, std::max(1.0, std::log2(E2 / variance_[0]))) : 1.0;
    int best = 0;
    for (int j = 0; j < kCandidates; ++j) {
        // The error at equal time relative to the all-made estimator's: with N ∝ 1/cost passes
        // and V ∝ N^−α, V_j(4)·(cost_j/cost_all)^α.
        error_[j] = variance_[j] > 0 && cost_[j] > 0 && cost_[0] > 0 ? variance_[j] * std::pow(cost_[j] / cost_[0], rate_) : 0.0;
        if (keepSegments_ && candidate(j).segment <= 0) continue;  // (keepSegments)
        if (error_[j] > 0 && (error_[best] <= 0 || error_[j] < error_[best])) best = j;
    }
    shares_ = candidate(best);
    decided_ = true;
    batches_ = {};
    values_ = {};
    vertexCalls_ = {};
    passingCalls_ = {};
    sized_.store(false, std::memory_order_release);
}

std::string ConnectionShares::report() const {
    if (!decided_) return "connection shares: learning\n";
    char buf[160];
    std::string out;
    // D's column and rows only where D was made (emissive triangles by solid angle, close by).
    const bool solidAngle = counts_.pt.solidAngleCalls > 0;
    std::snprintf(buf, sizeof buf, "connection shares: at medium vertices %.0f, on segments %.0f", double(shares_.vertex),
                  double(shares_.segment));
    out += buf;
    if (solidAngle) {
        std::snprintf(buf, sizeof buf, ", by solid angle %.0f", double(shares_.solidAngle));
        out += buf;
    }
    std::snprintf(buf, sizeof buf, " (learned from %d passes)\n", passes_);
    out += buf;
    std::snprintf(buf, sizeof buf,
                  "  (all made: weighted relative variance of 4 passes %.3g, summed over pixels; it falls as passes^-%.2f)\n",
                  variance_[0], rate_);
    out += buf;
    out += solidAngle ? "  shares (vertex, segment, solid angle)" : "  shares (vertex, segment)";
    out += "   variance at 4 passes      cost   efficiency   (relative to all made)\n";
    for (int j = 0; j < (solidAngle ? kCandidates : kCandidates / 2); ++j) {
        const Shares q = candidate(j);
        const double e = error_[j] > 0 ? error_[0] / error_[j] : 0.0;
        if (solidAngle)
            std::snprintf(buf, sizeof buf, "  %.0f, %.0f, %.0f                                ", double(q.vertex), double(q.segment),
                          double(q.solidAngle));
        else
            std::snprintf(buf, sizeof buf, "  %.0f, %.0f                     ", double(q.vertex), double(q.segment));
        out += buf;
        std::snprintf(buf, sizeof buf, "%20.3g  %8.3g  %11.3g%s\n", variance_[0] > 0 ? variance_[j] / variance_[0] : 0.0,
                      cost_[0] > 0 ? cost_[j] / cost_[0] : 0.0, e,
                      keepSegments_ && q.segment <= 0 ? "   not a candidate: a point-like light in a medium" : "");
        out += buf;
    }
    return out;
}

std::string ConnectionShares::saveState() const {
    std::string out = "CSH5";
    auto put = [&](const void* p, size_t bytes) { out.append(static_cast<const char*>(p), bytes); };
    const uint8_t decided = decided_ ? 1 : 0;
    put(&decided, 1);
    put(&shares_, sizeof shares_);
    put(&passes_, sizeof passes_);
    put(&width_, sizeof width_);
    put(&height_, sizeof height_);
    putVector(out, batches_);
    putVector(out, values_);
    putVector(out, vertexCalls_);
    putVector(out, passingCalls_);
    std::vector<uint64_t> counts;
    counts_.forEach([&](const uint64_t& v) { counts.push_back(v); });
    putVector(out, counts);
    put(variance_, sizeof variance_);
    put(&rate_, sizeof rate_);
    put(cost_, sizeof cost_);
    put(error_, sizeof error_);
    return out;
}

void ConnectionShares::loadState(const std::string& state) {
    if (state.compare(0, 4, "CSH5") != 0) throw std::runtime_error("connection shares state is malformed");
    StateReader r{state, 4};
    decided_ = r.get<uint8_t>() != 0;
    shares_ = r.get<Shares>();
    passes_ = r.get<int>();
    width_ = r.get<int>();
    height_ = r.get<int>();
    const size_t pixels = size_t(std::max(width_, 0)) * size_t(std::max(height_, 0));
    const int k = width_ > 0 && height_ > 0 ? stride(width_, height_) : 1;
    const size_t slots = width_ > 0 && height_ > 0 ? size_t((width_ + k - 1) / k) * size_t((height_ + k - 1) / k) : 0;
    batches_ = r.getVector<float>(slots * kCandidates * kFields);
    values_ = r.getVector<float>(slots * kLearningPasses);
    vertexCalls_ = r.getVector<uint32_t>(pixels);
    passingCalls_ = r.getVector<uint32_t>(pixels);
    const std::vector<uint64_t> counts = r.getVector<uint64_t>(PathCounts::kCount);
    if (counts.size() != size_t(PathCounts::kCount)) throw std::runtime_error("connection shares state is malformed");
    size_t i = 0;
    counts_.forEach([&](uint64_t& v) { v = counts[i++]; });
    for (double& v : variance_) v = r.get<double>();
    rate_ = r.get<double>();
    for (double& v : cost_) v = r.get<double>();
    for (double& v : error_) v = r.get<double>();
    if (r.at != state.size()) throw std::runtime_error("connection shares state has trailing bytes");
    if (!decided_ && (batches_.size() != slots * kCandidates * kFields || values_.size() != slots * kLearningPasses ||
                       vertexCalls_.size() != pixels ||
                       passingCalls_.size() != pixels))
        throw std::runtime_error("connection shares state is malformed");
    sized_.store(!decided_ && pixels > 0, std::memory_order_release);
}

}  // namespace brume
