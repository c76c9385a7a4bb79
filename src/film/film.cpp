#include "brume/film/film.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace brume {

Film::Film(int width, int height) : width_(width), height_(height) {
    if (width <= 0 || height <= 0)
        throw std::invalid_argument("film size must be positive, got " + std::to_string(width) + "x" +
                                    std::to_string(height));
    sum_.assign(3 * size_t(width) * size_t(height), Sum(0));
}

void Film::trackNoise() {
    if (tracksNoise()) return;
    if (passes_ > 0) throw std::logic_error("film: noise tracking must start before the first pass");
    samples_.assign(size_t(width_) * size_t(height_), 0);
    squares_.assign(sum_.size(), Sum(0));
}

void Film::addPassValue(size_t i, Spectrum value) {
    ++samples_[i];
    for (int c = 0; c < 3; ++c) squares_[3 * i + size_t(c)] += toFixed(value[c] * value[c]);
}

void Film::splat(int x, int y, Spectrum value) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    hasSplats_ = true;
    Sum* p = &sum_[3 * (size_t(y) * size_t(width_) + size_t(x))];
    p[0] += toFixed(value.x);
    p[1] += toFixed(value.y);
    p[2] += toFixed(value.z);
}

void Film::mergeSplats(const SplatList& splats) {
    for (const SplatList::Record& r : splats.records()) splat(r.x, r.y, r.value);
}

Spectrum Film::pixel(int x, int y) const {
    const size_t p = size_t(y) * size_t(width_) + size_t(x), i = 3 * p;
    const int n = samples(p);
    if (n == 0) return Spectrum(0.0f);
    double inv = 1.0 / n;
    return {float(fromFixed(sum_[i]) * inv), float(fromFixed(sum_[i + 1]) * inv), float(fromFixed(sum_[i + 2]) * inv)};
}

std::vector<float> Film::rgb() const {
    std::vector<float> out(sum_.size(), 0.0f);
    for (size_t p = 0; p < sum_.size() / 3; ++p) {
        const int n = samples(p);
        if (n == 0) continue;
        const double inv = 1.0 / n;
        for (size_t i = 3 * p; i < 3 * p + 3; ++i) out[i] = float(fromFixed(sum_[i]) * inv);
    }
    return out;
}

// The left-out passes came before any pixel stopped (renderer.cpp starts stopping after
// the integrator's learning passes), so every pixel took part in them.
std::vector<float> Film::rgbWithout(int passes, const std::vector<Sum>& sums) const {
    return rgbWithout(passes, sums, [](int) { return true; });
}

std::vector<float> Film::rgbWithout(int passes, const std::vector<Sum>& sums, const std::function<bool(int)>& leaveOut) const {
    if (passes <= 0 || passes >= passes_ || sums.size() != sum_.size()) return rgb();
    std::vector<float> out = rgb();
    for (size_t p = 0; p < sum_.size() / 3; ++p) {
        const int n = samples(p) - passes;
        if (n <= 0 || !leaveOut(n)) continue;
        const double inv = 1.0 / n;
        for (size_t i = 3 * p; i < 3 * p + 3; ++i) out[i] = float(fromFixed(sum_[i] - sums[i]) * inv);
    }
    return out;
}

void Film::restore(int passes, std::vector<Sum> sums, bool hasSplats, std::vector<int32_t> samples,
                   std::vector<Sum> squares) {
    if (passes < 0) throw std::invalid_argument("film: negative pass count " + std::to_string(passes));
    if (sums.size() != sum_.size())
        throw std::invalid_argument("film: restored state does not match the " + std::to_string(width_) + "x" +
                                    std::to_string(height_) + " film");
    if (samples.empty() != squares.empty() || (!samples.empty() && (samples.size() != sum_.size() / 3 || squares.size() != sum_.size())))
        throw std::invalid_argument("film: restored noise tracking does not match the film");
    for (int32_t n : samples)
        if (n < 0 || n > passes) throw std::invalid_argument("film: restored pixel sample count out of range");
    passes_ = passes;
    sum_ = std::move(sums);
    hasSplats_ = hasSplats;
    samples_ = std::move(samples);
    squares_ = std::move(squares);
}

void Film::clear() {
    passes_ = 0;
    std::fill(sum_.begin(), sum_.end(), Sum(0));
    hasSplats_ = false;
    std::fill(samples_.begin(), samples_.end(), 0);
    std::fill(squares_.begin(), squares_.end(), Sum(0));
}

}  // namespace brume
