// Bidirectional path tracing in participating media (`--integrator bdpt`): a camera subpath
// and a light subpath (bdpt_subpaths.h), every (s, t) connection strategy (bdpt_strategies.h),
// MIS over all of them with densities that include the free-flight sampling in both
// directions (bdpt_mis.h). docs/mis.md derives the weights.
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include "brume/integrators/bdpt_allocation.h"
#include "brume/integrators/mis.h"
#include "brume/integrators/path_tracer.h"
#include "brume/scene/light_pixels.h"

namespace brume {

struct PathVertex;

// Tests: told of every weighted contribution, with the two subpaths as joined (for s = 1 the
// light "subpath" is the sampled light vertex alone) and the sample's hero channel (coloured
// media: the weight is then taken over channels too, times their count; bdpt_mis.h).
class BdptObserver {
public:
    virtual ~BdptObserver() = default;
    // equiAngular: the sample is the equi-angular variant (z(t−1) moved towards y(s−1)).
    virtual void onWeight(const PathVertex* light, int s, const PathVertex* camera, int t, float weight,
                          bool equiAngular, int hero) const = 0;
};

// Debugging, strategy images and tests: which strategy a render keeps, and who hears of
// every weight.
struct BdptHooks {
    // Only the strategy (s, t) contributes (s = −1: all), unweighted unless `weighted`. Random
    // numbers are drawn the same way whichever strategy is kept, so the weighted images of all
    // strategies add up to the full image for the same seed.
    int onlyS = -1, onlyT = -1;
    bool weighted = false;
    // With onlyS: 0 keeps only the free-flight variant of the strategy, 1 only its
    // equi-angular variant (a connection vertex placed towards the other subpath), −1 both.
    int onlyVariant = -1;
    const BdptObserver* observer = nullptr;
};

struct BdptOptions {
    // The user's settings.
    int maxDepth = -1;  // most scattering events on a full path; −1 = unlimited
    MisHeuristic heuristic = MisHeuristic::Power;
    // Light connections at medium vertices: Density = plain BDPT; EquiAngular = the camera
    // vertex z(t−1) is sampled equi-angularly towards y(s−1) instead of by free flight;
    // Mis = both variants, MIS-weighted (docs/mis.md).
    ConnectMode connect = ConnectMode::Density;
    // Equi-angular densities in the weights over the real, clipped segment (a ray cast each)
    // instead of the unbounded-ray stand-in; for measuring the difference (docs/results.md).
    bool exactEquiAngular = false;
    // Equi-angular variants of the general connections (s, t ≥ 2) too, not only of light
    // (s = 1) and camera (t = 1) connections. Their anchors are light-subpath vertices,
    // usually a mean free path from the ray, where the equi-angular density is nearly flat:
    // per unit time they lose (docs/results.md), so they are off unless asked for.
    bool generalEquiAngular = false;
    // The efficiency-aware tracer (`--integrator auto`): the allocation below is replaced pass
    // by pass by the planner's (allocation_planner.h): the pilot's, then the chosen one.
    // (Without the camera walk's pass-through at the last scattering event --max-depth allows,
    // which only equi-angular light connections cover and which a candidate may turn off.)
    bool efficiencyAware = false;
    // Light tracing's share of paths of one scattering event (MisSettings::directLightTracing):
    // < 0 learns it from the first passes (direct_light_tracing.h; the fixed tracer with light
    // tracing, all strategies); otherwise this factor (e.g. the learned one, for the strategy
    // images of a render).
    double directLightTracing = -1.0;
    // Path guiding (`--guiding on`, docs/path-guiding.md): the first PathGuide::kLastFitPass
    // passes are the guided path tracer's training passes; after them the camera walk
    // samples directions from the learned field and survives by it (guided survival). Not
    // with efficiencyAware.
    bool guiding = false;
    float guideShare = -1;  // ≥ 0: the guided share α in every cell, not learned (tests)
    // Next-event estimation towards emissive media with grids (volume_light_sampling.h), here
    // (grey scenes) and in the path tracer inside (auto's pt allocation, guiding's training
    // passes; PathTracerOptions::volumeLights).
    bool volumeLights = true;
    // With --connect mis, the path tracer inside (auto's and --allocation's "path tracer")
    // learns how often to make its light connections in media (connection_shares.h), from
    // its last duel passes, or its first passes once it renders for good
    // (IntegratorSettings::learnShares; sharesPassAt).
    bool learnShares = false;
    // efficiencyAware: the passes the render will take (0: not known, e.g. `--time`). In full
    // transport the duel is held only where at least as many passes follow it as it takes
    // (allocation_planner.h); a short render keeps the pilot's choice.
    int plannedPasses = 0;

    // Which strategies each sample makes, and how often (bdpt_allocation.h): every one, general
    // connections with probability 1/4, by default.
    BdptAllocation allocation;

    BdptHooks hooks;
    // Single scattering beside point and spot lights in homogeneous grey fog: the camera
    // family made by the path tracer inside and light tracing split by one weight per path
    // (one_event_split.h), where the fixed tracer makes every strategy. false: the generic
    // weights over every strategy (as --strategy-images splits them).
    bool oneEventSplit = true;
    // `--guiding auto` (efficiencyAware only): once the planner has chosen the path tracer for
    // good and its connection shares are learnt, the path tracer inside starts a guide where
    // enough passes follow (guide_start.h); its training passes stay in the image.
    bool guidingAuto = false;
    // efficiencyAware: the pilot's collecting pass renders the camera side at its recording
    // pixels alone and is always left out of the image (AllocationPlanner::partialAt), where
    // the render is long enough. Not for a film that tracks noise (adaptive stopping, the
    // variance layer): its per-pixel squares would hold that pass.
    bool partialPilot = false;
};

// Per pass, how many samples each kind of strategy contributed to (a nonzero weighted
// estimate), by variant: the statistics that flow back through the pass hooks, deterministic
// for any thread count (PathStats::counts, summed in tile order).
struct StrategyCounts {
    uint64_t freeFlight[4] = {}, equiAngular[4] = {};  // by StrategyKind (path_stats.h)
};

class AllocationPlanner;
class DirectLightTracing;

class BdptIntegrator : public SplattingIntegrator {
public:
    explicit BdptIntegrator(BdptOptions options);
    ~BdptIntegrator() override;
    Spectrum sampleWithSplats(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                              PathStats& stats, SplatList& splats) const override;
    void beginPass(const Scene& scene, int pass) override;
    SamplerKind samplerFor(int pass, SamplerKind requested) const override;
    uint64_t sequenceIndexFor(int pass, SamplerKind kind) const override;
    LeftOutPasses leftOut() const override;
    void endPass(const Scene& scene, const PassSummary& summary) override;
    bool learning(int pass) const override;
    void expectPasses(int total) override { guideStart_.expect(total); }
    // Whether this pass renders by the one-event split (BdptOptions::oneEventSplit).
    bool splitsOneEvent() const { return splitting_; }
    // Whether this (fixed) tracer's split checks light tracing's factor with the render's Sobol
    // numbers on `scene` (direct_light_tracing.h): passes that every rank must render.
    bool checksLightTracing(const Scene& scene) const;
    std::string saveState() const override;
    void loadState(const std::string& state) override;

    // The counts of the last complete pass, and of all complete passes so far.
    const StrategyCounts& lastPassCounts() const { return lastPass_; }
    const StrategyCounts& totalCounts() const { return total_; }
    // With BdptOptions::efficiencyAware, what it chose and why; else null.
    const AllocationPlanner* planner() const { return planner_.get(); }
    // Light tracing's learned share of one-event paths (direct_light_tracing.h).
    const DirectLightTracing* directLightTracing() const { return direct_.get(); }
    // The guide (`guiding`, or `guidingAuto` once started; else null), for --stats.
    const PathGuide* guide() const { return pathTracer_.guide(); }
    // The connection shares of the path tracer inside (BdptOptions::learnShares; else null),
    // for --stats.
    const ConnectionShares* connectionShares() const { return pathTracer_.connectionShares(); }
    // The probability that a sample of the pass in force traces a light subpath: with
    // --max-depth 1, where light subpaths serve light tracing alone, its learned subpath share
    // (DirectLightTracing::subpathShare; camera connections then count that many times in the
    // weights and 1/that in the image); 1 otherwise.
    double lightSubpathsMade() const;

private:
    // Whether the one-event split takes this render's samples (one_event_split.h).
    bool splitApplies(const Scene& scene) const;
    BdptOptions options_;
    StrategyCounts lastPass_, total_;
    std::unique_ptr<AllocationPlanner> planner_;
    PathTracer pathTracer_;  // for BdptOptions::pathTracer
    bool collecting_ = false;  // this pass records statistics (planner_)
    bool partialPass_ = false; // this pass is the planner's partial pilot pass (partialAt)
    std::unique_ptr<DirectLightTracing> direct_;
    bool learningDirect_ = false;  // this pass gathers direct_'s images
    bool usesShare_ = false;       // this pass weights with direct_'s share (auto: the pilot's allocation)
    bool guideTraining_ = false;   // this pass is one of the guide's training passes (pathTracer_)
    bool sharesPass_ = false;      // this pass teaches pathTracer_ its connection shares
    GuideStart guideStart_;        // guidingAuto: whether enough passes follow
    bool splitting_ = false;       // this render's samples take the one-event split (beginPass)
    bool checkingDirect_ = false;  // this pass checks direct_'s factor with Sobol numbers (the split)
    mutable std::vector<FixedSum> leftOutSums_;  // the guide's and direct_'s left-out passes together
    // Passes before the bidirectional tracer's own: the guide's training passes (16, or fewer
    // when its records filled up first).
    int guidePasses() const { return options_.guiding ? pathTracer_.guide()->trainingPasses() : 0; }
    // guidingAuto: whether the path tracer inside starts its guide before pass `pass`.
    bool guideStartsAt(int pass) const;
    // Whether the state holds the path tracer's (its guide's or its shares').
    bool keepsPathTracerState() const;
    std::string saveOwnState() const;
    void loadOwnState(const std::string& state);
    // Whether pass `pass` is one the path tracer inside learns its shares from, while they are
    // still learnt: its allocation is the path tracer's for good (after the planner's
    // choice), or it is one of the path tracer's last duel passes.
    bool sharesPassAt(int pass) const;
    // The pixels around a light's image (light_pixels.h) for this render's scene and film,
    // which the split's weights read: made by the first sample that asks, and kept while the
    // tracer lives (so that a pointer read by one thread stays valid).
    const LightPixels* lightPixelsFor(const Scene& scene, int width, int height) const;
    mutable std::mutex lightPixelsMaking_;
    mutable std::atomic<const LightPixels*> lightPixels_{nullptr};
    mutable std::vector<std::unique_ptr<LightPixels>> lightPixelTables_;
    // A sample by the one-event split (one_event_split.h).
    Spectrum sampleSplit(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                         PathStats& stats, SplatList& splats) const;
};

}  // namespace brume
