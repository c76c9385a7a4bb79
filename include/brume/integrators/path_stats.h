// What the samples of a tile count, typed: the renderer keeps one PathStats per tile and sums
// them in tile order once the pass is complete, so the statistics an integrator keeps from pass
// to pass (its endPass) are the same for any thread count.
#pragma once
#include <cstdint>
#include <initializer_list>

#include "brume/integrators/technique_sums.h"

namespace brume {

// The bidirectional tracer's kinds of strategy (bdpt_strategies.h).
enum class StrategyKind : int { EmitterHit, LightConnection, CameraConnection, SubpathConnection };
constexpr int kStrategyKinds = 4;
// Its technique slots in TechniqueSums: 2·kind + [equi-angular variant].
constexpr int techniqueSlot(StrategyKind kind, bool equiAngular) { return 2 * int(kind) + (equiAngular ? 1 : 0); }
static_assert(2 * kStrategyKinds <= techniqueSlot(PathTracerTechnique::EmitterHit), "a slot per kind and variant");


// The bidirectional tracer's counts: contributions (nonzero weighted estimates) by kind and
// variant, and the rays each part of a sample traced (the cost model of the efficiency-aware
// tracer, sample_cost.h): the two walks, and each kind of connection but the emitter hit
// (which traces none of its own) by variant.
struct BidirectionalCounts {
    uint64_t contributions[2][kStrategyKinds] = {};  // [equi-angular variant][kind]
    uint64_t cameraWalkRays = 0, lightWalkRays = 0;
    uint64_t connectionRays[kStrategyKinds][2] = {};  // [kind][equi-angular variant]
    // Of the free-flight light (0) and camera (1) connections' rays, those at vertices where
    // the equi-angular variant was on and could have made the vertex: what an ea-only
    // allocation (bdpt_allocation.h) would not trace.
    uint64_t replaceableRays[2] = {};

    uint64_t& contribution(StrategyKind k, bool equiAngular) { return contributions[equiAngular ? 1 : 0][int(k)]; }
    uint64_t contribution(StrategyKind k, bool equiAngular) const { return contributions[equiAngular ? 1 : 0][int(k)]; }
    uint64_t& rays(StrategyKind k, bool equiAngular) { return connectionRays[int(k)][equiAngular ? 1 : 0]; }
    uint64_t rays(StrategyKind k, bool equiAngular) const { return connectionRays[int(k)][equiAngular ? 1 : 0]; }
};

// The path tracer's counts: its samples, the rays of its walk, and the calls and rays of each
// part of its light connections: at vertices (free flight, surfaces), on segments
// (equi-angular or product) and by an emitter's solid angle. segmentTracingCalls: the calls on
// segments that traced a ray (the others return at once: towards a light at infinity, which
// has no equi-angular point, or where distances by an emitter's solid angle take C's place);
// what the connection shares save by skipping C (connection_shares.h). The cost model
// (sample_cost.h) was fitted on every call.
struct PathTracerCounts {
    uint64_t samples = 0, walkRays = 0;
    uint64_t vertexRays = 0, vertexCalls = 0;
    uint64_t segmentRays = 0, segmentCalls = 0, segmentTracingCalls = 0;
    uint64_t solidAngleRays = 0, solidAngleCalls = 0;
    uint64_t connectionRays() const { return vertexRays + segmentRays + solidAngleRays; }
};

// Both, as a pass or a render counted them.
struct PathCounts {
    BidirectionalCounts bdpt;
    PathTracerCounts pt;

    // Every count, in a fixed order (for adding and for checkpoints).
    template <class F>
    void forEach(F&& f) { visit(*this, f); }
    template <class F>
    void forEach(F&& f) const { visit(*this, f); }
    void add(const PathCounts& o) {
        const uint64_t* from[kCount];
        int n = 0;
        o.forEach([&](const uint64_t& v) { from[n++] = &v; });
        n = 0;
        forEach([&](uint64_t& v) { v += *from[n++]; });
    }
    static constexpr int kCount = 2 * kStrategyKinds + 2 + 2 * (kStrategyKinds - 1) + 2 + 9;

private:
    template <class Self, class F>
    static void visit(Self& s, F& f) {
        for (auto& row : s.bdpt.contributions)
            for (auto& v : row) f(v);
        f(s.bdpt.cameraWalkRays);
        f(s.bdpt.lightWalkRays);
        for (int k = 1; k < kStrategyKinds; ++k)
            for (auto& v : s.bdpt.connectionRays[k]) f(v);
        for (auto& v : s.bdpt.replaceableRays) f(v);
        for (auto* v : {&s.pt.samples, &s.pt.walkRays, &s.pt.vertexRays, &s.pt.vertexCalls, &s.pt.segmentRays,
                        &s.pt.segmentCalls, &s.pt.segmentTracingCalls, &s.pt.solidAngleRays, &s.pt.solidAngleCalls})
            f(*v);
    }
};

// The efficiency-aware tracer's sums over its recording pixels (allocation_statistics.h): per
// candidate allocation Σ w·F² (with the products of a sample's contributions to one pixel),
// its second moment two ways (from each candidate's own strategies' samples, and through the
// pilot's weights), and the probe of the path tracer, Σ w·L and Σ w·L². The two moments are
// summed apart in kGroups interleaved groups of recording pixels, so that one sample's spike
// can be told from a tail (allocation_planner.cpp decide).
struct AllocationMoments {
    static constexpr int kCandidates = 32;
    static constexpr int kGroups = 16;
    double candidate[kGroups][kCandidates] = {};
    double combined[kGroups][kCandidates] = {};
    double probeMean = 0, probe = 0;

    // The group of recording pixel (x, y) (even x and y): the recording pixels of one group
    // are 8 apart in x and y.
    static int group(int x, int y) { return ((x >> 1) & 3) + 4 * ((y >> 1) & 3); }

    template <class F>
    void forEach(F&& f) {
        for (auto& row : candidate)
            for (double& v : row) f(v);
        for (auto& row : combined)
            for (double& v : row) f(v);
        f(probeMean);
        f(probe);
    }
    template <class F>
    void forEach(F&& f) const {
        for (const auto& row : candidate)
            for (const double& v : row) f(v);
        for (const auto& row : combined)
            for (const double& v : row) f(v);
        f(probeMean);
        f(probe);
    }
    static constexpr int kCount = 2 * kGroups * kCandidates + 2;
    void add(const AllocationMoments& o) {
        for (int g = 0; g < kGroups; ++g)
            for (int j = 0; j < kCandidates; ++j) {
                candidate[g][j] += o.candidate[g][j];
                combined[g][j] += o.combined[g][j];
            }
        probeMean += o.probeMean;
        probe += o.probe;
    }
};

struct PathStats {
    uint64_t rays = 0;  // closest-hit and shadow rays traced
    PathCounts counts;
    AllocationMoments moments;
    TechniqueSums techniques;
    // auto's partial pilot passes (AllocationPlanner::partialAt): what the samples of pixels
    // that do not record counted (their light subpaths), apart from `counts`, which then holds
    // the recording pixels' whole samples alone.
    PathCounts partialLight;
    void add(const PathStats& o) {
        rays += o.rays;
        counts.add(o.counts);
        partialLight.add(o.partialLight);
        moments.add(o.moments);
        techniques.add(o.techniques);
    }
};

}  // namespace brume
