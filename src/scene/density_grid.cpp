#include "brume/scene/density_grid.h"

#include "brume/scene/medium.h"

namespace brume {

void DensityGrid::layout(const int lo[3], const int hi[3]) {
    const bool none = hi[0] < lo[0] || hi[1] < lo[1] || hi[2] < lo[2];
    for (int a = 0; a < 3; ++a) {
        lo_[a] = none ? 0 : lo[a];
        hi_[a] = none ? -1 : hi[a];
        // Padding: a zero voxel before lo and after hi. (Bricks on OpenVDB's leaf boundaries,
        // origin a multiple of 8, were tried: the brick before the data then holds only its
        // first plane as apron, and its majorant covers 7 empty voxels; a shadow ray entering
        // a dense grid drew 7750 tentative collisions instead of 220.)
        origin[a] = lo_[a] - 1;
        n[a] = hi_[a] + 2 - origin[a];
        bn[a] = std::max(1, (n[a] - 1 + kBrick - 1) / kBrick);
    }
    const size_t bricks = size_t(bn[0]) * bn[1] * bn[2];
    for (int a = 0; a < 3; ++a) rn[a] = (bn[a] + kRegion - 1) / kRegion;
    occupied.assign(size_t(rn[0]) * rn[1] * rn[2], 0);
    occupiedRegions = 0;
    brick.assign(bricks, kEmptyBrick);
    majorant.assign(bricks, 0.0f);
    mean.assign(bricks, 0.0f);
    voxels.clear();
    activeVoxels = 0;
    maxValue = 0;
}

float DensityGrid::regionExit(Vec3 q0, Vec3 dq, const int cell[3], const int step[3], int* out) const {
    const float B = float(kBrick);
    float tOut = INFINITY;
    *out = -1;
    for (int a = 0; a < 3; ++a) {
        if (step[a] == 0) continue;
        const int r = cell[a] / kRegion;
        const int edge = step[a] > 0 ? std::min((r + 1) * kRegion, bn[a]) : r * kRegion;
        const float te = (float(edge) * B - q0[a]) / dq[a];
        if (te < tOut) tOut = te, *out = a;
    }
    return tOut;
}

bool DensityGrid::enterAfterRegion(Vec3 q0, Vec3 dq, float t, int out, int cell[3], const int step[3]) const {
    const float B = float(kBrick);
    for (int a = 0; a < 3; ++a) {  // the brick beyond the exit face; elsewhere where the ray is
        const int r = cell[a] / kRegion;
        if (a == out) {
            cell[a] = step[a] > 0 ? std::min((r + 1) * kRegion, bn[a]) : r * kRegion - 1;
        } else {
            const int lo = r * kRegion, hi = std::min((r + 1) * kRegion, bn[a]) - 1;
            cell[a] = std::min(std::max(int(std::floor((q0[a] + dq[a] * t) / B)), lo), hi);
        }
    }
    return cell[out] >= 0 && cell[out] < bn[out];
}

void GridPlacement::place(const Mat4& node) {
    // local = index − origin: a translation after world → index.
    Mat4 toLocal = (node * indexToWorld).affineInverse();
    for (int a = 0; a < 3; ++a) toLocal(a, 3) -= double(grid->origin[a]);
    worldToLocal = toLocal;
}

}  // namespace brume
