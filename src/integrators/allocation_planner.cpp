#include "brume/integrators/allocation_planner.h"

#include "brume/integrators/bdpt.h"
#include "brume/integrators/sample_cost.h"
#include "brume/integrators/state_bytes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>

namespace brume {

namespace {

constexpr double kRelativeEpsilon = 1e-2;  // as brume bench's relative MSE
constexpr int kBlur = 2;                   // the pixel weights' box filter radius
constexpr double kCombinedOverstates = 2;  // more than M through the pilot's weights overstates (decide)

}  // namespace

AllocationPlanner::AllocationPlanner(ConnectMode connect, bool learnedShare, int plannedPasses, bool partialPilot)
    : candidates_(candidateAllocations(connect)),
      learnedShare_(learnedShare),
      plannedPasses_(plannedPasses),
      partial_(partialPilot && !learnedShare && (plannedPasses == 0 || plannedPasses >= kPartialFrom)) {
    static_assert(AllocationMoments::kCandidates >= 31, "a moment per candidate");
    BdptAllocation pilot = pilotAllocation();
    if (connect == ConnectMode::Density) pilot.equiAngularLight = pilot.equiAngularCamera = false;
    for (size_t j = 0; j < candidates_.size(); ++j)
        if (candidates_[j] == pilot) pilot_ = int(j);
}

const BdptAllocation& AllocationPlanner::allocationFor(int pass) const {
    if (pass <= decisionPass() || pilotChoice_ < 0) return candidates_[size_t(pilot_)];
    if (dueling() && pass <= lastDecisionPass())
        return candidates_[size_t(duelists_[(pass - duelStart()) / AllocationDuel::kPasses])];
    return candidates_[size_t(chosen_ >= 0 ? chosen_ : pilotChoice_)];
}

// The pass's own image (samples and splats), 3 floats per pixel.
void AllocationPlanner::passImage(const PassSummary& s, std::vector<float>& image) const {
    image.assign(size_t(s.width) * size_t(s.height) * 3, 0.0f);
    for (size_t i = 0; i < size_t(s.width) * size_t(s.height); ++i)
        for (int c = 0; c < 3; ++c) image[3 * i + size_t(c)] = s.radiance[i][c];
    for (int l = 0; l < s.splatLists; ++l)
        for (const SplatList::Record& r : s.splats[l].records())
            for (int c = 0; c < 3; ++c) image[3 * (size_t(r.y) * size_t(s.width) + size_t(r.x)) + size_t(c)] += r.value[c];
}

void AllocationPlanner::endPass(const PassSummary& s) {
    if (!s.complete || !s.radiance) return;
    if (chosen_ < 0 && s.pass <= lastDecisionPass()) {
        const bool partial = partial_ && s.pass <= decisionPass();
        addPassExact(s, partial ? partialSums_ : leftOut_[s.pass < duelStart() ? 0 : 1 + (s.pass - duelStart()) / AllocationDuel::kPasses]);
        if (partial) ++partialPasses_;
    }
    if (s.pass > decisionPass()) {
        if (dueling() && chosen_ < 0 && s.pass <= lastDecisionPass() && weights_.size() == size_t(s.width) * size_t(s.height) * 3) {
            std::vector<float> image;
            passImage(s, image);
            duelPass(s, image);
        }
        return;
    }
    if (pilotChoice_ >= 0) return;
    if (s.pass == 0) pilotSeconds_ = 0;
    pilotSeconds_ += s.seconds;
    if (s.pass == 0) {
        width_ = s.width;
        height_ = s.height;
        sum_.assign(size_t(s.width) * size_t(s.height) * 3, 0.0);
        sumSq_ = sum_;
        ownParts_.assign(size_t((s.width + 1) / 2) * size_t((s.height + 1) / 2) * 3 * candidates_.size(), 0.0f);
        ownSquares_.clear();
        passes_ = 0;
        firstPassSeconds_ = s.seconds;
        timeBudget_ = s.timeBudget;
        // A partial pass's time as a whole pilot pass's: × the whole pass's counted cost (the
        // recording pixels' samples, × pixels over them) over the partial pass's (with the
        // other pixels' light subpaths).
        if (partial_) {
            const BdptAllocation& pilot = candidates_[size_t(pilot_)];
            const double recording = cost(pilot, s.totals.counts, recordingPixels());
            const double rest = cost(pilot, s.totals.partialLight, double(s.width) * double(s.height) - recordingPixels());
            if (recording > 0) firstPassSeconds_ *= recording * countScale() / (recording + rest);
        }
    }
    if (sum_.size() != size_t(s.width) * size_t(s.height) * 3 || passes_ != s.pass) return;  // (not from pass 0 on)
    std::vector<float> image;
    passImage(s, image);
    for (size_t i = 0; i < image.size(); ++i) {
        sum_[i] += image[i];
        sumSq_[i] += double(image[i]) * double(image[i]);
    }
    ++passes_;
    // With a partial pilot pass 0 counts the rays (of its recording pixels' samples: the other
    // pixels' light subpaths count apart, PathStats::partialLight), the collecting pass the
    // path tracer's probe.
    if (partial_ && s.pass == 0) counts_.add(s.totals.counts);
    if (s.pass == kWeightPasses - 1) {
        // Ī: the mean of the passes so far, box-filtered (over the recording pixels alone
        // with a partial pilot: every 5×5 box holds 4 to 9 of them).
        const int W = width_, H = height_;
        weights_.assign(sum_.size(), 0.0f);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double mean[3] = {0, 0, 0};
                int n = 0;
                for (int yy = std::max(0, y - kBlur); yy <= std::min(H - 1, y + kBlur); ++yy)
                    for (int xx = std::max(0, x - kBlur); xx <= std::min(W - 1, x + kBlur); ++xx) {
                        if (partial_ && !collectsPixel(xx, yy)) continue;
                        ++n;
                        for (int c = 0; c < 3; ++c) mean[c] += sum_[3 * (size_t(yy) * size_t(W) + size_t(xx)) + size_t(c)];
                    }
                for (int c = 0; c < 3; ++c) {
                    double m = mean[c] / (n * passes_);
                    weights_[3 * (size_t(y) * size_t(W) + size_t(x)) + size_t(c)] = float(1.0 / (m * m + kRelativeEpsilon));
                }
            }
    }
    if (!collects(s.pass) || weights_.empty()) return;
    moments_.add(s.totals.moments);
    if (partial_) {
        PathCounts probe;
        probe.pt = s.totals.counts.pt;
        counts_.add(probe);
    } else {
        counts_.add(s.totals.counts);
    }
    samples_ += partial_ ? uint64_t(recordingPixels()) : uint64_t(s.width) * uint64_t(s.height);
    if (++collected_ == collectPasses()) decide();
}

// M_j − M_pilot from the recording pixels' groups (AllocationMoments): the mean of the
// groups' differences, and their median. The caller takes the mean, unless it reads a variance
// below zero: then a few groups' spikes are in it (sixteen groups: with four, two fireflies in
// two groups put the median below zero too), and the median is taken where higher. A spike
// in one sample of the pilot that a candidate weighs less (one firefly of its equi-angular
// camera connection, counted 4× as every recording pixel is) would otherwise credit that
// candidate with a variance below zero: in forward-scattering fog, seed 81, every candidate
// with general connections always on read −4× the pilot's variance, was rated at the floor (a
// hundredth of the pilot's), 59× the pilot's efficiency, beyond the duel's range, and rendered
// at half the efficiency of the fixed methods. (The max of mean and median everywhere raised
// the estimates wherever groups disagree: beside a quad light one candidate's median estimate
// went from 0.98 to 1.24 of its measured variance.)
AllocationPlanner::GroupDifference AllocationPlanner::groupDifference(
    const double (&m)[AllocationMoments::kGroups][AllocationMoments::kCandidates], size_t j) const {
    constexpr int G = AllocationMoments::kGroups;
    double d[G], mean = 0;
    for (int g = 0; g < G; ++g) {
        d[g] = (m[g][j] - m[g][size_t(pilot_)]) * G;
        if (!std::isfinite(d[g])) return {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};  // (a biased candidate)
        mean += d[g] / G;
    }
    std::sort(d, d + G);
    return {mean, (d[(G - 1) / 2] + d[G / 2]) / 2};
}

// The cost of one pass of allocation a (sample_cost.h's units and weights), from the pilot's
// counts: the parts a candidate drops left out, general connections scaled by their
// probability.
//
// The path tracer: where it is probed, what its probe's samples count (sample_cost.h: its own
// parts, the solid-angle tables beside an emissive triangle among them; beside a panel in fog
// pt+ea × kPathTracerCost put it at 0.23× the pilot's cost, where its parts count 0.42× and
// its passes take 0.36×); elsewhere the cost of the bidirectional tracer's same strategies
// ("pt+ea") times kPathTracerCost, measured on bench_fog_room and area_hall (160x120,
// unlimited depth: pt:mis samples per second over those of `bdpt --allocation pt+ea`). (The
// duel counts both contenders' costs from their own passes.)
double AllocationPlanner::cost(const BdptAllocation& a) const { return cost(a, counts_, double(samples_)); }

// The same from counts of `samples` samples of the pilot's allocation.
double AllocationPlanner::cost(const BdptAllocation& a, const PathCounts& counts, double samples) const {
    using namespace bdpt_cost;
    constexpr double kPathTracerCost = 0.57;
    if (a.pathTracer && probe_ && counts.pt.samples > 0)  // its probe's own parts, per sample
        return pathTracerCost(counts.pt) / double(counts.pt.samples) * samples / std::max(1, collected_);
    if (a.pathTracer) {
        BdptAllocation same = a;
        same.pathTracer = false;
        return kPathTracerCost * cost(same, counts, samples);
    }
    const BidirectionalCounts& n = counts.bdpt;
    auto rays = [&](StrategyKind kind, bool ea) { return double(n.rays(kind, ea)); };
    const BdptAllocation& p = candidates_[size_t(pilot_)];
    // An ea-only allocation does not trace the free-flight variants its equi-angular ones replace.
    const bool onlyL = a.equiAngularOnly && a.equiAngularLight, onlyC = a.equiAngularOnly && a.equiAngularCamera;
    double c = kSample * samples + kCameraWalk * double(n.cameraWalkRays) +
               kLightConnection * (rays(StrategyKind::LightConnection, false) - (onlyL ? double(n.replaceableRays[0]) : 0.0));
    if (a.equiAngularLight) c += kLightConnectionEa * rays(StrategyKind::LightConnection, true);
    if (a.lightSubpaths) {  // (summed apart: the light subpath's parts)
        double light = kLightWalk * double(n.lightWalkRays);
        if (a.lightTracing) {
            light += kCameraConnection * (rays(StrategyKind::CameraConnection, false) - (onlyC ? double(n.replaceableRays[1]) : 0.0));
            if (a.equiAngularCamera) light += kCameraConnectionEa * rays(StrategyKind::CameraConnection, true);
        }
        if (p.generalConnection > 0)
            light += kGeneralConnection * a.generalConnection / p.generalConnection *
                     (rays(StrategyKind::SubpathConnection, false) + rays(StrategyKind::SubpathConnection, true));
        c += light;
    }
    return c / std::max(1, collected_);
}

// A contender's cost in the duel: one of its passes, counted from its own passes
// (sample_cost.h), so that what it made there (light tracing's share of light subpaths, the
// path tracer's solid-angle tables) is in it.
double AllocationPlanner::duelCost(int c) const {
    return duel_.cost(c, candidates_[size_t(duelists_[c])].pathTracer);
}

// Σ over pixels and channels of w · E[g_own]², per candidate, for one pass over the whole
// image (allocation_statistics.h): g_own the part of a pixel's value its own sample carries.
// E[g]² from one sample would be its square, which is E[g²]; so a recording pixel's mean
// part is multiplied by the mean of its (up to 8) recording neighbours', an independent
// estimate of nearly the same mean wherever the image is smooth on the scale of 4 pixels.
std::vector<double> AllocationPlanner::ownSquares() const {
    const size_t nc = candidates_.size();
    std::vector<double> q(nc, 0.0);
    const int cw = (width_ + 1) / 2, ch = (height_ + 1) / 2;
    if (ownParts_.size() != size_t(cw) * size_t(ch) * 3 * nc || collected_ == 0) return q;
    const double passes = collected_;
    auto part = [&](int cx, int cy, size_t j, int c) {
        return double(ownParts_[(size_t(cy) * size_t(cw) + size_t(cx)) * 3 * nc + 3 * j + size_t(c)]) / passes;
    };
    for (int cy = 0; cy < ch; ++cy)
        for (int cx = 0; cx < cw; ++cx) {
            const float* w = weights_.data() + 3 * (size_t(2 * cy) * size_t(width_) + size_t(2 * cx));
            for (size_t j = 0; j < nc; ++j)
                for (int c = 0; c < 3; ++c) {
                    double around = 0;
                    int n = 0;
                    for (int y = std::max(0, cy - 1); y <= std::min(ch - 1, cy + 1); ++y)
                        for (int x = std::max(0, cx - 1); x <= std::min(cw - 1, cx + 1); ++x)
                            if (x != cx || y != cy) {
                                around += part(x, y, j, c);
                                ++n;
                            }
                    if (n > 0) q[j] += double(w[c]) * part(cx, cy, j, c) * around / n;
                }
        }
    for (double& v : q) v *= 4.0;  // (every second pixel in x and y recorded)
    return q;
}

void AllocationPlanner::decide() {
    // The pilot's variance of one pass, measured: per pixel and channel, the unbiased sample
    // variance of its (independent) pilot passes, weighted. With a partial pilot at the
    // recording pixels alone (the others' values of the partial pass are not whole), ×4 as the
    // moments are.
    double pilotVariance = 0, pilotSecond = 0, pilotMean = 0;
    const double pixelScale = partial_ ? 4.0 : 1.0;
    for (size_t i = 0; i < sum_.size(); ++i) {
        const size_t pixel = i / 3;
        if (partial_ && !collectsPixel(int(pixel % size_t(width_)), int(pixel / size_t(width_)))) continue;
        const double n = passes_, v = (sumSq_[i] - sum_[i] * sum_[i] / n) / (n - 1);
        const double w = double(weights_[i]) * pixelScale;
        pilotVariance += w * std::max(v, 0.0);
        pilotSecond += w * sumSq_[i] / n;
        pilotMean += w * sum_[i] / n;
    }
    // In single scattering nothing was recorded: the duel decides (header), and the
    // candidates keep only their counted costs.
    if (!ratesCandidates()) {
        estimates_.assign(candidates_.size(), Estimate{});
        for (size_t j = 0; j < candidates_.size(); ++j) estimates_[j].cost = cost(candidates_[j]);
        pilotChoice_ = pilot_;
        pilotVariance_ = pilotVariance;
        startDuel();
        if (chosen_ >= 0) keepLeftOut();
        return;
    }
    // Each candidate's, by the difference of second moments: V_j = V_pilot + (M + C − Q)_j −
    // (M + C − Q)_pilot, Q = Σ w·E[g_own]² (allocation_statistics.h; the covariances
    // between path lengths that M + C leaves out are taken as the pilot's). Per pass over the
    // whole image: every second pixel in x and y recorded (×4). M two ways: from each
    // candidate's own strategies' samples (unbiased, but where the candidate leans on a
    // strategy whose rare large values the pilot leaves to others, a pilot that missed them
    // rates it far too well: a tenth of its variance in a glass-focused beam), and through the
    // pilot's weights (which sees those values where the other strategies find them, but
    // reads the densities the weights use, not those the light connection samples with: beside
    // a panel light it rates ea-only allocations 1.2–1.45× too noisy). The variance is the
    // first, unless the second is more than kCombinedOverstates times that: then the first
    // missed rare values, and the second is taken.
    const double scale = 4.0 / std::max(1, collected_);
    // (Summed once, when the pilot's passes are in; then only the sums are kept.)
    if (!ownParts_.empty()) {
        ownSquares_ = ownSquares();
        ownParts_ = std::vector<float>();
    }
    if (ownSquares_.size() != candidates_.size()) ownSquares_.assign(candidates_.size(), 0.0);
    const std::vector<double>& own = ownSquares_;
    auto difference = [&](size_t j) {
        const double q = own[j] - own[size_t(pilot_)];
        auto pick = [&](const GroupDifference& g) {
            const double mean = g.mean * scale;
            return pilotVariance + mean - q >= 0 ? mean : std::max(mean, g.median * scale);
        };
        const double alone = pick(groupDifference(moments_.candidate, j));
        const double combined = pick(groupDifference(moments_.combined, j));
        const bool missed = pilotVariance + combined - q > kCombinedOverstates * (pilotVariance + alone - q);
        return (missed ? combined : alone) - q;
    };
    estimates_.assign(candidates_.size(), Estimate{});
    int best = pilot_;
    for (size_t j = 0; j < candidates_.size(); ++j) {
        Estimate& e = estimates_[j];
        // (Kept above a hundredth of the pilot's where noise would make it negative.)
        // The path tracer: as "pt+ea" (the same strategies), or in coloured media and with
        // strategies of its own its probe, where that saw as much light as the pilot (header).
        double d = difference(j);
        if (candidates_[j].pathTracer) {
            BdptAllocation same = candidates_[j];
            same.pathTracer = false;
            for (size_t k = 0; k < candidates_.size(); ++k)
                if (candidates_[k] == same) d = difference(k);
            const bool probeSawAll = moments_.probeMean * scale >= 0.9 * pilotMean;
            if (probe_ && std::isfinite(d) && probeSawAll) d = moments_.probe * scale - pilotSecond;
        }
        e.variance = std::isfinite(d) ? std::max(pilotVariance + d, 1e-2 * pilotVariance) : std::numeric_limits<double>::infinity();
        e.cost = cost(candidates_[j]);
        e.efficiency = e.variance > 0 && e.cost > 0 && std::isfinite(e.variance) ? 1.0 / (e.variance * e.cost) : 0.0;
        if (e.efficiency > estimates_[size_t(best)].efficiency) best = int(j);
    }
    pilotChoice_ = best;
    pilotVariance_ = pilotVariance;
    startDuel();
    if (chosen_ >= 0) keepLeftOut();
}

// What the image may leave out, once the choice is final: the pilot's passes and the duel's
// loser's. When the bidirectional allocation won, the pilot's passes (rendered by every
// strategy, the winner's among them) stay, unless the winner carries light tracing's
// learned share, which the pilot's passes (c = 1) do not.
bool AllocationPlanner::pilotLeftOut() const { return !(dueling() && chosen_ == duelists_[0] && !learnedShare_); }

// Their variance per pass over the winner's, from the duel's batches of one pass (the
// pilot's passes: V_pilot each); 0 without a duel.
double AllocationPlanner::leftOutNoise() const {
    if (chosen_ < 0 || !dueling()) return 0.0;
    const int won = chosen_ == duelists_[0] ? 0 : 1;
    const double mine = duel_.variance(won, 0), loser = duel_.variance(1 - won, 0);
    const double theirs = pilotLeftOut() ? (pilotGroupPasses() * pilotVariance_ + AllocationDuel::kPasses * loser) /
                                               (pilotGroupPasses() + AllocationDuel::kPasses)
                                         : loser;
    return mine > 0 ? theirs / mine : 0.0;
}

// After a duel, passes noisier per pass than the winner's are left out whatever their share
// (renderer.h finalImage): the path tracer's, where it lost, are cheaper and noisier, with
// tails that its 8 passes rarely show. The plain mean, which the image kept while they were
// more than a fifth of the passes and less than 2 + k/n times noisier, had 1.38× the
// relative MSE of leaving them out in forward-scattering fog; weighing them by the duel's
// variances (inverse-variance blending, the winner's rate read from its batches) 1.18× there
// and 0.95× beside a panel light (against references, docs/results.md). Where the path tracer
// won, the bidirectional tracer's passes and the pilot's are less noisy per pass, and leaving
// them out cost 1.4–1.8× in the forward fog: they follow the rules for passes of unknown
// worth.
// The partial pilot passes (partialAt) are left out always, decided or not.
Integrator::LeftOutPasses AllocationPlanner::leftOut() const {
    Integrator::LeftOutPasses out;
    if (leftOutPasses() > 0) {
        out = Integrator::LeftOutPasses{leftOutPasses_, &leftOut_[0], leftOutNoise()};
        out.always = out.noise > 1;
    }
    if (partialPasses_ > 0) {
        out.partialPasses = partialPasses_;
        out.partialSums = &partialSums_;
    }
    return out;
}

// leftOut_: [0] the pilot's passes, [1] and [2] the duelists'; after the choice [0] holds
// what the image may leave out.
void AllocationPlanner::keepLeftOut() {
    std::vector<FixedSum> out;
    leftOutPasses_ = 0;
    auto add = [&](std::vector<FixedSum>& sums, int passes) {
        if (out.empty()) out = std::move(sums);
        else
            for (size_t i = 0; i < out.size() && i < sums.size(); ++i) out[i] += sums[i];
        leftOutPasses_ += passes;
    };
    if (pilotLeftOut()) add(leftOut_[0], pilotGroupPasses());
    if (dueling()) add(leftOut_[chosen_ == duelists_[0] ? 2 : 1], AllocationDuel::kPasses);
    for (std::vector<FixedSum>& v : leftOut_) v = std::vector<FixedSum>();
    leftOut_[0] = std::move(out);
}

// The pilot's estimate cannot see what the sampler gives each candidate (its passes use
// independent numbers). So the best bidirectional allocation by that estimate and the path
// tracer, where the estimate puts them within kDuelRange of each other, render
// AllocationDuel::kPasses passes each with the render's sampler (allocation_duel.h) and the
// better at equal cost wins. Out of that range, or where the path tracer is biased (no light
// subpaths where only they see the light: its estimate is 0), the pilot's choice stands.
void AllocationPlanner::startDuel() {
    constexpr double kDuelRange = 16;
    duelists_[0] = duelists_[1] = -1;
    chosen_ = pilotChoice_;
    // The bidirectional contender has light subpaths: the bidirectional tracer without them
    // ("pt+ea", "pt ea-only", "pt") makes the path tracer's strategies at more cost, so a duel
    // with it would measure the path tracer against itself (on a lamp in thin fog, where the
    // estimate of the tracer without light subpaths came within 1.1× of the best with them,
    // the duel met it and never saw light tracing, which the sampler put 1.3× ahead).
    int bidirectional = -1, pathTracer = -1;
    for (size_t j = 0; j < candidates_.size(); ++j) {
        if (!candidates_[j].pathTracer && !candidates_[j].lightSubpaths) continue;
        int& best = candidates_[j].pathTracer ? pathTracer : bidirectional;
        if (best < 0 || estimates_[j].efficiency > estimates_[size_t(best)].efficiency) best = int(j);
    }
    if (bidirectional < 0 || pathTracer < 0) return;
    // With light tracing's learned share (single scattering) the bidirectional contender is
    // the pilot's allocation (every strategy) with the share, which the pilot's estimate does
    // not know: it always meets the path tracer.
    if (learnedShare_) {
        duelists_[0] = pilot_;
        duelists_[1] = pathTracer;
        chosen_ = -1;
        return;
    }
    // A duel pays for its passes only through the passes after it, and in full transport it
    // overturns the pilot's choice only by 2×: in a render whose passes are known and fewer
    // than its own after it, the pilot's choice stands (the default 16 spp: 14 passes of it
    // instead of 8 + 6 of the two contenders, the choice left undecided).
    if (plannedPasses_ > 0 && plannedPasses_ < lastDecisionPass() + 1 + 2 * AllocationDuel::kPasses) return;
    const double b = estimates_[size_t(bidirectional)].efficiency, p = estimates_[size_t(pathTracer)].efficiency;
    if (!(b > 0 && p > 0 && std::max(b, p) <= kDuelRange * std::min(b, p))) return;
    // Under a time budget the duel's cost is its loser's passes (left out of the image, or kept
    // though dearer per unit of variance), and it pays only where it overturns the pilot's
    // choice, by 2×. It is held only if each contender's passes would take at most kDuelShare
    // of the budget (as much as the pilot may take at 4 s, docs/mis.md), their time
    // estimated from the pilot's first pass (which records nothing) × the estimated cost
    // relative to the pilot's. Measured at 4 s on the six validation scenes (docs/results.md):
    // the duel never overturned the pilot's choice in 24 renders, its loser's passes took
    // 9–20 % of the budget, and without it the default was 1.09× as efficient (side panel
    // 1.26×, forward fog 0.93×).
    if (timeBudget_ > 0 && firstPassSeconds_ > 0) {
        const double pilotCost = estimates_[size_t(pilot_)].cost;
        const double dearer = std::max(estimates_[size_t(bidirectional)].cost, estimates_[size_t(pathTracer)].cost);
        duelSeconds_ = AllocationDuel::kPasses * firstPassSeconds_ * (pilotCost > 0 ? dearer / pilotCost : 1.0);
        if (duelSeconds_ > kDuelShare * timeBudget_) return;
    }
    duelists_[0] = bidirectional;
    duelists_[1] = pathTracer;
    chosen_ = -1;
}

void AllocationPlanner::duelPass(const PassSummary& s, const std::vector<float>& image) {
    const int k = s.pass - duelStart(), c = k / AllocationDuel::kPasses, i = k % AllocationDuel::kPasses;
    if (duel_.passes(c) != i || (c == 1 && duel_.passes(0) != AllocationDuel::kPasses)) return;  // (in order only)
    duel_.addWork(c, s.totals, double(s.width) * double(s.height));
    duel_.addPass(c, i, image, weights_);
    if (c == 1 && i == AllocationDuel::kPasses - 1) decideDuel();
}

// 1 / (relative variance of the mean of 4 passes × the cost of 4 passes).
double AllocationPlanner::duelEfficiency(int c) const {
    const int top = AllocationDuel::kLevels - 1, batch = 1 << top;
    const double v = duel_.variance(c, top), cost = duelCost(c);
    return v > 0 && cost > 0 ? 1.0 / (v * batch * cost) : 0.0;
}

void AllocationPlanner::decideDuel() {
    double efficiency[2];
    for (int c = 0; c < 2; ++c) {
        efficiency[c] = duelEfficiency(c);
        if (std::getenv("BRUME_DEBUG_PLANNER"))
            std::fprintf(stderr, "duel: %s: V(1) %g V(2) %g V(4) %g, mean %g, cost %g, efficiency %g; pilot's V %g efficiency %g\n",
                         candidates_[size_t(duelists_[c])].name().c_str(), duel_.variance(c, 0), duel_.variance(c, 1),
                         duel_.variance(c, 2), duel_.mean(c), duelCost(c), efficiency[c], estimates_[size_t(duelists_[c])].variance,
                         estimates_[size_t(duelists_[c])].efficiency);
    }
    // The path tracer must see the light the pilot's choice sees (10 %, as its probe): black
    // where only light subpaths reach would look noiseless.
    const bool sawAll = duel_.mean(1) >= 0.9 * duel_.mean(0);
    // The pilot's estimate sees every path's second moment, heavy tails included (the rare
    // long paths of a forward-scattering fog: on one, it rated the path tracer's variance 32×
    // the bidirectional one's), but not the sampler; the duel sees the sampler, but as a
    // median over pixel groups of 8 passes not a tail those passes rarely reach (it rated the
    // path tracer 2× ahead there, where it was 4.5× behind at 4 s). So the duel overturns the
    // pilot's choice where it is decisive (overturnMargin).
    const int pilots = pilotSide();
    const double margin = efficiency[pilots] > 0 ? efficiency[1 - pilots] / efficiency[pilots] : HUGE_VAL;
    chosen_ = duelists_[margin > overturnMargin() ? 1 - pilots : pilots];
    if (!sawAll) chosen_ = duelists_[0];
    keepLeftOut();
}

// The contender on the pilot's side: the bidirectional one if the pilot chose it, else the
// path tracer (the pilot's choice, or the bidirectional tracer without light subpaths, which
// makes the path tracer's strategies).
int AllocationPlanner::pilotSide() const { return pilotChoice_ == duelists_[0] ? 0 : 1; }

// The duel's margin that overturns the pilot's choice: kOverturn where the pilot's estimate
// rates its choice that far ahead of the other contender or more (heavy tails, decideDuel), its
// own margin where it rates them closer: where the pilot cannot tell the two apart (beside a
// panel light, with the path tracer's cost counted from its probe: within 1.2×, while the
// sampler gave the path tracer 1.5×), the sampler decides. With light tracing's learned share
// the pilot's estimate does not rate the bidirectional contender, and both contenders make
// every strategy (no tail is left to one of them alone): the duel decides by itself (1).

double AllocationPlanner::overturnMargin() const {
    constexpr double kOverturn = 2;
    if (learnedShare_) return 1.0;
    const int pilots = pilotSide();
    const Estimate &mine = estimates_[size_t(duelists_[pilots])], &theirs = estimates_[size_t(duelists_[1 - pilots])];
    return theirs.efficiency > 0 ? std::min(kOverturn, mine.efficiency / theirs.efficiency) : kOverturn;
}

std::string AllocationPlanner::duelistName(int c) const {
    const std::string name = candidates_[size_t(duelists_[c])].name();
    if (!learnedShare_ || duelists_[c] != pilot_) return name;
    char buf[96];
    std::snprintf(buf, sizeof buf, " with light tracing's learned share (subpaths %.3g per sample)", lightShare_);
    return name + buf;
}

std::string AllocationPlanner::summaryLine() const {
    if (pilotChoice_ < 0) return "allocation: pilot (" + candidates_[size_t(pilot_)].name() + "), not yet decided";
    if (chosen_ < 0)
        return "allocation: " + candidates_[size_t(duelists_[0])].name() + " against " + candidates_[size_t(duelists_[1])].name() +
               " in a duel, not yet decided";
    const Estimate& e = estimates_[size_t(chosen_)];
    const Estimate& p = estimates_[size_t(pilot_)];
    char buf[512];
    const int chosenDuelist = dueling() ? (chosen_ == duelists_[0] ? 0 : 1) : -1;
    const std::string name = chosenDuelist >= 0 ? duelistName(chosenDuelist) : candidates_[size_t(chosen_)].name();
    if (ratesCandidates())
        std::snprintf(buf, sizeof buf, "allocation: %s (estimated efficiency %.2fx the pilot's: variance %.2fx, cost %.2fx)",
                      name.c_str(), p.efficiency > 0 ? e.efficiency / p.efficiency : 0.0, p.variance > 0 ? e.variance / p.variance : 0.0,
                      p.cost > 0 ? e.cost / p.cost : 0.0);
    else
        std::snprintf(buf, sizeof buf, "allocation: %s (estimated cost %.2fx the pilot's)", name.c_str(), p.cost > 0 ? e.cost / p.cost : 0.0);
    std::string out = buf;
    if (dueling()) {
        // Efficiency of each, from the duel: 1 / (V(4 passes) · cost).
        const int won = chosen_ == duelists_[0] ? 0 : 1;
        auto eff = [&](int c) { return duelEfficiency(c); };
        char overturn[96];
        std::snprintf(overturn, sizeof overturn, "%.2fx overturns the pilot's choice", overturnMargin());
        std::snprintf(buf, sizeof buf, "; in a duel with the render's sampler against %s: %.2fx its efficiency (%s)%s",
                      duelistName(1 - won).c_str(), eff(1 - won) > 0 ? eff(won) / eff(1 - won) : 0.0,
                      learnedShare_ ? "the better wins" : overturn, won == 0 && duel_.mean(1) < 0.9 * duel_.mean(0) ? ", which saw too little light" : "");
        out += buf;
    } else if (duelSeconds_ > kDuelShare * timeBudget_ && timeBudget_ > 0) {
        std::snprintf(buf, sizeof buf, "; no duel: a contender's %d passes would take about %.2f s, over %.0f%% of the %.3g-s budget",
                      AllocationDuel::kPasses, duelSeconds_, 100 * kDuelShare, timeBudget_);
        out += buf;
    }
    return out;
}

std::string AllocationPlanner::report() const {
    std::string out = summaryLine() + "\n";
    if (pilotChoice_ < 0) return out;
    const Estimate& p = estimates_[size_t(pilot_)];
    std::vector<size_t> order(candidates_.size());
    for (size_t j = 0; j < order.size(); ++j) order[j] = j;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return estimates_[a].efficiency > estimates_[b].efficiency; });
    char buf[512];
    const BidirectionalCounts& n = counts_.bdpt;
    // (A partial pilot counts its recording pixels alone: scaled to a whole pass.)
    auto perPass = [&](uint64_t count) { return double(count) * countScale() / std::max(1, collected_); };
    // Its time, where this process rendered it (not kept in checkpoints).
    if (pilotSeconds_ > 0) {
        std::snprintf(buf, sizeof buf, "  pilot: %d passes%s in %.3f s\n", decisionPass() + 1,
                      partial_ ? " (camera side at the recording pixels alone)" : "", pilotSeconds_);
        out += buf;
    }
    std::snprintf(buf, sizeof buf,
                  "  pilot, rays per pass: camera walk %.0f, light walk %.0f, light connections %.0f + %.0f "
                  "equi-angular, camera connections %.0f + %.0f, general connections %.0f; samples %.0f\n",
                  perPass(n.cameraWalkRays), perPass(n.lightWalkRays), perPass(n.rays(StrategyKind::LightConnection, false)),
                  perPass(n.rays(StrategyKind::LightConnection, true)), perPass(n.rays(StrategyKind::CameraConnection, false)),
                  perPass(n.rays(StrategyKind::CameraConnection, true)),
                  perPass(n.rays(StrategyKind::SubpathConnection, false)) + perPass(n.rays(StrategyKind::SubpathConnection, true)),
                  perPass(samples_));
    out += buf;
    if (!ratesCandidates()) {
        out += "  candidates not rated: in single scattering the duel decides\n";
    } else {
        std::snprintf(buf, sizeof buf, "  %-24s %12s %10s %12s   (relative to the pilot)\n", "candidate", "variance", "cost",
                      "efficiency");
        out += buf;
        for (size_t j : order) {
            const Estimate& e = estimates_[j];
            std::snprintf(buf, sizeof buf, "  %-24s %12.3g %10.3f %12.3g%s\n", candidates_[j].name().c_str(),
                          e.variance / p.variance, e.cost / p.cost, e.efficiency / p.efficiency,
                          int(j) == chosen_ ? "   chosen" : int(j) == pilotChoice_ ? "   pilot's choice" : int(j) == pilot_ ? "   pilot" : "");
            out += buf;
        }
    }
    if (dueling() && duel_.passes(1) == AllocationDuel::kPasses) {
        // The duel's measurements with the render's sampler: the weighted relative variance
        // of the mean of 1, 2 and 4 passes (allocation_duel.h), relative to the pilot's V of
        // one pass with independent numbers; the efficiency compared, 1 / (V(4) · cost).
        std::snprintf(buf, sizeof buf, "  duel, the render's sampler: %-24s %9s %9s %9s %10s   (variance relative to the pilot's one pass)\n",
                      "", "V(1)", "V(2)", "V(4)", "mean");
        out += buf;
        for (int c = 0; c < 2; ++c) {
            const double v = pilotVariance_ > 0 ? pilotVariance_ : 1.0;
            std::snprintf(buf, sizeof buf, "  %-52s %9.3g %9.3g %9.3g %10.4g%s\n", duelistName(c).c_str(),
                          duel_.variance(c, 0) / v, duel_.variance(c, 1) / v, duel_.variance(c, 2) / v, duel_.mean(c),
                          duelists_[c] == chosen_ ? "   chosen" : "");
            out += buf;
        }
        if (decided()) {
            std::snprintf(buf, sizeof buf, "  the image %s the %d passes of %s: %.3gx the winner's variance per pass\n",
                          leftOutNoise() > 1 ? "leaves out" : "may keep", leftOutPasses(),
                          pilotLeftOut() ? "the pilot and the duel's loser" : "the duel's loser", leftOutNoise());
            out += buf;
        }
    }
    return out;
}

// State: "BAP9", then u8 whether the path tracer is probed (setPathTracerProbe: set from the
// scene before each pass, but loadState re-derives the choice before any pass, and without it
// a scene with a probe resumed to another choice), i32 pilot's choice, chosen, duelists × 2, collected, passes, width,
// height; u64 samples; f64 × kSums moments; u64 × kCounters counters; then (u64 n, n values)
// for sum (f64), sumSq (f64), weights (f32), ownParts (f32), ownSquares (f64); then the duel's (AllocationDuel::save); then i32
// passes left out and (u64 n, n × i128) for each of the three left-out sums; then i32 partial
// pilot passes and (u64 n, n × i128) their sums.

std::string AllocationPlanner::saveState() const {
    std::string out = "BAP9";
    putBytes(out, uint8_t(probe_ ? 1 : 0));
    putBytes(out, int32_t(pilotChoice_));
    putBytes(out, int32_t(chosen_));
    putBytes(out, int32_t(duelists_[0]));
    putBytes(out, int32_t(duelists_[1]));
    putBytes(out, int32_t(collected_));
    putBytes(out, int32_t(passes_));
    putBytes(out, int32_t(width_));
    putBytes(out, int32_t(height_));
    putBytes(out, samples_);
    moments_.forEach([&](double m) { putBytes(out, m); });
    counts_.forEach([&](uint64_t c) { putBytes(out, c); });
    putVector(out, sum_);
    putVector(out, sumSq_);
    putVector(out, weights_);
    putVector(out, ownParts_);
    putVector(out, ownSquares_);
    duel_.save(out);
    putBytes(out, int32_t(leftOutPasses_));
    for (const std::vector<FixedSum>& v : leftOut_) putVector(out, v);
    putBytes(out, int32_t(partialPasses_));
    putVector(out, partialSums_);
    return out;
}

void AllocationPlanner::loadState(const std::string& state) {
    if (state.size() < 4 || state.compare(0, 4, "BAP9") != 0) throw std::runtime_error("not an allocation state");
    StateReader r{state, 4};
    const uint8_t probe = r.get<uint8_t>();
    if (probe > 1) throw std::runtime_error("allocation state is malformed");
    const int pilotChoice = r.get<int32_t>(), chosen = r.get<int32_t>();
    const int duelist0 = r.get<int32_t>(), duelist1 = r.get<int32_t>();
    const int collected = r.get<int32_t>(), passes = r.get<int32_t>();
    const int width = r.get<int32_t>(), height = r.get<int32_t>();
    const int n = int(candidates_.size());
    auto index = [n](int j) { return j >= -1 && j < n; };
    if (!index(pilotChoice) || !index(chosen) || !index(duelist0) || !index(duelist1) || collected < 0 ||
        collected > collectPasses() || passes < 0 || passes > decisionPass() + 1 || width < 0 || height < 0 ||
        width > (1 << 16) || height > (1 << 16) || (pilotChoice >= 0 && collected != collectPasses()))
        throw std::runtime_error("allocation state is malformed");
    samples_ = r.get<uint64_t>();
    moments_.forEach([&](double& m) { m = r.get<double>(); });
    counts_.forEach([&](uint64_t& c) { c = r.get<uint64_t>(); });
    const size_t values = size_t(width) * size_t(height) * 3;
    sum_ = r.getVector<double>(values);
    sumSq_ = r.getVector<double>(values);
    weights_ = r.getVector<float>(values);
    const size_t parts = size_t((width + 1) / 2) * size_t((height + 1) / 2) * 3 * candidates_.size();
    ownParts_ = r.getVector<float>(parts);
    ownSquares_ = r.getVector<double>(candidates_.size());
    if ((!ownParts_.empty() && ownParts_.size() != parts) || (!ownSquares_.empty() && ownSquares_.size() != candidates_.size()))
        throw std::runtime_error("allocation state is malformed");
    duel_.load(r, values);
    const int leftOutPasses = r.get<int32_t>();
    std::vector<FixedSum> leftOut[3];
    for (std::vector<FixedSum>& v : leftOut) {
        v = r.getVector<FixedSum>(values);
        if (!v.empty() && v.size() != values) throw std::runtime_error("allocation state is malformed");
    }
    const int partialPasses = r.get<int32_t>();
    std::vector<FixedSum> partialSums = r.getVector<FixedSum>(values);
    const bool partialFits = partialPasses == 0 ? partialSums.empty() : values > 0 && partialSums.size() == values;
    if (partialPasses < 0 || partialPasses > (partial_ ? decisionPass() + 1 : 0) || !partialFits || leftOutPasses < 0 ||
        leftOutPasses > kMaxLastDecisionPass + 1)
        throw std::runtime_error("allocation state is malformed");
    if (r.at != state.size()) throw std::runtime_error("allocation state has trailing bytes");
    pilotChoice_ = chosen_ = -1;
    probe_ = probe != 0;
    collected_ = collected;
    passes_ = passes;
    width_ = width;
    height_ = height;
    if (pilotChoice >= 0) {
        decide();  // the estimates again, from the same numbers, and whether to duel
        if (pilotChoice_ != pilotChoice || duelists_[0] != duelist0 || duelists_[1] != duelist1)
            throw std::runtime_error("allocation state is malformed");
        if (dueling() && duel_.passes(1) == AllocationDuel::kPasses) decideDuel();
        if (chosen_ != chosen) throw std::runtime_error("allocation state is malformed");
    }
    leftOutPasses_ = leftOutPasses;
    for (int k = 0; k < 3; ++k) leftOut_[k] = std::move(leftOut[k]);
    partialPasses_ = partialPasses;
    partialSums_ = std::move(partialSums);
}

}  // namespace brume
