// A density grid (heterogeneous media, docs/scene-format.md "density grids"): voxel values on
// the integer points of the grid's index space, trilinear between them, 0 where the source had
// no active voxel; and a coarse grid of majorants, one per brick of kBrick³ voxels, walked by a
// DDA so that delta and ratio tracking (scene/heterogeneous_medium.cpp) step through thin
// regions in few steps. Each brick also keeps the mean of its voxels, from which the MIS
// stand-in densities take their optical depth (docs/mis.md, "heterogeneous media").
//
// Storage: sparse bricks. The local box q = index − origin, q ∈ [0, n − 1] per axis, covers the
// active voxels with one zero voxel of padding on every side (origin = lo − 1). A brick b
// covers q ∈ [b·B, (b + 1)·B); the trilinear value there mixes voxels b·B … (b + 1)·B only,
// so each stored brick keeps those (B + 1)³ voxels (its own and the first plane of its
// neighbours: one table lookup per query, no branch across bricks), and its majorant is their
// maximum. A brick none of whose voxels is non-zero is not stored: memory grows with the
// active voxels (and their bricks' surfaces), not with the size of the box. The brick table (4 bytes a brick) and the
// majorants and means (8 bytes a brick) are dense over the box: for a 2048 × 1024 × 2048 box,
// 100 MiB.
//
// Empty space: bricks group into regions of kRegion³ bricks (128³ voxels, the span of an
// OpenVDB internal node), and the walk crosses a region none of whose bricks holds a non-zero
// voxel in one step (one piece of majorant 0), so that a ray's work grows with the occupied
// regions it meets and the optical depth it crosses, not with the empty box around them.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>
#include "brume/math/vec3.h"

namespace brume {

struct DensityGrid {
    static constexpr int kBrick = 8;
    static constexpr int kApron = kBrick + 1;                   // voxels per axis a brick keeps
    static constexpr int kBrickVoxels = kApron * kApron * kApron;
    static constexpr uint32_t kEmptyBrick = ~0u;
    static constexpr int kRegion = 16;  // bricks per region and axis
    int n[3] = {0, 0, 0};         // local box voxel counts (padding included)
    int origin[3] = {0, 0, 0};    // the index of local voxel (0, 0, 0): the active box's lo − 1
    int bn[3] = {0, 0, 0};        // bricks per axis
    std::vector<uint32_t> brick;  // per brick (x fastest): its slot in `voxels`, or kEmptyBrick
    std::vector<float> voxels;    // kBrickVoxels values per stored brick, x fastest
    std::vector<float> majorant;  // per brick, x fastest
    std::vector<float> mean;      // per brick: the mean of the voxels it mixes
    int rn[3] = {0, 0, 0};          // regions per axis
    std::vector<uint8_t> occupied;  // per region (x fastest): 1 if a brick in it is stored
    size_t occupiedRegions = 0;
    double activeVoxels = 0;      // non-zero voxels of the source
    float maxValue = 0;

    // Building: layout() fixes the box for the active voxels [lo, hi] (index space,
    // inclusive; hi < lo: none) with every brick empty (majorant 0); storeBrick() fills brick
    // (bx, by, bz) from value(i, j, k) (index space; asked for voxels of [lo, hi] only, 0
    // elsewhere) and keeps it unless all its voxels are 0. A value must be finite and ≥ 0, and
    // value a function of the voxel: bricks share their faces, so a voxel may be asked twice.
    // build() stores every brick (tests, small grids); a sparse source stores the bricks
    // its active voxels touch (vdb_file.cpp).
    void layout(const int lo[3], const int hi[3]);
    template <class F>
    void storeBrick(int bx, int by, int bz, F value);
    template <class F>
    void build(const int lo[3], const int hi[3], F value);
    size_t memoryBytes() const {
        return brick.size() * sizeof(uint32_t) + (voxels.size() + majorant.size() + mean.size()) * sizeof(float) +
               occupied.size();
    }

    // Voxel value at local integer coordinates (0 outside the box).
    float at(int i, int j, int k) const {
        if (i < 0 || j < 0 || k < 0 || i >= n[0] - 1 || j >= n[1] - 1 || k >= n[2] - 1) return 0.0f;
        const uint32_t s = brick[(size_t(k / kBrick) * bn[1] + j / kBrick) * bn[0] + i / kBrick];
        if (s == kEmptyBrick) return 0.0f;
        return voxels[size_t(s) * kBrickVoxels + ((k % kBrick) * kApron + j % kBrick) * kApron + i % kBrick];
    }
    // Density at local coordinates q (trilinear; 0 outside).
    float lookup(Vec3 q) const {
        if (!(q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < n[0] - 1 && q.y < n[1] - 1 && q.z < n[2] - 1)) return 0;
        const int i = int(q.x), j = int(q.y), k = int(q.z);
        const uint32_t s = brick[(size_t(k / kBrick) * bn[1] + j / kBrick) * bn[0] + i / kBrick];
        if (s == kEmptyBrick) return 0;
        const float fx = q.x - i, fy = q.y - j, fz = q.z - k;
        constexpr size_t sy = kApron, sz = kApron * kApron;
        const float* v = &voxels[size_t(s) * kBrickVoxels + (k % kBrick) * sz + (j % kBrick) * sy + i % kBrick];
        const float c00 = v[0] + fx * (v[1] - v[0]), c10 = v[sy] + fx * (v[sy + 1] - v[sy]);
        const float c01 = v[sz] + fx * (v[sz + 1] - v[sz]), c11 = v[sz + sy] + fx * (v[sz + sy + 1] - v[sz + sy]);
        const float c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
        return std::max(0.0f, c0 + fz * (c1 - c0));
    }
    // The brick holding local point q (inside the box), as an index into `brick`; and the
    // interval of the whole line q0 + t·dq inside brick b's box [b·B, (b + 1)·B]³, unclipped:
    // the one-point-per-brick emission estimate draws its point there, and next-event
    // estimation towards emissive media reads its density from it (medium_emission.cpp).
    size_t brickAt(Vec3 q) const {
        return (size_t(int(q.z) / kBrick) * bn[1] + size_t(int(q.y) / kBrick)) * bn[0] + size_t(int(q.x) / kBrick);
    }
    bool brickInterval(size_t b, Vec3 q0, Vec3 dq, float* ta, float* tb) const {
        const int c[3] = {int(b % size_t(bn[0])), int((b / size_t(bn[0])) % size_t(bn[1])), int(b / (size_t(bn[0]) * bn[1]))};
        float lo = -INFINITY, hi = INFINITY;
        for (int a = 0; a < 3; ++a) {
            const float l = float(c[a] * kBrick), h = float((c[a] + 1) * kBrick);
            if (dq[a] == 0) {
                if (q0[a] < l || q0[a] >= h) return false;
                continue;
            }
            float t0 = (l - q0[a]) / dq[a], t1 = (h - q0[a]) / dq[a];
            if (t0 > t1) std::swap(t0, t1);
            lo = std::max(lo, t0);
            hi = std::min(hi, t1);
        }
        *ta = lo;
        *tb = hi;
        return lo < hi;
    }
    // Local coordinates of an index-space point.
    Vec3 local(Vec3 index) const { return Vec3(index.x - origin[0], index.y - origin[1], index.z - origin[2]); }

    // Walks the line q(t) = q0 + t·dq, t ∈ [t0, t1], through the bricks it crosses, calling
    // f(ta, tb, majorant, mean) for consecutive pieces (only inside the grid's box; the rest
    // has density 0); f returns false to stop.
    template <class F>
    void forEachMajorant(Vec3 q0, Vec3 dq, float t0, float t1, F f) const;

private:
    int lo_[3] = {0, 0, 0}, hi_[3] = {-1, -1, -1};  // the active box (index space)

    // The empty-region steps of forEachMajorant, kept out of its loop (density_grid.cpp):
    // whether cell's region holds no stored brick; where the ray leaves that region (out: the
    // axis of the face); and the cell beyond that face at t (false: past the box).
    bool emptyRegion(const int cell[3]) const {
        return !occupied[(size_t(cell[2] / kRegion) * rn[1] + cell[1] / kRegion) * rn[0] + cell[0] / kRegion];
    }
    [[gnu::noinline]] float regionExit(Vec3 q0, Vec3 dq, const int cell[3], const int step[3], int* out) const;
    [[gnu::noinline]] bool enterAfterRegion(Vec3 q0, Vec3 dq, float t, int out, int cell[3], const int step[3]) const;
};

template <class F>
void DensityGrid::storeBrick(int bx, int by, int bz, F value) {
    const size_t b = (size_t(bz) * bn[1] + by) * bn[0] + bx;
    if (brick[b] != kEmptyBrick) return;
    const size_t slot = voxels.size() / kBrickVoxels;
    voxels.resize(voxels.size() + kBrickVoxels, 0.0f);
    float* v = &voxels[slot * kBrickVoxels];
    const int b0[3] = {bx * kBrick, by * kBrick, bz * kBrick};
    float m = 0;
    double sum = 0, count = 0;
    for (int dk = 0; dk < kApron; ++dk)
        for (int dj = 0; dj < kApron; ++dj)
            for (int di = 0; di < kApron; ++di) {
                const int q[3] = {b0[0] + di, b0[1] + dj, b0[2] + dk};
                const int idx[3] = {q[0] + origin[0], q[1] + origin[1], q[2] + origin[2]};
                const bool inside = idx[0] >= lo_[0] && idx[0] <= hi_[0] && idx[1] >= lo_[1] && idx[1] <= hi_[1] &&
                                    idx[2] >= lo_[2] && idx[2] <= hi_[2];
                const float x = inside ? value(idx[0], idx[1], idx[2]) : 0.0f;
                v[(dk * kApron + dj) * kApron + di] = x;
                if (q[0] <= n[0] - 1 && q[1] <= n[1] - 1 && q[2] <= n[2] - 1) {  // (the mean over the box, as mixed)
                    m = std::max(m, x);
                    sum += x;
                    count += 1;
                }
                if (di < kBrick && dj < kBrick && dk < kBrick && x > 0) {  // its own voxels: each counted once
                    activeVoxels += 1;
                    maxValue = std::max(maxValue, x);
                }
            }
    if (!(m > 0)) {  // all zero: not stored
        voxels.resize(slot * kBrickVoxels);
        return;
    }
    brick[b] = uint32_t(slot);
    majorant[b] = m;
    mean[b] = float(sum / count);
    uint8_t& region = occupied[(size_t(bz / kRegion) * rn[1] + by / kRegion) * rn[0] + bx / kRegion];
    occupiedRegions += region == 0;
    region = 1;
}

template <class F>
void DensityGrid::build(const int lo[3], const int hi[3], F value) {
    layout(lo, hi);
    for (int bz = 0; bz < bn[2]; ++bz)
        for (int by = 0; by < bn[1]; ++by)
            for (int bx = 0; bx < bn[0]; ++bx) storeBrick(bx, by, bz, value);
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
    // Amanatides–Woo over bricks from the entry point; an empty region is crossed in one piece.
    int cell[3], step[3];
    float tNext[3], tDelta[3];
    const float B = float(kBrick);
    for (int a = 0; a < 3; ++a) {
        const float p = q0[a] + dq[a] * ta;
        cell[a] = std::min(std::max(int(std::floor(p / B)), 0), bn[a] - 1);
        step[a] = dq[a] > 0 ? 1 : (dq[a] < 0 ? -1 : 0);
        tDelta[a] = step[a] != 0 ? B / std::abs(dq[a]) : INFINITY;
    }
    // The next brick face on each axis from the current cell.
    auto faces = [&] {
        for (int a = 0; a < 3; ++a)
            tNext[a] = step[a] == 0 ? INFINITY : ((cell[a] + (step[a] > 0 ? 1 : 0)) * B - q0[a]) / dq[a];
    };
    faces();
    float t = ta;
    // Whether the region of `cell` is empty: asked on entering a region only. (A grid without
    // an empty region, most dense ones, skips the bookkeeping.)
    const bool regions = occupiedRegions < occupied.size();
    bool empty = regions && emptyRegion(cell);
    for (;;) {
        // One call of f per step, from a brick or, out of the cold helper, an empty region.
        int a = 0, out = -1;
        float tExit, m = 0, mn = 0;
        if (empty) {
            tExit = std::min(regionExit(q0, dq, cell, step, &out), tb);
        } else {
            a = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
            tExit = std::min(tNext[a], tb);
            const size_t b = (size_t(cell[2]) * bn[1] + cell[1]) * bn[0] + cell[0];
            m = majorant[b];
            mn = mean[b];
        }
        if (tExit > t && !f(t, tExit, m, mn)) return;
        if (tExit >= tb) return;
        t = tExit;
        if (empty) {
            if (out < 0 || !enterAfterRegion(q0, dq, t, out, cell, step)) return;
            faces();
            empty = emptyRegion(cell);
            continue;
        }
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= bn[a]) return;
        tNext[a] += tDelta[a];
        // A new region along a: (cell mod kRegion) wrapped round.
        if (regions && unsigned(cell[a]) % kRegion == (step[a] > 0 ? 0u : unsigned(kRegion - 1))) empty = emptyRegion(cell);
    }
}

}  // namespace brume
