#include "brume/integrators/direct_light_tracing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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
        for (size_t i = 0; i < n; ++i) {
            // Relative to the pair's mean of both families (the same weight for both).
            const double mean = 0.25 * (double(first_[0][i]) + camera_[i] + first_[1][i] + lightImage[i]);
            const double w = 1.0 / (mean * mean + 0.01);
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

void DirectLightTracing::discardPass() {
    if (!ready_.load()) return;
    std::fill(camera_.begin(), camera_.end(), 0.0f);
    for (size_t i = 0; i < camera_.size(); ++i) light_[i].store(0, std::memory_order_relaxed);
}

// State: i32 passes, f64 factor, f64 variances × 2, f64 squares × 2·kGroups, the pair's
// first pass (u64 n, n f32) × 2, then the learning passes' exact sums (u64 n, n × 128 bits).
void DirectLightTracing::save(std::string& out) const {
    putBytes(out, int32_t(passes_));
    putBytes(out, factor_);
    for (double v : variance_) putBytes(out, v);
    for (const auto& row : squares_)
        for (double v : row) putBytes(out, v);
    for (const std::vector<float>& f : first_) putVector(out, f);
    putVector(out, passSums_);
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
}

}  // namespace brume
