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
    brick.assign(bricks, kEmptyBrick);
    majorant.assign(bricks, 0.0f);
    mean.assign(bricks, 0.0f);
    voxels.clear();
    activeVoxels = 0;
    maxValue = 0;
}

void GridPlacement::place(const Mat4& node) {
    // local = index − origin: a translation after world → index.
    Mat4 toLocal = (node * indexToWorld).affineInverse();
    for (int a = 0; a < 3; ++a) toLocal(a, 3) -= double(grid->origin[a]);
    worldToLocal = toLocal;
}

}  // namespace brume
