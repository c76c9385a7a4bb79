// Adaptive stopping (`--noise-threshold E`): which pixels have reached a relative error E,
// estimated from the film's own passes (a film that tracks noise, film.h).
//
// Pixel p took part in n passes; per channel c its values per pass (sample and splats) sum to
// S and their squares to Q. The mean is m = S/n, the spread of one pass
// s² = (Q − S²/n)/(n − 1), and the mean's variance s²/n. Weighed as `brume bench`'s relative
// MSE weighs an error (x − r)² / (r² + 0.01), the pixel's expected relative squared error is
//   e² = mean_c (s_c²/n) / (m_c² + 0.01),
// so an image whose pixels all have e ≤ E has a relative MSE of about E² or less. (Passes
// with Sobol numbers are not independent: their mean converges faster than s²/n says, so the
// estimate errs high and pixels stop late, never early for that reason.)
//
// One pixel's s² from a few passes is itself noisy, and it is correlated with the pixel's
// mean: where rare samples are bright, a pixel whose bright samples have not yet come looks
// both darker and converged. Stopping on it biases the image low (the furnace: −0.5 % with
// pt, −0.75 % with bdpt at E = 0.15, z ≈ 3–4 over 32 renders). So a pixel stops when the mean
// e² of its 3×3 neighbourhood is at most E², its own e² weighing 1/9 (the same furnace:
// +0.14 % and −0.10 %, within noise), and only after kNoiseMinPasses passes. The price: a
// lone noisy pixel among clean ones may stop at up to 3E.
//
// A function of the film alone: the same bits for any thread count and after a resume.
#pragma once
#include <cstdint>
#include <vector>

#include "brume/film/film.h"

namespace brume {

constexpr int kNoiseMinPasses = 16;
constexpr double kRelativeErrorEpsilon = 0.01;  // as bench's relative MSE

// e² of pixel i (y·width + x); +inf with fewer than 2 passes. The film must track noise.
double pixelRelativeVariance(const Film& film, size_t i);

// The variance of each pixel's mean, s²/n per channel (3 floats per pixel, row-major, top row
// first; 0 where a pixel has fewer than 2 passes): the `Variance` layer of `--aov variance`.
std::vector<float> pixelVariances(const Film& film);

struct NoiseState {
    int active = 0;           // pixels that go on
    double meanSquared = 0;   // the mean e² over the image: its estimated relative MSE
    // The pixel samples the active pixels still need, as e² ∝ 1/n says: a pixel with n
    // passes whose neighbourhood mean is w needs n·(w/E² − 1) more, at most maxPasses − n.
    double samplesLeft = 0;
};

// For a film that tracks noise: active[i] = 1 for the pixels that took part in every pass so
// far and have not reached `threshold` (with fewer than kNoiseMinPasses passes, or
// threshold ≤ 0, every pixel that took part in every pass). Resizes `active`. `maxPasses`
// bounds samplesLeft (0: no estimate).
NoiseState activePixels(const Film& film, double threshold, std::vector<uint8_t>& active, int maxPasses = 0);

}  // namespace brume
