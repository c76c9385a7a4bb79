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
    if (passes_ == 0) return Spectrum(0.0f);
    size_t i = 3 * (size_t(y) * size_t(width_) + size_t(x));
    double inv = 1.0 / passes_;
    return {float(fromFixed(sum_[i]) * inv), float(fromFixed(sum_[i + 1]) * inv), float(fromFixed(sum_[i + 2]) * inv)};
}

std::vector<float> Film::rgb() const {
    std::vector<float> out(sum_.size(), 0.0f);
    if (passes_ == 0) return out;
    double inv = 1.0 / passes_;
    for (size_t i = 0; i < sum_.size(); ++i) out[i] = float(fromFixed(sum_[i]) * inv);
    return out;
}

std::vector<float> Film::rgbWithout(int passes, const std::vector<Sum>& sums) const {
    if (passes <= 0 || passes >= passes_ || sums.size() != sum_.size()) return rgb();
    std::vector<float> out(sum_.size(), 0.0f);
    const double inv = 1.0 / (passes_ - passes);
    for (size_t i = 0; i < sum_.size(); ++i) out[i] = float(fromFixed(sum_[i] - sums[i]) * inv);
    return out;
}

void Film::restore(int passes, std::vector<Sum> sums, bool hasSplats) {
    if (passes < 0) throw std::invalid_argument("film: negative pass count " + std::to_string(passes));
    if (sums.size() != sum_.size())
        throw std::invalid_argument("film: restored state does not match the " + std::to_string(width_) + "x" +
                                    std::to_string(height_) + " film");
    passes_ = passes;
    sum_ = std::move(sums);
    hasSplats_ = hasSplats;
}

void Film::clear() {
    passes_ = 0;
    std::fill(sum_.begin(), sum_.end(), Sum(0));
    hasSplats_ = false;
}

}  // namespace brume
