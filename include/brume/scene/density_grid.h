// A density grid (heterogeneous media, docs/scene-format.md "density grids"): voxel values on
// the integer points of the grid's index space, trilinear between them, 0 where the source had
// no active voxel; and a coarse grid of majorants, one per brick of kBrick³ voxels, walked by a
// DDA so that delta and ratio tracking (scene/heterogeneous_medium.cpp) step through thin
// regions in few steps. Each brick also keeps the mean of its voxels, from which the MIS
// stand-in densities take their optical depth (docs/mis.md, "heterogeneous media").
//
// Storage: a dense array over the active voxels' bounding box, padded by one zero voxel on
// every side, so a lookup needs one range test and no other branch. Local coordinates
// q = index − (lo − 1) run over [0, n − 1] per axis; outside that the density is 0.
// A brick b covers q ∈ [b·B, (b + 1)·B); the trilinear value there mixes voxels b·B … (b + 1)·B
// only, so the brick's majorant is their maximum (B + 1 per axis, shared with the neighbours).
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>
#include "brume/math/vec3.h"

namespace brume {

struct DensityGrid {
    static constexpr int kBrick = 8;
    int n[3] = {0, 0, 0};         // padded voxel counts
    int lo[3] = {0, 0, 0};        // index of the first active voxel (padding voxel: lo − 1)
    std::vector<float> values;    // x fastest
    int bn[3] = {0, 0, 0};        // bricks per axis
    std::vector<float> majorant;  // per brick, x fastest
    std::vector<float> mean;      // per brick: the mean of the voxels it mixes
    double activeVoxels = 0;      // non-zero voxels of the source
    float maxValue = 0;

    // Fills the padded array from a callback value(i, j, k) over the active box [lo, hi]
    // (inclusive, index space) and builds the majorants. Values must be finite and ≥ 0.
    template <class F>
    void build(const int lo_[3], const int hi_[3], F value);
    void buildMajorants();

    float at(int i, int j, int k) const { return values[(size_t(k) * n[1] + j) * n[0] + i]; }
    // Density at local coordinates q (trilinear; 0 outside).
    float lookup(Vec3 q) const {
        if (!(q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < n[0] - 1 && q.y < n[1] - 1 && q.z < n[2] - 1)) return 0;
        const int i = int(q.x), j = int(q.y), k = int(q.z);
        const float fx = q.x - i, fy = q.y - j, fz = q.z - k;
        const size_t sy = size_t(n[0]), sz = size_t(n[0]) * n[1];
        const float* v = &values[k * sz + j * sy + i];
        const float c00 = v[0] + fx * (v[1] - v[0]), c10 = v[sy] + fx * (v[sy + 1] - v[sy]);
        const float c01 = v[sz] + fx * (v[sz + 1] - v[sz]), c11 = v[sz + sy] + fx * (v[sz + sy + 1] - v[sz + sy]);
        const float c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
        return std::max(0.0f, c0 + fz * (c1 - c0));
    }
    // Local coordinates of an index-space point.
    Vec3 local(Vec3 index) const { return Vec3(index.x - (lo[0] - 1), index.y - (lo[1] - 1), index.z - (lo[2] - 1)); }

    // Walks the line q(t) = q0 + t·dq, t ∈ [t0, t1], through the bricks it crosses, calling
    // f(ta, tb, majorant, mean) for consecutive pieces (only inside the grid's box; the rest
    // has density 0); f returns false to stop.
    template <class F>
    void forEachMajorant(Vec3 q0, Vec3 dq, float t0, float t1, F f) const;
};

template <class F>
void DensityGrid::build(const int lo_[3], const int hi_[3], F value) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = lo_[a];
        n[a] = hi_[a] - lo_[a] + 3;
    }
    values.assign(size_t(n[0]) * n[1] * n[2], 0.0f);
    activeVoxels = 0;
    maxValue = 0;
    for (int k = 1; k < n[2] - 1; ++k)
        for (int j = 1; j < n[1] - 1; ++j)
            for (int i = 1; i < n[0] - 1; ++i) {
                const float v = value(lo[0] + i - 1, lo[1] + j - 1, lo[2] + k - 1);
                values[(size_t(k) * n[1] + j) * n[0] + i] = v;
                if (v > 0) activeVoxels += 1;
                maxValue = std::max(maxValue, v);
            }
    buildMajorants();
}

template <class F>
void DensityGrid::forEachMajorant(Vec3 q0, Vec3 dq, float t0, float t1, F f) const {
    // Clip to the box [0, n − 1]³ (the slab test).
    float ta = t0, tb = t1;
    for (int a = 0; a < 3; ++a) {
        const float o = q0[a], d = dq[a], hi = float(n[a] - 1);
        if (d == 0) {
            if (o < 0 || o >= hi) return;
            continue;
        }
        float tl = (0 - o) / d, th = (hi - o) / d;
        if (tl > th) std::swap(tl, th);
        ta = std::max(ta, tl);
        tb = std::min(tb, th);
    }
    if (!(ta < tb)) return;
    // Amanatides–Woo over bricks from the entry point.
    int cell[3], step[3];
    float tNext[3], tDelta[3];
    const float B = float(kBrick);
    for (int a = 0; a < 3; ++a) {
        const float p = q0[a] + dq[a] * ta;
        cell[a] = std::min(std::max(int(std::floor(p / B)), 0), bn[a] - 1);
        if (dq[a] > 0) {
            step[a] = 1;
            tNext[a] = ((cell[a] + 1) * B - q0[a]) / dq[a];
            tDelta[a] = B / dq[a];
        } else if (dq[a] < 0) {
            step[a] = -1;
            tNext[a] = (cell[a] * B - q0[a]) / dq[a];
            tDelta[a] = -B / dq[a];
        } else {
            step[a] = 0;
            tNext[a] = INFINITY;
            tDelta[a] = INFINITY;
        }
    }
    float t = ta;
    for (;;) {
        const int a = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
        const float tExit = std::min(tNext[a], tb);
        const size_t b = (size_t(cell[2]) * bn[1] + cell[1]) * bn[0] + cell[0];
        if (tExit > t && !f(t, tExit, majorant[b], mean[b])) return;
        if (tExit >= tb) return;
        t = tExit;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= bn[a]) return;
        tNext[a] += tDelta[a];
    }
}

}  // namespace brume
