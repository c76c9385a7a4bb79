// Renders an image in passes of one sample per pixel. Within a pass the image is cut into
// 16×16 tiles that persistent worker threads take from an atomic counter; all workers meet
// at a barrier at the end of each pass. Every pixel sample uses its own
// Sampler(seed, y·width + x, pass): the jitter inside the pixel first (box filter), then
// whatever the integrator draws. No sample depends on which thread takes it and the film's
// sums are exact (film.h), so the same seed gives the same image for any thread count — and
// a film restored from a checkpoint after pass k continues to the same bits as one that never
// stopped, and passes rendered by several processes sum to the same bits as in one.
//
// A pass is rendered into a buffer of its own and added to the film only once all its tiles
// are done, so a pass can be abandoned half-way (RenderControl::dropInFlight) without a trace.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>

#include "brume/integrators/integrator.h"
#include "brume/film/film.h"

namespace brume {

class Scene;

struct RenderOptions {
    int width = 0, height = 0;  // must match the film
    int spp = 16;               // passes to render (ignored when timeBudget > 0)
    double timeBudget = 0;      // seconds; > 0: whole passes until it is spent (at least one
                                // the image keeps: renderer.cpp)
    uint64_t seed = 0;
    SamplerKind sampler = SamplerKind::Sobol;  // sampling/sampler.h
    int threads = 0;            // 0 = std::thread::hardware_concurrency()
    // Which passes: by default the film's next ones (film.passes(), + 1, ...); with firstPass
    // ≥ 0, firstPass, firstPass + passStride, ... (a share of a render split over processes).
    int firstPass = -1;
    int passStride = 1;
    bool progress = false;      // progress bar on stderr
    // Adaptive sampling (film/pixel_noise.h): > 0 is the image's relative error to reach;
    // each pixel stops after the passes that reach it soonest, and the render once every
    // pixel has (or spp or the time budget ends it first). Pixels stop only between passes,
    // at the decision passes, after kNoiseMinPasses and the
    // integrator's learning passes (Integrator::learning): a stopped pixel takes no sample
    // and keeps no splat, and a pass's light-tracing splats are scaled by pixels / pixels
    // that took part (each such pixel traced one light subpath: the estimate stays
    // unbiased). Needs a film that tracks noise from its first pass (render() starts it on
    // an empty film), and a single process (firstPass < 0).
    double noiseThreshold = 0;
    // With a noise threshold: no pixel stops alone; the render ends at the first decision pass
    // where the whole image's estimated relative error is at most the threshold
    // (`--target-error`, the default rule of `brume render`; pixel_noise.h, imageActive).
    bool noiseWholeImage = false;
    // In the pixel that holds a point or spot light's image in fog and its eight neighbours,
    // film positions drawn in proportion to 1/(distance to the image) (scene/light_pixels.h);
    // false: uniform there too (tests that compare the two).
    bool lightPixels = true;
    // With a time budget, end where the image's passes are a count whose binary digits below
    // its top three are 0 (…, 256, 320, 384, 448, 512, …; imagePasses), at the last such count
    // before the budget at the pace so far, or at the budget. With Owen-scrambled Sobol numbers
    // and a nearly exact estimator (single scattering) the first n points of each pixel's
    // sequence are best stratified at those counts: between them the error of a 4-s render was
    // up to 3.7× that at the count before (docs/results.md, "A time budget ends on a block of
    // Sobol passes"). Set by `brume render --time` and `brume bench` in single scattering
    // (--max-depth 0 or 1); acts only with Sobol numbers, a time budget and no noise threshold.
    bool sobolBlocks = false;
};

// The smallest block of Sobol passes the image of n passes ends on (RenderOptions::sobolBlocks):
// 2^(⌊log2 n⌋ − 2), at least 1.
int sobolBlock(int n);

struct RenderStats {
    double seconds = 0;      // wall-clock time of the passes
    int passes = 0;          // passes completed by this call (= spp unless stopped early)
    uint64_t samples = 0;    // pixel samples of those passes, non-finite ones included
    uint64_t rays = 0;       // as counted by the integrator (PathStats::rays), same passes
    PathCounts counts;       // the integrator's own (PathStats), same passes
    TechniqueSums techniques;  // each technique's share of the image and its squares (--stats)
    uint64_t nonFinite = 0;  // samples and splats dropped for being NaN or infinite
    // With a noise threshold: pixels still going on after the last pass, and the image's
    // estimated relative MSE then (film/pixel_noise.h; every pixel, stopped or not).
    int activePixels = 0;
    double estimatedRelMse = 0;
};

// What render() watches and calls besides its options; every member is optional.
struct RenderControl {
    // Checked between passes: once it is true no new pass starts. The first pass always runs
    // unless dropInFlight is set. (Nor does it stop a render whose film holds partial passes
    // alone, auto's partial pilot: it goes on to the first whole pass, renderer.cpp.)
    const std::atomic<bool>* cancel = nullptr;
    // Also checked between tiles: once `cancel` is true the pass in flight is abandoned and
    // the film stays as it was after the last completed pass (possibly none); not a pass
    // that starts on partial passes alone.
    bool dropInFlight = false;
    // Called on the calling thread after each completed pass, with the film holding it and
    // the statistics so far (seconds included).
    std::function<void(const Film&, const RenderStats&)> afterPass;
};

// Adds passes to `film` (pass indices continue from film.passes(), so calling render() again
// on the same film refines it). Samples and splats that are not finite are dropped (they
// count as black) and counted, for the completed passes only. Throws std::invalid_argument
// for bad options (film size mismatch, spp < 1 without a time budget, negative threads) and
// rethrows anything an integrator or afterPass throws.
// The integrator hears of every pass through beginPass/endPass.
RenderStats render(const Scene& scene, Integrator& integrator, const RenderOptions& options, Film& film,
                   const RenderControl& control);
// The same with only a cancel flag (the pass in flight is finished).
RenderStats render(const Scene& scene, Integrator& integrator, const RenderOptions& options, Film& film,
                   const std::atomic<bool>* cancel = nullptr);
// An integrator made for this render alone.
inline RenderStats render(const Scene& scene, Integrator&& integrator, const RenderOptions& options, Film& film,
                          const std::atomic<bool>* cancel = nullptr) {
    return render(scene, integrator, options, film, cancel);
}

// The image of a render: the film's mean, or the mean without the passes the integrator
// says the image may leave out (Integrator::leftOut: the efficiency-aware tracer's pilot and
// its duel's loser), when leaving them out is the better estimate:
//   - always, where the integrator says so (Integrator::LeftOutPasses::always: after auto's
//     duel, where they are noisier per pass than the winner's, allocation_planner.cpp);
//   - when their variance per pass, v, exceeds the others' by more than 2 + k/n (k of them, n
//     others): the mean of n passes of variance 1 and k of variance v has variance
//     (n + k·v)/(n + k)², above 1/n exactly then (passes taken as independent);
//   - with Sobol numbers, once the others are at least kLeftOutRatio times as many: their
//     passes, stratified together, converge faster than 1/n, while the left-out ones keep
//     the error of as many independent samples (on a lamp in thin fog, 4 s: relative MSE
//     4.6e-6 with them in the image, 2.4e-6 without, docs/mis.md). That costs at most
//     1/(1 + kLeftOutRatio) of the samples.
// Under adaptive sampling each pixel decides by the passes it keeps (a pixel stopped early
// keeps them all when they are more than a small share of its own). Passes that rendered part
// of the image (LeftOutPasses::partialPasses: auto's partial pilot pass) are left out always,
// besides; such a film must not track noise (std::logic_error).
// A function of the film and the integrator's state alone: the same bits after any thread
// count, rank count or resume.
constexpr int kLeftOutRatio = 4;
std::vector<float> finalImage(const Film& film, const Integrator& integrator, SamplerKind sampler);

// How many passes finalImage averages (leaving out what it leaves out; per pixel under adaptive
// sampling it may differ: there the film's count less the passes left out always).
int imagePasses(const Film& film, const Integrator& integrator, SamplerKind sampler);

}  // namespace brume
