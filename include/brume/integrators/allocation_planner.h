// The efficiency-aware allocation (`--integrator auto`, the default): the bidirectional
// tracer starts with the pilot allocation (every strategy on), learns from its first passes
// what each candidate allocation (bdpt_allocation.h) would cost and how noisy it would be,
// and renders the rest with the one of best estimated efficiency 1 / (relative variance ×
// cost). After Grittmann, Yazici, Georgiev and Slusallek, "Efficiency-aware multiple
// importance sampling for bidirectional rendering algorithms" (SIGGRAPH 2022).
//
// Schedule, by the film's pass index:
//   passes 0–1    pilot (0–3 in single scattering, below), with independent samples; pass
//                 0 gives each pixel's weight 1/(Ī² + ε) (Ī: its value box-filtered 5×5;
//                 ε = 0.01 as in `brume bench`'s relative MSE); the spread of the pilot
//                 passes' values gives the pilot's own relative variance V_pilot;
//   pass 1        also: every second pixel in x and y records its contributions, for the
//                 second moment M_j of each candidate j (allocation_statistics.h), and each
//                 part of a sample counts its rays (passes 1–3 count, and record nothing, in
//                 single scattering, where no estimate decides); with a partial pilot
//                 (partialAt) only the recording pixels render their camera side in both
//                 passes, the image always leaves them out, and pass 0 counts the rays;
//   passes 2–17   (4–19) the duel (allocation_duel.h), where the pilot rated the best
//                 bidirectional allocation with light subpaths and the path tracer within
//                 16× of each other:
//                 the two render 8 passes each, in turn, with the sampler asked for (each
//                 from Sobol index 0: an aligned block), and the better at equal cost
//                 (relative variance of 4 passes × the cost its own passes counted,
//                 sample_cost.h) renders the rest if it is the pilot's choice or better than
//                 that by 2× (the pilot sees heavy tails, the duel's median over pixel groups
//                 does not) — and the path tracer only if its mean is within 10 % of the
//                 other's (black where only light subpaths reach would look noiseless). The
//                 pilot's estimate cannot see what Owen-scrambled Sobol gives each (34× the
//                 path tracer, 3.9× the bidirectional tracer, at 64 spp on one lamp in fog);
//                 the duel measures it;
//                 In full transport a render whose passes are known (--spp) and leave
//                 fewer than 16 after the duel holds none: the pilot's choice stands; so
//                 does one under a time budget where a contender's 8 passes would take
//                 over a tenth of it (startDuel);
//   then          the chosen allocation, for good, with the sampler asked for, continuing
//                 its own sequence (sequenceIndex).
// In single scattering (learnedShare) the bidirectional tracer also learns light tracing's
// share of one-event paths in passes 0–3, its pilot (direct_light_tracing.h: the same passes, the same
// independent numbers and plain weights), and its camera walk passes through media at its
// one scattering event, as the fixed tracer's does. The pilot's estimate knows neither, so
// the duel always takes place, between the pilot's allocation (every strategy) with the
// learned share and the path tracer, and decides alone: both make every strategy, so no
// tail is left to one of them, and the margin that guards against the duel's blindness to
// tails is not needed. Where the bidirectional tracer wins, its image leaves out the
// pilot's passes too (plain weights: noisier).
// Estimated relative variance of one pass: V_j = V_pilot + (M + C − Q)_j − (M + C − Q)_pilot,
// summed over pixels and channels with the weights (allocation_statistics.h: the second
// moment, the products within a sample, the squared mean of each pixel's own part; the
// covariance between path lengths is taken as the pilot's). The path tracer is another estimator, not a
// re-weighting of the pilot's samples (in coloured media it even picks its channels
// otherwise): each recording pixel also renders one path-tracer sample L that goes nowhere
// but into Σ w·L², and V_pt = V_pilot + E[w·L²] − E[w·F²], F the pilot's pixel values. That
// is for coloured media only: in grey media the path tracer is the same estimator as "pt+ea"
// (the same strategies in the bidirectional tracer), whose re-weighted moment also sees the
// rare paths the pilot's light subpaths found and a probe of a few passes misses (a caustic
// that the path tracer finds only by chance would look less noisy, being black there) —
// unless the path tracer has a strategy of its own (distances by the solid angle of an
// emissive triangle, integrators/solid_angle_segment.h), when it is probed as in coloured
// media; there too the probe is set aside for pt+ea's moment when its mean falls more than
// 10 % short of the pilot's, and pt+ea's bias (an infinite moment) rules it out.
// Cost: the rays each part of the pilot's samples traced, each part weighted by the
// measured cost of one of its rays (sample_cost.h), the parts a candidate drops left out and
// general connections scaled by their probability; a deterministic stand-in for time, which
// would make the image depend on the machine's load. Every number comes from completed
// passes summed in tile order, so the choice is the same for any thread count, and it is
// kept in checkpoints (saveState).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "brume/integrators/allocation_duel.h"
#include "brume/integrators/allocation_statistics.h"
#include "brume/integrators/bdpt_allocation.h"
#include "brume/math/fixed_sum.h"

namespace brume {

class AllocationPlanner {
public:
    // The pilot: one pass for the pixel weights, then passes that collect statistics: one in
    // full transport; three in single scattering, where light tracing's share learns in the
    // same four passes (direct_light_tracing.h). (Three in full transport too until the pilot
    // was measured to take a quarter of a 4-s render: with one, the default gained 1.11× in
    // the geometric mean over the six validation scenes, docs/results.md.)
    static constexpr int kWeightPasses = 1, kCollectPassesFull = 1, kCollectPassesSingle = 3;
    int collectPasses() const { return learnedShare_ ? kCollectPassesSingle : kCollectPassesFull; }
    int decisionPass() const { return kWeightPasses + collectPasses() - 1; }  // the pilot's choice after it
    // The duel's passes (allocation_duel.h), one contender after the other, and the last pass
    // after which the allocation may still change (at most kMaxLastDecisionPass).
    int duelStart() const { return decisionPass() + 1; }
    int lastDecisionPass() const { return duelStart() + 2 * AllocationDuel::kPasses - 1; }
    static constexpr int kMaxLastDecisionPass = kWeightPasses + kCollectPassesSingle + 2 * AllocationDuel::kPasses - 1;

    // learnedShare: in single scattering, where the bidirectional tracer learns light
    // tracing's share (direct_light_tracing.h), the duel's bidirectional contender is the
    // pilot's allocation with that share, and the duel alone decides (decideDuel).
    // plannedPasses: the passes the render will take (0: not known); in full transport the
    // duel is held only if at least 2·AllocationDuel::kPasses passes follow it (startDuel).
    // partialPilot: in full transport, the pilot's passes render only what its recording
    // pixels need (partialAt), where the render is long enough (kPartialFrom).
    explicit AllocationPlanner(ConnectMode connect, bool learnedShare = false, int plannedPasses = 0,
                               bool partialPilot = false);
    bool learnedShare() const { return learnedShare_; }
    // How often that contender traces a light subpath (for the report); told before each pass.
    void setLightShare(double q) { lightShare_ = q; }
    // Whether the path tracer is an estimator of its own rather than "pt+ea" re-weighted, so
    // that its probe samples (below) measure it: in coloured media, and where it has a
    // strategy the bidirectional tracer lacks (distances by an emitter's solid angle). Told
    // before each pass.
    void setPathTracerProbe(bool on) { probe_ = on; }
    bool pathTracerProbe() const { return probe_; }

    // The allocation for pass `pass`, and whether that pass records statistics at pixel (x, y).
    const BdptAllocation& allocationFor(int pass) const;
    bool collects(int pass) const { return pilotChoice_ < 0 && pass >= kWeightPasses && pass <= decisionPass(); }
    // Whether the pilot's recording pixels record contributions for the candidates' estimates:
    // not in single scattering, where the duel decides alone (the header) and the estimates
    // would serve only --stats (recording made a pilot pass 1.4–1.6× as long on two
    // validation scenes).
    bool ratesCandidates() const { return !learnedShare_; }
    // The pilot passes sample independently (their spread measures the pilot's variance);
    // the rest with the sampler asked for.
    SamplerKind samplerFor(int pass, SamplerKind requested) const {
        return pass <= decisionPass() ? SamplerKind::Independent : requested;
    }
    static bool collectsPixel(int x, int y) { return (x & 1) == 0 && (y & 1) == 0; }
    // Whether pass `pass` is a partial pilot pass: only the recording pixels render their
    // camera side (camera walk, light and general connections), while every pixel traces its
    // light subpath, whose camera connections reach only the recording pixels. Those pixels'
    // values are then whole pass values, as the pixel weights (box-filtered over recording
    // pixels alone), the statistics and the spread that measures V_pilot need; the others are
    // not, so the image leaves these passes out always (leftOut). Why: the pilot's two passes
    // of every strategy took 10–25 % of a 4-s render at 160×120; the camera side is about 3/4
    // of a pilot pass's rays. Only in full transport (single scattering's pilot passes are
    // light tracing's learning passes, which need whole images), and where a render is known
    // to be long enough (at least kPartialFrom passes, or a time budget) that the pilot's
    // passes would be outnumbered and left out of a Sobol image anyway (renderer.h,
    // kLeftOutRatio).
    static constexpr int kPartialFrom = 16;
    bool partialAt(int pass) const { return partial_ && pass <= decisionPass() && pilotChoice_ < 0; }
    // The index of pass `pass` in the sequence of a sampler of kind `kind`. With Sobol the
    // pilot's passes (independent numbers) take none; each of the duel's contenders starts at
    // 0 (an aligned block of 8), and the allocation chosen continues its own sequence: the
    // passes the image keeps are then indices 0, 1, 2, … of one sequence, whose power-of-two
    // prefixes are whole nets (on a panel light in fog, 128 passes from 0 had a third of the
    // error of 143 passes from 8). Independent numbers are indexed by the pass itself (two
    // passes with one index would repeat their numbers). Known when the pass starts.
    uint64_t sequenceIndex(int pass, SamplerKind kind) const {
        if (kind != SamplerKind::Sobol || pass <= decisionPass()) return uint64_t(pass);
        if (!dueling()) return uint64_t(pass - duelStart());
        if (pass <= lastDecisionPass()) return uint64_t((pass - duelStart()) % AllocationDuel::kPasses);
        return uint64_t(pass - duelStart() - AllocationDuel::kPasses);
    }
    // Once decided: the passes the image may leave out (the pilot's and the duel's loser's;
    // with the path tracer's duel passes when the bidirectional one won, the pilot's stay) and
    // their exact sums as the film keeps them (renderer.h, finalImage).
    int leftOutPasses() const { return chosen_ >= 0 ? leftOutPasses_ : 0; }
    const std::vector<FixedSum>& leftOutSums() const { return leftOut_[0]; }
    // Their relative variance per pass over the chosen allocation's, from the duel (0 if
    // there was none: unknown).
    double leftOutNoise() const;
    // All of it for the image (Integrator::leftOut): always left out where noisier per pass.
    Integrator::LeftOutPasses leftOut() const;
    // Whether the pass that renders now is the pilot's allocation (with the learned share,
    // once decided: the bidirectional contender).
    bool pilotAllocationAt(int pass) const { return allocationFor(pass) == candidates_[size_t(pilot_)]; }
    PixelWeights weights() const { return PixelWeights{width_, height_, weights_.data()}; }
    // The recording pixel (x, y)'s sums of each candidate's contributions to its own value
    // (3 per candidate: accumulateMoments' `own`), over the passes that record: written, while
    // they render, only by the thread that renders that pixel. Their squares' part of each
    // candidate's variance is estimated in decide (allocation_statistics.h), and then only
    // that is kept (31 candidates × 3 floats per recording pixel: 190 MB at 1920×1080, by
    // count, while the pilot records).
    // (nullptr where the pilot is not recording.)
    float* ownParts(int x, int y) {
        const size_t cell = size_t(y / 2) * size_t((width_ + 1) / 2) + size_t(x / 2);
        const size_t at = cell * 3 * candidates_.size();
        return x >= 0 && y >= 0 && x < width_ && y < height_ && at < ownParts_.size() ? ownParts_.data() + at : nullptr;
    }
    const std::vector<BdptAllocation>& candidates() const { return candidates_; }

    void endPass(const PassSummary& summary);

    bool decided() const { return chosen_ >= 0; }
    const BdptAllocation& chosen() const { return candidates_[size_t(chosen_ < 0 ? pilot_ : chosen_)]; }
    // Whether the best bidirectional allocation met the path tracer in a duel (decided or not).
    bool dueling() const { return duelists_[0] >= 0; }
    // The duel's contenders (0: bidirectional, 1: the path tracer; candidate indices), and
    // once both rendered, each one's efficiency as the duel measured it.
    int duelist(int c) const { return duelists_[c]; }
    // Whether pass `pass` is one of the path tracer's duel passes, the index-th of its
    // kPasses or later.
    bool pathTracerDuelPass(int pass, int fromIndex) const {
        if (!dueling() || pilotChoice_ < 0 || pass < duelStart() || pass > lastDecisionPass()) return false;
        const int k = pass - duelStart();
        return candidates_[size_t(duelists_[k / AllocationDuel::kPasses])].pathTracer && k % AllocationDuel::kPasses >= fromIndex;
    }
    double duelEfficiency(int c) const;
    // The duel's margin that overturns the pilot's choice (allocation_planner.cpp).
    double overturnMargin() const;
    int pilotSide() const;
    // One line: the choice and its estimated efficiency relative to the pilot's; and a table
    // of every candidate's estimated relative variance, cost and efficiency.
    std::string summaryLine() const;
    std::string report() const;

    std::string saveState() const;
    void loadState(const std::string& state);  // std::runtime_error if malformed

    // The estimates behind the choice (after it), per candidate.
    struct Estimate {
        double variance = 0, cost = 0, efficiency = 0;
    };
    const std::vector<Estimate>& estimates() const { return estimates_; }

private:
    void passImage(const PassSummary& summary, std::vector<float>& image) const;
    void decide();
    std::vector<double> ownSquares() const;
    void startDuel();
    void duelPass(const PassSummary& summary, const std::vector<float>& image);
    void decideDuel();
    void keepLeftOut();
    struct GroupDifference {
        double mean, median;
    };
    GroupDifference groupDifference(const double (&m)[AllocationMoments::kGroups][AllocationMoments::kCandidates], size_t j) const;
    double cost(const BdptAllocation& a) const;
    double duelCost(int c) const;
    std::string duelistName(int c) const;
    bool pilotLeftOut() const;
    // The pilot's passes that the image may leave out or keep (partial ones are always out).
    int pilotGroupPasses() const { return partial_ ? 0 : duelStart(); }
    double cost(const BdptAllocation& a, const PathCounts& counts, double samples) const;
    // Recording pixels, and what counts_ and samples_ are of a whole pass (pixels over
    // recording pixels with a partial pilot, which counts the recording pixels alone; else 1).
    double recordingPixels() const { return double((width_ + 1) / 2) * double((height_ + 1) / 2); }
    double countScale() const { return partial_ && width_ > 0 ? double(width_) * double(height_) / recordingPixels() : 1.0; }

    std::vector<BdptAllocation> candidates_;
    int pilot_ = 0;
    bool probe_ = false;
    bool learnedShare_ = false;
    int plannedPasses_ = 0;
    bool partial_ = false;                 // partialAt
    std::vector<FixedSum> partialSums_;    // the partial passes' exact sums (always left out)
    int partialPasses_ = 0;                // how many passes they are
    // Under a time budget (PassSummary): the pilot's first pass's seconds, the budget, and the
    // duel's estimated seconds per contender (startDuel; not in the saved state: checkpoints
    // and MPI ranks count passes, with no budget here).
    static constexpr double kDuelShare = 0.1;
    double firstPassSeconds_ = 0, timeBudget_ = 0, duelSeconds_ = 0;
    double pilotSeconds_ = 0;  // the pilot's passes' time, for the report
    double lightShare_ = 1.0;
    int pilotChoice_ = -1;          // the pilot's estimate's choice
    int chosen_ = -1;               // the final one (the duel's winner, if there was a duel)
    int duelists_[2] = {-1, -1};    // the best bidirectional allocation with light subpaths and the path tracer
    AllocationDuel duel_;
    // Exact sums of passes (3 per pixel): [0] the pilot's, [1] and [2] the duelists'; after
    // the choice [0] alone, what the image may leave out (keepLeftOut).
    std::vector<FixedSum> leftOut_[3];
    double pilotVariance_ = 0;  // V_pilot: the pilot's weighted relative variance of one pass
    int leftOutPasses_ = 0;
    int width_ = 0, height_ = 0;
    std::vector<double> sum_, sumSq_;  // per pixel and channel, over the pilot passes so far
    int passes_ = 0;                   // pilot passes in sum_
    std::vector<float> weights_;       // 3 per pixel
    std::vector<float> ownParts_;      // per recording pixel, candidate and channel (ownParts)
    std::vector<double> ownSquares_;   // per candidate, once the pilot's passes are in (ownSquares)
    AllocationMoments moments_;  // the pilot's passes' sums (PathStats::moments)
    PathCounts counts_;
    uint64_t samples_ = 0;
    int collected_ = 0;
    std::vector<Estimate> estimates_;
};

}  // namespace brume
