#include "brume/integrators/connection_shares.h"

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

double shareOf(const ConnectionShares::Record& r, ConnectionShares::Shares q) {
    q = ConnectionShares::madeWith(q, r.p);
    switch (r.technique) {
        case ConnectionShares::Technique::Vertex: return q.vertex;
        case ConnectionShares::Technique::Segment: return q.segment;
        case ConnectionShares::Technique::SolidAngle: return q.solidAngle;
        default: return 1.0;
    }
}

}  // namespace

void ConnectionShares::ensure(int width, int height) {
    std::lock_guard<std::mutex> lock(sizing_);
    if (width_ == width && height_ == height && !sum_.empty()) {
        sized_.store(true, std::memory_order_release);
        return;
    }
    width_ = width;
    height_ = height;
    const size_t n = size_t(width) * size_t(height);
    moments_.assign(n * kCandidates, 0.0f);
    sum_.assign(n, 0.0);
    vertexCalls_.assign(n, 0);
    passingCalls_.assign(n, 0);
    sized_.store(true, std::memory_order_release);
}

void ConnectionShares::addSample(int width, int height, uint32_t pixel, double L, const Record* records, int n,
                                 uint32_t mediumVertexCalls, uint32_t passingSegmentCalls) {
    if (!sized_.load(std::memory_order_acquire)) ensure(width, height);  // (the first samples of a render)
    if (!std::isfinite(L)) return;
    // The rest of the sample: L without the records' estimates as weighted now (q = 1).
    double rest = L;
    for (int i = 0; i < n; ++i) rest -= records[i].value * weightUnder(records[i], Shares{});
    float* m = &moments_[size_t(pixel) * kCandidates];
    for (int j = 0; j < kCandidates; ++j) {
        const Shares q = candidate(j);
        double s = rest, bernoulli = 0;
        for (int i = 0; i < n; ++i) {
            const double v = records[i].value * weightUnder(records[i], q);
            s += v;
            const double share = shareOf(records[i], q);
            if (share < 1 && share > 0) bernoulli += v * v * (1.0 / share - 1.0);  // (share 0: v = 0)
        }
        const double moment = s * s + bernoulli;
        if (std::isfinite(moment)) m[j] += float(moment);
    }
    vertexCalls_[pixel] += mediumVertexCalls;
    passingCalls_[pixel] += passingSegmentCalls;
}

void ConnectionShares::endPass(const PassSummary& summary) {
    if (decided_ || !summary.complete || !summary.radiance) return;
    ensure(summary.width, summary.height);
    const size_t n = size_t(summary.width) * size_t(summary.height);
    for (size_t p = 0; p < n; ++p) {
        const Spectrum& v = summary.radiance[p];
        sum_[p] += double(v.x + v.y + v.z) / 3.0;
    }
    counts_.add(summary.totals.counts);
    if (++passes_ >= kLearningPasses) decide(summary);
}

void ConnectionShares::decide(const PassSummary& summary) {
    const size_t n = size_t(summary.width) * size_t(summary.height);
    double variance[kCandidates] = {};
    uint64_t vertexCalls = 0, passingCalls = 0;
    for (size_t p = 0; p < n; ++p) {
        const double mean = sum_[p] / passes_;
        const double w = 1.0 / (mean * mean + 0.01);
        for (int j = 0; j < kCandidates; ++j)
            variance[j] += w * (double(moments_[p * kCandidates + size_t(j)]) / passes_ - mean * mean);
        vertexCalls += vertexCalls_[p];
        passingCalls += passingCalls_[p];
    }
    // Cost of the learning passes' samples, less the connections a candidate would skip (on
    // segments only those that trace: the others return at once, path_stats.h; with qC = 0
    // not those where the walk passes through, which C alone makes: madeWith; D's rays, which
    // qD = 0 skips all of: D is never made where the walk passes through).
    const double base = pathTracerCost(counts_.pt);
    const double segmentCalls = double(counts_.pt.segmentTracingCalls);
    const double solidAngleRays = double(counts_.pt.solidAngleRays);
    int best = 0;
    for (int j = 0; j < kCandidates; ++j) {
        const Shares q = candidate(j);
        variance_[j] = variance[j];
        cost_[j] = base - pt_cost::kVertexCall * (1.0 - q.vertex) * double(vertexCalls) -
                   pt_cost::kSegmentCall * (q.segment > 0 ? (1.0 - q.segment) * segmentCalls : segmentCalls - double(passingCalls)) -
                   pt_cost::kSolidAngleRay * (1.0 - q.solidAngle) * solidAngleRays;
        if (variance_[j] > 0 && cost_[j] > 0 && variance_[j] * cost_[j] < variance_[best] * cost_[best]) best = j;
    }
    shares_ = candidate(best);
    decided_ = true;
    moments_ = {};
    sum_ = {};
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
    std::snprintf(buf, sizeof buf, "connection shares: at medium vertices %.2f, on segments %.2f", double(shares_.vertex),
                  double(shares_.segment));
    out += buf;
    if (solidAngle) {
        std::snprintf(buf, sizeof buf, ", by solid angle %.0f", double(shares_.solidAngle));
        out += buf;
    }
    std::snprintf(buf, sizeof buf, " (learned from %d passes)\n", passes_);
    out += buf;
    out += solidAngle ? "  shares (vertex, segment, solid angle)   variance       cost   efficiency   (relative to 1, 1, 1)\n"
                      : "  shares (vertex, segment)   variance       cost   efficiency   (relative to 1, 1)\n";
    for (int j = 0; j < (solidAngle ? kCandidates : kCandidates / 2); ++j) {
        const Shares q = candidate(j);
        const double e = variance_[j] > 0 && cost_[j] > 0 ? (variance_[0] * cost_[0]) / (variance_[j] * cost_[j]) : 0.0;
        if (solidAngle)
            std::snprintf(buf, sizeof buf, "  %4.2f, %4.2f, %.0f                        ", double(q.vertex), double(q.segment),
                          double(q.solidAngle));
        else
            std::snprintf(buf, sizeof buf, "  %4.2f, %4.2f             ", double(q.vertex), double(q.segment));
        out += buf;
        std::snprintf(buf, sizeof buf, "%9.3g  %9.3g  %11.3g\n", variance_[0] > 0 ? variance_[j] / variance_[0] : 0.0,
                      cost_[0] > 0 ? cost_[j] / cost_[0] : 0.0, e);
        out += buf;
    }
    return out;
}

std::string ConnectionShares::saveState() const {
    std::string out = "CSH4";
    auto put = [&](const void* p, size_t bytes) { out.append(static_cast<const char*>(p), bytes); };
    const uint8_t decided = decided_ ? 1 : 0;
    put(&decided, 1);
    put(&shares_, sizeof shares_);
    put(&passes_, sizeof passes_);
    put(&width_, sizeof width_);
    put(&height_, sizeof height_);
    putVector(out, moments_);
    putVector(out, sum_);
    putVector(out, vertexCalls_);
    putVector(out, passingCalls_);
    std::vector<uint64_t> counts;
    counts_.forEach([&](const uint64_t& v) { counts.push_back(v); });
    putVector(out, counts);
    put(variance_, sizeof variance_);
    put(cost_, sizeof cost_);
    return out;
}

void ConnectionShares::loadState(const std::string& state) {
    if (state.compare(0, 4, "CSH4") != 0) throw std::runtime_error("connection shares state is malformed");
    StateReader r{state, 4};
    decided_ = r.get<uint8_t>() != 0;
    shares_ = r.get<Shares>();
    passes_ = r.get<int>();
    width_ = r.get<int>();
    height_ = r.get<int>();
    const size_t pixels = size_t(std::max(width_, 0)) * size_t(std::max(height_, 0));
    moments_ = r.getVector<float>(pixels * kCandidates);
    sum_ = r.getVector<double>(pixels);
    vertexCalls_ = r.getVector<uint32_t>(pixels);
    passingCalls_ = r.getVector<uint32_t>(pixels);
    const std::vector<uint64_t> counts = r.getVector<uint64_t>(PathCounts::kCount);
    if (counts.size() != size_t(PathCounts::kCount)) throw std::runtime_error("connection shares state is malformed");
    size_t i = 0;
    counts_.forEach([&](uint64_t& v) { v = counts[i++]; });
    for (double& v : variance_) v = r.get<double>();
    for (double& v : cost_) v = r.get<double>();
    if (r.at != state.size()) throw std::runtime_error("connection shares state has trailing bytes");
    if (!decided_ && (moments_.size() != pixels * kCandidates || sum_.size() != pixels || vertexCalls_.size() != pixels ||
                       passingCalls_.size() != pixels))
        throw std::runtime_error("connection shares state is malformed");
    sized_.store(!decided_ && pixels > 0, std::memory_order_release);
}

}  // namespace brume
