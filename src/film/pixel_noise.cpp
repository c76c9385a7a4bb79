#include "brume/film/pixel_noise.h"

#include <algorithm>
#include <cmath>

namespace brume {

namespace {

// s²/n of channel value c (3·pixel + channel) of a pixel with n ≥ 2 passes, and its mean.
double meanVariance(const Film& film, size_t c, int n, double* mean) {
    const double S = fromFixed(film.sums()[c]), Q = fromFixed(film.squares()[c]);
    *mean = S / n;
    return std::max(0.0, (Q - S * *mean) / (n - 1)) / n;
}

}  // namespace

double pixelRelativeVariance(const Film& film, size_t i) {
    const int n = film.samples(i);
    if (n < 2) return HUGE_VAL;
    double e2 = 0, m;
    for (size_t c = 3 * i; c < 3 * i + 3; ++c) e2 += meanVariance(film, c, n, &m) / (m * m + kRelativeErrorEpsilon);
    return e2 / 3;
}

std::vector<float> pixelVariances(const Film& film) {
    std::vector<float> out(film.sums().size(), 0.0f);
    double m;
    for (size_t i = 0; i < out.size() / 3; ++i) {
        const int n = film.samples(i);
        if (n < 2) continue;
        for (size_t c = 3 * i; c < 3 * i + 3; ++c) out[c] = float(meanVariance(film, c, n, &m));
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
    NoiseState state;
    // The pixels not stopped before; a stopped pixel stays stopped.
    active.resize(count);
    std::vector<double> e2(count);
    for (size_t i = 0; i < count; ++i) {
        e2[i] = pixelRelativeVariance(film, i);
        state.meanSquared += e2[i] / double(count);
        active[i] = film.samples(i) == film.passes() ? 1 : 0;
        state.active += active[i];
    }
    if (!(threshold > 0) || !noiseDecisionPass(film.passes())) return state;
    // A decision: σ² = n·e² (the relative variance of one pass) as the median over the 5×5
    // neighbourhood.
    std::vector<double> sigma(count);
    float window[25];
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int n = 0;
            for (int yy = std::max(0, y - 2); yy <= std::min(h - 1, y + 2); ++yy)
                for (int xx = std::max(0, x - 2); xx <= std::min(w - 1, x + 2); ++xx) {
                    const size_t j = size_t(yy) * size_t(w) + size_t(xx);
                    window[n++] = float(std::min(e2[j] * film.samples(j), 1e30));
                }
            std::nth_element(window, window + n / 2, window + n);
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            sigma[i] = std::sqrt(double(window[n / 2]));
        }
    // n* = K·σ, K such that the image's predicted mean e² is E²: a pixel that goes on to n*
    // passes will have e²·n/n*; one that stops (σ = 0, or stopped before) keeps its e².
    double kept = 0, going = 0;  // (each summed over the image, / pixel count)
    for (size_t i = 0; i < count; ++i) {
        if (active[i] && sigma[i] > 0) going += e2[i] * film.samples(i) / sigma[i] / double(count);
        else kept += e2[i] / double(count);
    }
    const double bound = threshold * threshold;
    const double scale = bound > kept ? going / (bound - kept) : HUGE_VAL;
    state.samplesLeft = 0;
    for (size_t i = 0; i < count; ++i) {
        const double target = sigma[i] * scale, n = film.samples(i);
        if (!active[i]) continue;
        if (!(n < target)) {
            active[i] = 0;
            --state.active;
        } else if (maxPasses > 0) {
            state.samplesLeft += std::max(0.0, std::min(target, double(maxPasses)) - n);
        }
    }
    return state;
}

int expectedPasses(int passes, double meanSquared, double threshold, int maxPasses) {
    if (passes < 4 || !std::isfinite(meanSquared) || !(threshold > 0)) return -1;
    double n = std::ceil(passes * meanSquared / (threshold * threshold));
    n = std::max(n, double(passes));
    if (maxPasses > 0) n = std::min(n, double(maxPasses));
    return int(std::min(n, 1e9));
}

NoiseState imageActive(const Film& film, double threshold, std::vector<uint8_t>& active, int maxPasses) {
    return imageDecision(film.passes(), activePixels(film, 0.0, active), threshold, active, maxPasses);
}

NoiseState imageDecision(int passes, NoiseState state, double threshold, std::vector<uint8_t>& active, int maxPasses) {
    if (!(threshold > 0) || !noiseDecisionPass(passes)) return state;
    const double bound = threshold * threshold, n = passes;
    if (state.meanSquared <= bound) {
        std::fill(active.begin(), active.end(), uint8_t(0));
        state.active = 0;
        state.samplesLeft = 0;
        return state;
    }
    const double needed = maxPasses > 0 ? std::min(n * state.meanSquared / bound, double(maxPasses)) : n * state.meanSquared / bound;
    state.samplesLeft = std::max(0.0, needed - n) * double(state.active);
    return state;
}

}  // namespace brume
