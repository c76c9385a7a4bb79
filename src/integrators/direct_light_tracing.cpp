#include "brume/integrators/direct_light_tracing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "brume/integrators/sample_cost.h"

namespace brume {

namespace {

// Light tracing's splats in fixed point with 2^-24 resolution: sums of integers do not
// depend on the order the threads add them in. (Only the factor reads them.)
constexpr double kScale = 16777216.0;
int64_t fixedOf(float v) {
    if (!std::isfinite(v)) return 0;
    return int64_t(std::max(-4e18, std::min(4e18, double(v) * kScale)));
}

}  // namespace

void DirectLightTracing::ensureImages(int width, int height) {
    if (ready_.load(std::memory_order_acquire)) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (ready_.load(std::memory_order_relaxed)) return;
    const size_t n = size_t(width) * size_t(height) * 3;
    width_ = width;
    height_ = height;
    camera_.assign(n, 0.0f);
    light_.reset(new std::atomic<int64_t>[n]);
    for (size_t i = 0; i < n; ++i) light_[i].store(0, std::memory_order_relaxed);
    if (checkPasses_ < kCheckPasses && passes_ == kPasses) {  // (the check's)
        splitCamera_.assign(n, 0.0f);
        splitLight_.reset(new std::atomic<int64_t>[n]);
        for (size_t i = 0; i < n; ++i) splitLight_[i].store(0, std::memory_order_relaxed);
    }
    ready_.store(true, std::memory_order_release);
}

void DirectLightTracing::addCamera(int x, int y, const Spectrum& v) {
    float* p = &camera_[3 * (size_t(y) * size_t(width_) + size_t(x))];
    for (int c = 0; c < 3; ++c) p[c] = std::isfinite(v[c]) ? v[c] : 0.0f;
}

void DirectLightTracing::addLight(int x, int y, const Spectrum& v) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    std::atomic<int64_t>* p = &light_[3 * (size_t(y) * size_t(width_) + size_t(x))];
    for (int c = 0; c < 3; ++c) p[c].fetch_add(fixedOf(v[c]), std::memory_order_relaxed);
}

void DirectLightTracing::addSplitCamera(int x, int y, const Spectrum& v) {
    if (splitCamera_.empty()) return;
    float* p = &splitCamera_[3 * (size_t(y) * size_t(width_) + size_t(x))];
    for (int c = 0; c < 3; ++c) p[c] = std::isfinite(v[c]) ? v[c] : 0.0f;
}

void DirectLightTracing::addSplitLight(int x, int y, const Spectrum& v) {
    if (!splitLight_ || x < 0 || y < 0 || x >= width_ || y >= height_) return;
    std::atomic<int64_t>* p = &splitLight_[3 * (size_t(y) * size_t(width_) + size_t(x))];
    for (int c = 0; c < 3; ++c) p[c].fetch_add(fixedOf(v[c]), std::memory_order_relaxed);
}

void DirectLightTracing::endPass(const PassSummary& summary) {
    if (summary.radiance) addPassExact(summary, passSums_);
    if (!ready_.load()) {  // (a pass without samples: an empty image)
        ++passes_;
        if (passes_ >= kPasses) factor_ = 1.0;
        return;
    }
    const size_t n = camera_.size();
    std::vector<float> lightImage(n);
    for (size_t i = 0; i < n; ++i) lightImage[i] = float(double(light_[i].load(std::memory_order_relaxed)) / kScale);
    if (passes_ % 2 == 0) {
        first_[0] = camera_;
        first_[1] = std::move(lightImage);
    } else if (first_[0].size() == n && first_[1].size() == n) {
        if (weights_.size() != n) weights_.assign(n, 0.0f);
        for (size_t i = 0; i < n; ++i) {
            // Relative to the pair's mean of both families (the same weight for both).
            const double mean = 0.25 * (double(first_[0][i]) + camera_[i] + first_[1][i] + lightImage[i]);
            const double w = 1.0 / (mean * mean + 0.01);
            weights_[i] += float(w / (kPasses / 2));  // (the check's: the mean over the pairs)
            const double dc = double(camera_[i]) - first_[0][i], dl = double(lightImage[i]) - first_[1][i];
            squares_[0][(i / 3) % kGroups] += 0.5 * w * dc * dc;
            squares_[1][(i / 3) % kGroups] += 0.5 * w * dl * dl;
        }
    }
    ++passes_;
    std::fill(camera_.begin(), camera_.end(), 0.0f);
    for (size_t i = 0; i < n; ++i) light_[i].store(0, std::memory_order_relaxed);
    if (passes_ < kPasses) return;
    for (int f = 0; f < 2; ++f) {
        double g[kGroups];
        std::copy(squares_[f], squares_[f] + kGroups, g);
        std::nth_element(g, g + kGroups / 2, g + kGroups);
        variance_[f] = g[kGroups / 2] * kGroups / (kPasses / 2);
    }
    // No one-event paths seen by light tracing, or none at all: the plain weights.
    factor_ = variance_[1] > 0 ? std::max(kFloor, std::min(1.0, variance_[0] / variance_[1])) : 1.0;
    camera_ = {};
    light_.reset();
    ready_.store(false);
    first_[0] = first_[1] = {};
}

void DirectLightTracing::endCheckPass(const PathCounts* counts, int renderPasses) {
    // A pass without samples has no images: the check stops there (its batches need every
    // pass in order), and κ stays as learned.
    if (!ready_.load()) return;
    const size_t n = camera_.size();
    if (weights_.size() != n) weights_.assign(n, 1.0f);
    const bool split = splitCamera_.size() == n && splitLight_;
    std::vector<float> lightImage(n), splitImage(split ? n : 0);
    for (size_t i = 0; i < n; ++i) lightImage[i] = float(double(light_[i].load(std::memory_order_relaxed)) / kScale);
    if (split)
        for (size_t i = 0; i < n; ++i)
            splitImage[i] = splitCamera_[i] + float(double(splitLight_[i].load(std::memory_order_relaxed)) / kScale);
    batches_[0].addPass(0, checkPasses_, camera_, weights_);
    batches_[1].addPass(0, checkPasses_, lightImage, weights_);
    if (split) batches_[2].addPass(0, checkPasses_, splitImage, weights_);
    if (counts) {  // (sample_cost.h's units: the path tracer's and light tracing's parts)
        costs_[0] += pathTracerCost(counts->pt);
        costs_[1] += bidirectionalCost(counts->bdpt, 0.0);
        costs_[2] += kWeightCall * double(counts->pt.vertexCalls + counts->pt.segmentCalls);
    }
    ++checkPasses_;
    std::fill(camera_.begin(), camera_.end(), 0.0f);
    for (size_t i = 0; i < n; ++i) light_[i].store(0, std::memory_order_relaxed);
    if (split) {
        std::fill(splitCamera_.begin(), splitCamera_.end(), 0.0f);
        for (size_t i = 0; i < n; ++i) splitLight_[i].store(0, std::memory_order_relaxed);
    }
    if (checkPasses_ < kCheckPasses) return;
    // G = V(1) / (4·V(4)): 1 for independent numbers, more as Sobol numbers give more.
    for (int f = 0; f < 2; ++f) {
        const double v4 = batches_[f].variance(0, AllocationDuel::kLevels - 1);
        gain_[f] = v4 > 0 ? batches_[f].variance(0, 0) / (4.0 * v4) : 0.0;
    }
    if (gain_[0] > 0 && gain_[1] > 0) factor_ = std::max(kFloor, std::min(1.0, factor_ * gain_[1] / gain_[0]));
    // Light tracing pays if the split's estimate beats the camera side alone by more than the
    // time it adds (see the header), at the render's length: each variance carried from 4
    // passes to N at the rate its batches of 2 and 4 passes show.
    const int top = AllocationDuel::kLevels - 1;
    const double alone = batches_[0].variance(0, top), mixed = batches_[2].variance(0, top);
    const double alone2 = batches_[0].variance(0, top - 1), mixed2 = batches_[2].variance(0, top - 1);
    if (alone > 0 && mixed > 0 && alone2 > 0 && mixed2 > 0 && costs_[0] > 0) {
        const double n = renderPasses > 0 ? renderPasses : kAssumedPasses;
        auto rate = [](double v2, double v4) { return std::max(1.0, std::min(3.0, std::log2(v2 / v4))); };
        const double batches = std::max(1.0, n / double(1 << top));
        splitGain_ = alone / mixed * std::pow(batches, rate(mixed2, mixed) - rate(alone2, alone));
        costRatio_ = (costs_[0] + costs_[1] + costs_[2]) / costs_[0];
        off_ = splitGain_ < costRatio_;
    }
    camera_ = {};
    light_.reset();
    splitCamera_ = {};
    splitLight_.reset();
    ready_.store(false);
}

void DirectLightTracing::discardPass() {
    if (!ready_.load()) return;
    std::fill(camera_.begin(), camera_.end(), 0.0f);
    for (size_t i = 0; i < camera_.size(); ++i) light_[i].store(0, std::memory_order_relaxed);
    std::fill(splitCamera_.begin(), splitCamera_.end(), 0.0f);
    if (splitLight_)
        for (size_t i = 0; i < splitCamera_.size(); ++i) splitLight_[i].store(0, std::memory_order_relaxed);
}

// State: i32 passes, f64 factor, f64 variances × 2, f64 squares × 2·kGroups, the pair's
// first pass (u64 n, n f32) × 2, the learning passes' exact sums (u64 n, n × 128 bits), then the
// check: i32 passes, its pixel weights (u64 n, n f32), f64 gains × 2, its batches × 3
// (allocation_duel.h), u8 off, f64 split gain and cost ratio, f64 costs × 3.
void DirectLightTracing::save(std::string& out) const {
    putBytes(out, int32_t(passes_));
    putBytes(out, factor_);
    for (double v : variance_) putBytes(out, v);
    for (const auto& row : squares_)
        for (double v : row) putBytes(out, v);
    for (const std::vector<float>& f : first_) putVector(out, f);
    putVector(out, passSums_);
    putBytes(out, int32_t(checkPasses_));
    putVector(out, weights_);
    for (double g : gain_) putBytes(out, g);
    for (const AllocationDuel& b : batches_) b.save(out);
    putBytes(out, uint8_t(off_ ? 1 : 0));
    putBytes(out, splitGain_);
    putBytes(out, costRatio_);
    for (double c : costs_) putBytes(out, c);
}

void DirectLightTracing::load(StateReader& r) {
    passes_ = r.get<int32_t>();
    factor_ = r.get<double>();
    if (passes_ < 0 || passes_ > kPasses || !(factor_ >= kFloor && factor_ <= 1.0))
        throw std::runtime_error("light tracing state is malformed");
    for (double& v : variance_) v = r.get<double>();
    for (auto& row : squares_)
        for (double& v : row) v = r.get<double>();
    for (std::vector<float>& f : first_) f = r.getVector<float>(size_t(1) << 34);
    passSums_ = r.getVector<FixedSum>(size_t(1) << 34);
    checkPasses_ = r.get<int32_t>();
    if (checkPasses_ < 0 || checkPasses_ > kCheckPasses) throw std::runtime_error("light tracing state is malformed");
    weights_ = r.getVector<float>(size_t(1) << 34);
    for (double& g : gain_) g = r.get<double>();
    for (AllocationDuel& b : batches_) b.load(r, weights_.size());
    const uint8_t off = r.get<uint8_t>();
    if (off > 1) throw std::runtime_error("light tracing state is malformed");
    off_ = off == 1;
    splitGain_ = r.get<double>();
    costRatio_ = r.get<double>();
    for (double& c : costs_) c = r.get<double>();
}

}  // namespace brume
