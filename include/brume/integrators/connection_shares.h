// How often `pt --connect mis` makes each of its light connections in media: the connection
// at a free-flight vertex (A, path_tracer.cpp) with probability qA, the equi-angular (or
// product) connection on a segment (C) with probability qC, the connection by an emitter's
// solid angle (D) with probability qD ∈ {1, 0}, learned from the render's first passes
// (docs/path-tracer.md, "How often A, C and D are made").
//
// Why. Where one connection is nearly exact (C near a point light in thin fog) the other adds
// its variance back through the power heuristic and costs its rays; where the connections
// carry a small part of the variance (a caustic dominates, or the light is mostly occluded)
// both cost rays for little. D's table costs as much as the rest of a sample (a panel seen
// through thin fog: 27 % of the time, as much again in its light sample and ray) where A and
// the emitter hit B already do nearly as well. Making a connection with probability q is one-sample MIS with
// sample count q (Veach 1997, 9.2.4): its density enters every weight as q·p and its
// estimate is f·w/(q·p), so every path keeps weights that sum to one and no q > 0 biases.
//
// Learning, with the sampler the render uses. The first kLearningPasses (8) passes render with
// qA = qC = qD = 1. Each sample's value under a candidate j = (qA', qC', qD') is replayed from
// its light-connection records: re-weighted (their densities with q'), the rest of the sample
// as it was. The replay makes the same numbers' pass under j (A's and B's numbers do not
// depend on whether C or D is made), so the spread between aligned batches of passes measures
// j's error with Owen-scrambled Sobol numbers, as auto's duel does (allocation_duel.h: for two
// halves a, b of an aligned batch of 2n passes, E[(a − b)²]/2 = 2·V(n) − 2·V(2n), which follows
// V's power law n^−α). Per pixel on a
// lattice of at most kMaxLearningPixels, per candidate: E_j(2) from the two pairs of 2-pass
// batches and E_j(4) from the pair of 4-pass batches, weighted w_p = 1/(m_p² + 0.01) as bench
// weighs errors (m_p: the mean of the pixel's 8 passes without the largest) and summed in
// pixel order (not a median of pixel groups: the heavy tail of a candidate that leaves a
// technique out is what it must be charged for). Each also adds (m_j − m_all)², the gap
// between the candidate's 8-pass mean and the all-made one, as a variance of 8 passes: where a
// candidate's light is in events too rare for 8 passes (beside a 0.5° spot with C left out,
// free flight that seldom lands in the beam), its batches spread little (its passes black)
// while its mean falls short. The rate α = log2(E(2)/E(4)) of the all-made
// estimator, kept in [1, 3], is taken for all (a rate per candidate from 8 passes differs by
// its noise, which over 16× the passes outweighs the variances' differences); j's error at
// equal time, with N ∝ 1/cost passes and V ∝ N^−α, is E_j(4)·(cost_j/cost_all)^α: with α > 1
// cost counts for more than in variance × cost. The cost of a sample under j comes from the parts the passes counted
// (sample_cost.h: the calls at medium vertices scaled by qA', on segments by qC', less the
// ones a share of 0 still makes where the walk passes through; D's rays by qD', with the
// table and light sample that come with them). The
// candidate of least error renders the rest. Why not the second moments of independent
// samples: they cannot see what Owen scrambling gives each candidate (beside a panel light,
// leaving D out looked 11× worse per sample; measured at 256 passes it was 1.4× worse at half
// the cost). Sums per pixel (in float: eight passes of one pixel), added in pixel order: the
// same choice for any thread count, and kept in checkpoints.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "brume/integrators/integrator.h"
#include "brume/integrators/strategy_densities.h"

namespace brume {

class ConnectionShares {
public:
    static constexpr int kLearningPasses = 8;  // aligned: batches of 2 and 4 passes, in pairs
    static constexpr int kMaxLearningPixels = 1 << 16;
    // Each technique made always or never: (qA, qC) in {(1, 1), (1, 0), (0, 1)}, qD in {1, 0}.
    // (Shares between 0 and 1 stay possible, PathTracerOptions::shares, but are not learned:
    // making a connection by chance breaks its numbers' stratification, which 8 passes do not
    // show. Chosen by the learning, C ¼ with A 0 had 1.07× the all-made variance at 4 passes
    // in the glass beam's single scattering and 13× the error of pt:density at 384 passes.)
    static constexpr int kCandidates = 6;
    struct Shares {
        float vertex = 1, segment = 1, solidAngle = 1;  // qA, qC, qD
    };
    static Shares candidate(int j) {
        constexpr float a[3] = {1.0f, 1.0f, 0.0f}, c[3] = {1.0f, 0.0f, 1.0f};
        return Shares{a[j % 3], c[j % 3], j < 3 ? 1.0f : 0.0f};
    }
    // The shares a path is made with, given its strategies' densities p at q = 1: q, but 1 for
    // a technique of share 0 that no other strategy can make the path with. A share of 0 is
    // one technique left out of the MIS (qA = 0: C alone at medium vertices, as --connect
    // product; qC = 0: A alone, as --connect density), unbiased only where the others cover
    // its paths: not under the sun, which only A connects to (C and D have no point to aim at,
    // B cannot hit a delta light), nor where the walk passes through the medium, where only C
    // makes the path. (qA = qC = 0 is not a candidate: a point light would go unlit.) In
    // order A, C, D, each against the others' shares as decided so far, so that of a path some
    // strategy is always made: qD = 0 leaves D to A and B, and is kept wherever free flight can
    // scatter (B then has a density); where the walk passes through, D would be made (the
    // walk never passes where triangle lights can be hit: PathTracer::sample).
    static Shares madeWith(Shares q, const StrategyDensities& p) {
        if (q.vertex <= 0 && !(p.b > 0 || p.c * q.segment > 0 || p.d * q.solidAngle > 0)) q.vertex = 1;
        if (q.segment <= 0 && !(p.a * q.vertex > 0 || p.b > 0 || p.d * q.solidAngle > 0)) q.segment = 1;
        if (q.solidAngle <= 0 && !(p.a * q.vertex > 0 || p.b > 0 || p.c * q.segment > 0)) q.solidAngle = 1;
        return q;
    }

    // A light connection's record in a learning pass (grey values: the mean over channels).
    enum class Technique : uint8_t { Vertex, Emitter, Segment, SolidAngle };  // A, B, C, D
    struct Record {
        Technique technique;
        double value;         // its unweighted estimate f / p_self, times the throughput
        StrategyDensities p;  // the strategies' densities, at q = 1
    };

    // The shares pass `pass` renders with; learning until the choice is made.
    Shares shares() const { return shares_; }
    bool learning() const { return !decided_; }
    // Whether the learning replays the samples of `pixel` (on its lattice; every pixel of an
    // image up to kMaxLearningPixels): only those need their records.
    static bool learnsAt(int width, int height, uint32_t pixel);
    // One learning sample at `pixel`: its value L (grey), its records, how many connections
    // it made at medium vertices (their calls) and how many on segments that the walk passes
    // through and that traced (made whatever qC: madeWith). Thread-safe for distinct pixels.
    void addSample(int width, int height, uint32_t pixel, double L, const Record* records, int n, uint32_t mediumVertexCalls,
                   uint32_t passingSegmentCalls = 0);
    void endPass(const PassSummary& summary);
    // Whether candidates that leave C out (qC = 0) are ruled out: where a point or spot light
    // lies inside a medium, A alone has infinite variance near it (next-event estimation from
    // a free-flight point at distance r carries 1/r², and over the points of a ball around the
    // light ∫ (1/r²)² r² dr diverges; B cannot hit a point), a tail that 8 learning passes
    // do not show. Chosen so, `val_doorway` (full transport) rendered a firefly at seed 93:
    // relative MSE 1.04 against 0.05 at the other seeds. Beside a sphere light of radius R the
    // tail is bounded ((R/r)², r ≥ R) but as rare and as high where R is small: chosen so,
    // `dusk_haze` (0.12-m lamps) rendered single pixels 20–50× their mean. Set by the path
    // tracer before each endPass (PathTracer::endPass).
    void keepSegments(bool keep) { keepSegments_ = keep; }
    // The choice, for --stats: each candidate's estimated relative variance and cost.
    std::string report() const;

    std::string saveState() const;
    void loadState(const std::string& state);  // std::runtime_error if malformed

private:
    void decide();
    void ensure(int width, int height);
    // The learning lattice's spacing in pixels, and a pixel's place on it (−1: not on it).
    static int stride(int width, int height);
    static int slotOf(int width, int height, uint32_t pixel);
    // Per lattice pixel and candidate (kFields floats): the current 2-pass batch's sum (after
    // the last pass: the sum of all 8), the first 2-pass batch of its pair, the first 4-pass
    // batch, Σ (difference of a 2-pass pair's means)², (difference of the 4-pass pair's means)².
    static constexpr int kFields = 5;

    Shares shares_;
    bool decided_ = false;
    int passes_ = 0;
    int width_ = 0, height_ = 0;
    std::mutex sizing_;
    std::atomic<bool> sized_{false};  // the per-pixel sums below are sized for the render
    // Per lattice pixel: the batches above, and the pixel's value in each learning pass; per
    // pixel: its medium-vertex connections and passing segment calls.
    std::vector<float> batches_;  // kCandidates · kFields per lattice pixel
    std::vector<float> values_;   // kLearningPasses per lattice pixel
    std::vector<uint32_t> vertexCalls_;
    std::vector<uint32_t> passingCalls_;
    PathCounts counts_;  // the learning passes' parts
    double variance_[kCandidates] = {}, cost_[kCandidates] = {}, error_[kCandidates] = {};
    double rate_ = 1;  // the all-made estimator's, α
    bool keepSegments_ = false;  // keepSegments
};

}  // namespace brume
