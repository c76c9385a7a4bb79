#include "brume/film/pixel_noise.h"

#include <algorithm>
#include <cmath>

namespace brume {

double pixelRelativeVariance(const Film& film, size_t i) {
    const int n = film.samples(i);
    if (n < 2) return HUGE_VAL;
    double e2 = 0;
    for (size_t c = 3 * i; c < 3 * i + 3; ++c) {
        const double S = fromFixed(film.sums()[c]), Q = fromFixed(film.squares()[c]);
        const double m = S / n;
        const double spread = std::max(0.0, (Q - S * m) / (n - 1));  // s²
        e2 += spread / n / (m * m + kRelativeErrorEpsilon);
    }
    return e2 / 3;
}

std::vector<float> pixelVariances(const Film& film) {
    std::vector<float> out(film.sums().size(), 0.0f);
    for (size_t i = 0; i < out.size() / 3; ++i) {
        const int n = film.samples(i);
        if (n < 2) continue;
        for (size_t c = 3 * i; c < 3 * i + 3; ++c) {
            const double S = fromFixed(film.sums()[c]), Q = fromFixed(film.squares()[c]);
            out[c] = float(std::max(0.0, (Q - S * (S / n)) / (n - 1)) / n);
        }
    }
    return out;
}

NoiseState activePixels(const Film& film, double threshold, std::vector<uint8_t>& active, int maxPasses) {
    const int w = film.width(), h = film.height();
    const size_t count = size_t(w) * size_t(h);
    active.assign(count, 0);
    NoiseState state;
    std::vector<double> e2(count);
    for (size_t i = 0; i < count; ++i) e2[i] = pixelRelativeVariance(film, i);
    for (size_t i = 0; i < count; ++i) state.meanSquared += e2[i];
    state.meanSquared /= double(count);
    const bool deciding = threshold > 0 && film.passes() >= kNoiseMinPasses;
    const double bound = threshold * threshold;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            if (film.samples(i) != film.passes()) continue;  // stopped before
            double sum = 0;
            int n = 0;
            for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy)
                for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx, ++n)
                    sum += e2[size_t(yy) * size_t(w) + size_t(xx)];
            const double mean = sum / n;
            if (deciding && mean <= bound) continue;
            active[i] = 1;
            ++state.active;
            if (maxPasses > 0 && threshold > 0) {
                const double passes = film.passes(), cap = std::max(0.0, maxPasses - passes);
                state.samplesLeft += std::isfinite(mean) ? std::min(cap, passes * std::max(0.0, mean / bound - 1)) : cap;
            }
        }
    return state;
}

}  // namespace brume
