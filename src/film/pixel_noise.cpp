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

bool noiseDecisionPass(int passes) {
    if (passes < kNoiseMinPasses) return false;
    int top = 1;
    while (top * 2 <= passes) top *= 2;
    return passes % std::max(4, top / 4) == 0;
}

NoiseState activePixels(const Film& film, double threshold, std::vector<uint8_t>& active, int maxPasses) {
    const int w = film.width(), h = film.height();
    const size_t count = size_t(w) * size_t(h);
    active.assign(count, 1);
    NoiseState state;
    std::vector<float> spread(count);  // σ² = n·e², the relative variance of one pass
    for (size_t i = 0; i < count; ++i) {
        const double e2 = pixelRelativeVariance(film, i);
        state.meanSquared += e2 / double(count);
        spread[i] = float(std::min(e2 * film.samples(i), 1e30));
    }
    if (!(threshold > 0) || film.passes() < kNoiseMinPasses) {
        state.active = int(count);
        return state;
    }
    if (!noiseDecisionPass(film.passes())) {
        // Between decisions: the pixels that have not stopped go on.
        for (size_t i = 0; i < count; ++i) {
            active[i] = film.samples(i) == film.passes() ? 1 : 0;
            state.active += active[i];
        }
        return state;
    }
    // σ² as the median over the 5×5 neighbourhood, and σ's mean over the image.
    std::vector<double> sigma(count);
    double meanSigma = 0;
    float window[25];
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int n = 0;
            for (int yy = std::max(0, y - 2); yy <= std::min(h - 1, y + 2); ++yy)
                for (int xx = std::max(0, x - 2); xx <= std::min(w - 1, x + 2); ++xx)
                    window[n++] = spread[size_t(yy) * size_t(w) + size_t(xx)];
            std::nth_element(window, window + n / 2, window + n);
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            sigma[i] = std::sqrt(double(window[n / 2]));
            meanSigma += sigma[i] / double(count);
        }
    const double scale = meanSigma / (threshold * threshold);  // n* = σ · σ̄ / E²
    for (size_t i = 0; i < count; ++i) {
        const double target = sigma[i] * scale, n = film.samples(i);
        if (film.samples(i) != film.passes() || !(n < target)) {  // (stopped before, or now)
            active[i] = 0;
            continue;
        }
        ++state.active;
        if (maxPasses > 0) state.samplesLeft += std::max(0.0, std::min(target, double(maxPasses)) - n);
    }
    return state;
}

}  // namespace brume
