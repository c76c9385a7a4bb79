// The spatio-directional radiance cache of path guiding (docs/path-guiding.md): a kd-tree
// over the medium and surface vertices of training paths, split at the middle of the
// longest side while a cell holds more than maxRecords records that saw light, with per
// leaf and kind of
// vertex
//   - a vMF mixture fitted to the incident radiance (vmf_fit.h, weights L / p), and
//   - the share α of guided directions, chosen among a few values by the second moment
//     the records predict for it:  M(α) = Σ_j (f_j L_j)² / (p_α(ω_j) · p_j),
//     f_j the phase or f·|cos|, p_j the density ω_j was drawn with, p_α the guided
//     mixture with the new fit (guided_phase.h). α = 0 where guiding would not lower it by
//     a tenth (the extra cost of a guided vertex).
// Built from scratch from a list of records; deterministic in their order.
#pragma once
#include <cstdint>
#include <vector>

#include "brume/guiding/guide_record.h"
#include "brume/sampling/vmf.h"

namespace brume {

// Medium and surface records are fitted apart: light reaches a surface from one side only,
// and a mixture fitted to both would send half of a surface's guided directions into it.
struct GuidingCell {
    VmfMixture medium;       // incident radiance at medium vertices
    VmfMixture surface;      // and at surface vertices
    float share = 0;         // α at medium vertices (guided: the product with the phase)
    float surfaceShare = 0;  // α at surface vertices (guided: the surface mixture itself)
    // What a walk scattering here brings back per unit of throughput (the adjoint of
    // guided survival, path_tracer.cpp): the records' mean of f·L/p, for medium and surface
    // vertices; −1 where too few records of the kind were seen.
    float mediumAdjoint = -1, surfaceAdjoint = -1;
    // What a medium vertex here gathers per unit of throughput, X = direct + f·L/p (its
    // next-event estimate and its continuation): the records' mean of X and of X², for
    // guided distances (guided_distance.h); −1 where too few medium records were seen.
    float inscatter = -1, inscatter2 = -1;
};

struct GuidingSettings {
    int maxRecords = 2048;  // records that saw light per leaf, before it splits
    int minRecords = 64;    // records with radiance a leaf needs to guide at all
    int lobes = 6;
    int iterations = 6;     // EM steps
    int threads = 0;        // fitting leaves in parallel (0: all cores); no effect on the result
    float fixedShare = -1;  // ≥ 0: every fitted leaf guides with this α (tests: guiding forced on)
    // Learn the in-scattered radiance for guided distances: walks keep records lit only by
    // their next-event estimate, and leaves also split on those. Off, the records and the
    // tree are those of guided directions alone (more records would crowd the fits' budget:
    // guided pt lost 4–8 % at 12 s on four scenes when they were always kept).
    bool inscatter = false;
};

class GuidingField {
public:
    struct Node {
        float split = 0;
        uint32_t axis = 3;   // 0..2; 3: a leaf
        uint32_t index = 0;  // inner: left child (right = index + 1); leaf: cell, or kNoCell
    };
    static constexpr uint32_t kNoCell = ~0u;

    // Reorders `records` (grouped by leaf).
    void build(std::vector<GuideRecord>& records, const GuidingSettings& settings);
    // The cell at p, or null (outside the tree, or a leaf with too few records).
    const GuidingCell* lookup(Vec3 p) const;
    // The leaves the ray o + t·d crosses for t in [0, tMax] (tMax may be infinite), in order,
    // each as [t0, t1] with its cell (null: a leaf with too few records). The parts of the
    // ray outside the tree are not listed. Returns how many, or −1 if more than maxCount.
    struct Interval {
        float t0, t1;
        const GuidingCell* cell;
    };
    int along(Vec3 o, Vec3 d, float tMax, Interval* out, int maxCount) const;

    bool empty() const { return nodes_.empty(); }
    size_t leaves() const;
    size_t guidingCells() const;  // cells that guide either kind of vertex
    size_t memoryBytes() const { return nodes_.size() * sizeof(Node) + cells_.size() * sizeof(GuidingCell); }

    // Its parts, for a checkpoint, and back.
    Vec3 lower() const { return lo_; }
    Vec3 upper() const { return hi_; }
    const std::vector<Node>& nodes() const { return nodes_; }
    const std::vector<GuidingCell>& cells() const { return cells_; }
    // Throws std::runtime_error when the parts do not form a tree.
    void assign(Vec3 lo, Vec3 hi, std::vector<Node> nodes, std::vector<GuidingCell> cells);

private:
    Vec3 lo_, hi_;
    std::vector<Node> nodes_;
    std::vector<GuidingCell> cells_;
};

}  // namespace brume
