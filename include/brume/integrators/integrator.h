// An integrator estimates the radiance reaching the camera through one film position.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>
#include "brume/integrators/path_stats.h"
#include "brume/integrators/splat_list.h"
#include "brume/math/fixed_sum.h"
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

class Scene;

// A pass as its integrator hears of it after the fact.
struct PassSummary {
    int pass = 0;
    bool complete = false;  // false: abandoned, its samples thrown away
    PathStats totals;       // its tiles' counters, summed in tile order (complete passes only)
    // The pass's own image (complete passes only): one sample per pixel, row-major, and the
    // splats of its tiles in tile order. Under adaptive stopping (renderer.h) the pixels that
    // stopped have black samples here, and the splats are as made; no integrator learns from
    // such passes (Integrator::learning).
    int width = 0, height = 0;
    const Spectrum* radiance = nullptr;
    const SplatList* splats = nullptr;
    int splatLists = 0;
    // Wall time: the seconds the pass took, and the render's time budget (0: none, as when the
    // passes are counted or one MPI rank renders them one by one). For choices that a time
    // budget makes depend on the machine's speed anyway (AllocationPlanner::startDuel).
    double seconds = 0, timeBudget = 0;
};

// Adds a complete pass's image to exact sums (3 per pixel) as the film adds it: each sample
// and each splat on its own. What an integrator keeps of passes the image may leave out
// (Integrator::leftOut).
void addPassExact(const PassSummary& summary, std::vector<FixedSum>& sums);

// Russian roulette: the probability that a path with throughput beta (relative to `scale`)
// goes on after `events` scattering events.
//   Grey media: min(0.95, max β / scale), as always. The cap ends paths in non-absorbing media
//   and costs little variance there, since every channel's paths are equally long.
//   Coloured media: min(1, max β / scale). A cap c below 1 divides β by c at every event of a
//   path that absorbs nothing; where one channel's paths are much longer than the others'
//   (the densest channel of a coloured fog) its weights then grow faster than long paths
//   become rare: infinite variance (the coloured furnace's blue channel kept a median of 0.88
//   and pixels at 5 after 64 spp). After 64 events the cap is 0.99, to end paths that would
//   wander for ever in an unbounded non-absorbing haze (a weight growth of 1 % an event,
//   slower than any path-length decay seen in the furnaces). (On the channel average instead
//   of the maximum, paths end sooner, and the furnace's blue median fell back to 0.97.)
inline float rouletteSurvival(Spectrum beta, float scale, int events, bool coloured) {
    const float r = maxComponent(beta) / scale;
    return std::min(coloured ? (events < 64 ? 1.0f : 0.99f) : 0.95f, r);
}

class Integrator {
public:
    virtual ~Integrator() = default;
    // Radiance estimate through film point (fx, fy) in pixels, top-left origin, for an image
    // of width × height. Uses only `sampler` for randomness. Called from many threads at once.
    virtual Spectrum sample(const Scene& scene, float fx, float fy, int width, int height,
                            Sampler& sampler, PathStats& stats) const = 0;
    // Called on the renderer's thread, while no sample runs: before the first sample of pass
    // `pass` and after its last. What the integrator keeps from pass to pass (statistics that
    // steer later passes) changes only here, so every sample of a pass sees the same state.
    virtual void beginPass(const Scene& scene, int pass) {}
    // The sampler pass `pass` uses, given the one asked for (asked after beginPass), and the
    // pass's index in that sampler's sequence.
    virtual SamplerKind samplerFor(int pass, SamplerKind requested) const { return requested; }
    virtual uint64_t sequenceIndexFor(int pass, SamplerKind) const { return uint64_t(pass); }
    // Passes the image may leave out once the others far outnumber them (the efficiency-aware
    // tracer's pilot and its duel's loser, render/renderer.h finalImage): how many, and their
    // exact sums as the film adds them (3 per pixel); none by default.
    struct LeftOutPasses {
        int passes = 0;
        const std::vector<FixedSum>* sums = nullptr;
        double noise = 0;  // their variance per pass over the others' (0: not known)
        bool always = false;  // left out whatever their share (measured noisier: auto's duel)
        // Passes that rendered part of the image (auto's partial pilot pass,
        // AllocationPlanner::partialAt), left out always, besides the ones above; a film with
        // such a pass does not track noise (BdptOptions::partialPilot).
        int partialPasses = 0;
        const std::vector<FixedSum>* partialSums = nullptr;
    };
    virtual LeftOutPasses leftOut() const { return {}; }
    virtual void endPass(const Scene& scene, const PassSummary& summary) {}
    // Whether pass `pass` (asked before it starts) still teaches it from the pass's whole
    // image (its endPass reads every pixel: the planner's pilot and duel, light tracing's
    // learning passes, the guide's training and noise passes). Adaptive stopping
    // (renderer.h) stops no pixel while it does. None by default.
    virtual bool learning(int pass) const { return false; }
    // Under a target error for the whole image (renderer.h, RenderOptions::noiseWholeImage),
    // before each pass (and before learning() is asked about it): the render's expected
    // length in passes, from the film alone (pixel_noise.h, expectedPasses); −1 while not yet
    // estimated. Not called otherwise.
    virtual void expectPasses(int total) {}
    // What it keeps from pass to pass, as bytes for a checkpoint (empty: nothing), and back:
    // a render resumed from a checkpoint continues with the same state. loadState throws
    // std::runtime_error for bytes it did not write.
    virtual std::string saveState() const { return {}; }
    virtual void loadState(const std::string& state) {}
};

// An integrator that, besides the radiance through its own film position, deposits
// contributions at other pixels (light tracing, the t = 1 strategies of bidirectional path
// tracing). The renderer recognises it and passes the SplatList of the tile being rendered;
// splats end up in the film divided by the number of passes, like ordinary samples.
class SplattingIntegrator : public Integrator {
public:
    virtual Spectrum sampleWithSplats(const Scene& scene, float fx, float fy, int width, int height,
                                      Sampler& sampler, PathStats& stats, SplatList& splats) const = 0;
    // Outside render() there is nowhere for splats to go: they are made and thrown away.
    Spectrum sample(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                    PathStats& stats) const override;
};

}  // namespace brume
