// Adaptive sampling (`--noise-threshold E`): which pixels take part in the next pass so that
// the image reaches an estimated relative error E soonest, estimated from the film's own
// passes (a film that tracks noise, film.h).
//
// Pixel p took part in n passes; per channel c its values per pass (sample and splats) sum to
// S and their squares to Q. The mean is m = S/n, the spread of one pass
// s² = (Q − S²/n)/(n − 1), and the mean's variance s²/n. Weighed as `brume bench`'s relative
// MSE weighs an error (x − r)² / (r² + 0.01), the pixel's expected relative squared error is
//   e² = mean_c (s_c²/n) / (m_c² + 0.01),
// and the image's relative MSE is about the mean of e² over its pixels. (Passes with Sobol
// numbers are not independent: their mean converges faster than s²/n says, so the estimate
// errs high and pixels stop late, never early for that reason.)
//
// Which pixels go on: not those above E, but as many passes per pixel as reach an image
// relative MSE of E² soonest. A pixel whose passes have relative variance σ² = n·e² has
// e² = σ²/n after n passes; the image's mean e² at a given number of samples is least with
// n ∝ σ (Lagrange: minimise Σ σ²/n subject to Σ n fixed): n* = K·σ. K is set so that the
// image's predicted mean e² is E²: a pixel going on to n* passes will have e²·n/n*, one that
// stops keeps its e². (With exact σ that is K = σ̄/E², σ̄ the mean of σ; with the robust σ
// below, K also corrects for the median being below the mean: without it the fog room ended
// 25–50 % above E² in its estimated relative MSE, a test scene at E = 0.03 at 0.042.) A pixel
// takes part in the next pass while n < n*, and once it stops it has stopped for good (its
// passes are then one prefix of its Sobol sequence). (Stopping each pixel at e ≤ E instead gives it n ∝ σ²
// passes: on the street 5 % of the pixels were still going on at 1024 passes, half the
// samples, and the image reached a given error 1.6–3.5× later than uniform sampling,
// docs/adaptive-sampling.md.)
//
// One pixel's σ² from a few passes is itself noisy and heavy tailed, and it is correlated with
// the pixel's mean: where rare samples are bright, a pixel whose bright samples have not come
// yet looks both darker and quieter. Deciding on it biased the furnace low (−0.5 % with pt,
// −0.75 % with bdpt, z ≈ 3–4 over 32 renders), and a pixel that had met a bright sample kept
// going while its neighbours stopped. So σ² is the median over the pixel's 5×5
// neighbourhood: one bright pixel moves it little, and the pixel's own passes are one of 25.
// No pixel stops before kNoiseMinPasses passes.
//
// Decisions are made at passes 16, 20, 24, 28, 32, 40, 48, … (every quarter of the power of
// two below, at least 4: noiseDecisionPass); in between, the pixels not stopped go on. (A
// decision reads every pixel's 5×5 neighbourhood; between decisions a pass costs what its
// pixels cost and a scan of the image.)
//
// Or, for the whole image (`--target-error E`, and `brume render`'s default rule): no pixel
// stops alone; at a decision pass every pixel stops once the image's mean e² is at most E².
// (Choosing passes per pixel does not pay in lit fog, where the relative noise is nearly the
// same everywhere, and it loses where a pixel's rare bright samples have not come:
// docs/adaptive-sampling.md.)
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
    // At a decision: the pixel samples the active pixels still need, n* − n each with n* at
    // most maxPasses; −1 between decisions (not estimated).
    double samplesLeft = -1;
};

// Whether a film with this many passes chooses its pixels anew (kNoiseMinPasses and on).
bool noiseDecisionPass(int passes);

// For a film that tracks noise: active[i] = 1 for the pixels that took part in every pass so
// far, and at a decision pass (with threshold E > 0) only those of them with fewer passes
// than their n*. Resizes `active`. `maxPasses` bounds samplesLeft.
NoiseState activePixels(const Film& film, double threshold, std::vector<uint8_t>& active, int maxPasses = 0);

// The length a render under a target error E for the whole image is expected to take, in
// passes: passes × meanSquared / E² (the error falling as 1/passes), at least `passes`, at
// most maxPasses (if > 0); −1 before 4 passes or without a finite estimate.
int expectedPasses(int passes, double meanSquared, double threshold, int maxPasses);

// The same for the whole image: at a decision pass (threshold E > 0) every pixel stops if the
// image's mean e² is at most E², and none otherwise; samplesLeft then counts the passes that
// would reach E² if the error falls as 1/passes (at most maxPasses).
NoiseState imageActive(const Film& film, double threshold, std::vector<uint8_t>& active, int maxPasses = 0);
// Its decision alone, on activePixels(film, 0, active) of a film with this many passes (the
// renderer has that estimate already).
NoiseState imageDecision(int passes, NoiseState estimate, double threshold, std::vector<uint8_t>& active, int maxPasses);

}  // namespace brume
