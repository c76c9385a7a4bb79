#include "brume/film/film.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace brume {

Film::Film(int width, int height) : width_(width), height_(height) {
    if (width <= 0 || height <= 0)
        throw std::invalid_argument("film size must be positive, got " + std::to_string(width) + "x" +
                                    std::to_string(height));
    sum_.assign(3 * size_t(width) * size_t(height), 0.0);
}

void Film::splat(int x, int y, Spectrum value) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    if (splat_.empty()) splat_.assign(sum_.size(), 0.0);
    double* p = &splat_[3 * (size_t(y) * size_t(width_) + size_t(x))];
    p[0] += value.x;
    p[1] += value.y;
    p[2] += value.z;
}

void Film::mergeSplats(const SplatList& splats) {
    for (const SplatList::Record& r : splats.records()) splat(r.x, r.y, r.value);
}

Spectrum Film::pixel(int x, int y) const {
    if (passes_ == 0) return Spectrum(0.0f);
    size_t i = 3 * (size_t(y) * size_t(width_) + size_t(x));
    double s[3] = {sum_[i], sum_[i + 1], sum_[i + 2]};
    if (!splat_.empty())
        for (int c = 0; c < 3; ++c) s[c] += splat_[i + c];
    double inv = 1.0 / passes_;
    return {float(s[0] * inv), float(s[1] * inv), float(s[2] * inv)};
}

std::vector<float> Film::rgb() const {
    std::vector<float> out(sum_.size(), 0.0f);
    if (passes_ == 0) return out;
    double inv = 1.0 / passes_;
    for (size_t i = 0; i < sum_.size(); ++i) {
        double s = sum_[i];
        if (!splat_.empty()) s += splat_[i];
        out[i] = float(s * inv);
    }
    return out;
}

void Film::restore(int passes, std::vector<double> sampleSums, std::vector<double> splatSums) {
    if (passes < 0) throw std::invalid_argument("film: negative pass count " + std::to_string(passes));
    if (sampleSums.size() != sum_.size() || (!splatSums.empty() && splatSums.size() != sum_.size()))
        throw std::invalid_argument("film: restored state does not match the " + std::to_string(width_) + "x" +
                                    std::to_string(height_) + " film");
    passes_ = passes;
    sum_ = std::move(sampleSums);
    splat_ = std::move(splatSums);
}

void Film::clear() {
    passes_ = 0;
    std::fill(sum_.begin(), sum_.end(), 0.0);
    splat_.clear();
    splat_.shrink_to_fit();
}

}  // namespace brume
