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
// Learning. The first kLearningPasses passes render with qA = qC = 1 and keep, per pixel and
// for each candidate (qA', qC'), the second moment its sample would have had: the sample's
// light-connection records re-weighted (their densities with q'), the rest of the sample as
// it was, and for a record of a connection made with probability q' the Bernoulli term
// v²·(1/q' − 1) (its value v/q' with probability q', 0 otherwise, independently of the rest):
//   M_j = (L_rest + Σ_r v'_r)² + Σ_{r: A or C} v'_r²·(1/q'_r − 1).
// After them, V_j = Σ_p w_p·(M_j,p / n − m_p²), w_p = 1/(m_p² + 0.01) as bench weighs errors
// (m_p: the pixel's mean over those passes), and the cost of a sample under j from the parts
// the passes counted (sample_cost.h: the calls at medium vertices scaled by qA', on segments
// by qC', less the ones a share of 0 still makes where the walk passes through); the
// candidate of least V_j·cost_j renders the rest (D's cost: its rays, with the table and
// light sample that come with them). Sums per pixel (in float: four passes of one pixel),
// added in pixel order: the same choice for any thread count, and kept in checkpoints.
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
    static constexpr int kLearningPasses = 4;
    // qA, qC in {1, 1/2, 1/4, 0}, not both 0; qD in {1, 0} (D is its table or nothing).
    static constexpr int kCandidates = 30;
    struct Shares {
        float vertex = 1, segment = 1, solidAngle = 1;  // qA, qC, qD
    };
    static Shares candidate(int j) {
        constexpr float q[4] = {1.0f, 0.5f, 0.25f, 0.0f};
        return Shares{q[(j % 15) / 4], q[(j % 15) % 4], j < 15 ? 1.0f : 0.0f};
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
    // One learning sample at `pixel`: its value L (grey), its records, how many connections
    // it made at medium vertices (their calls) and how many on segments that the walk passes
    // through and that traced (made whatever qC: madeWith). Thread-safe for distinct pixels.
    void addSample(int width, int height, uint32_t pixel, double L, const Record* records, int n, uint32_t mediumVertexCalls,
                   uint32_t passingSegmentCalls = 0);
    void endPass(const PassSummary& summary);
    // The choice, for --stats: each candidate's estimated relative variance and cost.
    std::string report() const;

    std::string saveState() const;
    void loadState(const std::string& state);  // std::runtime_error if malformed

private:
    void decide(const PassSummary& summary);
    void ensure(int width, int height);

    Shares shares_;
    bool decided_ = false;
    int passes_ = 0;
    int width_ = 0, height_ = 0;
    std::mutex sizing_;
    std::atomic<bool> sized_{false};  // the per-pixel sums below are sized for the render
    // Per pixel: the candidates' second moments, the sample values and their medium-vertex
    // connections (summed over the learning passes).
    std::vector<float> moments_;  // kCandidates per pixel
    std::vector<double> sum_;
    std::vector<uint32_t> vertexCalls_;
    std::vector<uint32_t> passingCalls_;
    PathCounts counts_;  // the learning passes' parts
    double variance_[kCandidates] = {}, cost_[kCandidates] = {};
};

}  // namespace brume
