#include "brume/scene/density_grid.h"

#include "brume/scene/medium.h"

namespace brume {

void DensityGrid::buildMajorants() {
    for (int a = 0; a < 3; ++a) bn[a] = std::max(1, (n[a] - 1 + kBrick - 1) / kBrick);
    majorant.assign(size_t(bn[0]) * bn[1] * bn[2], 0.0f);
    mean.assign(majorant.size(), 0.0f);
    for (int bz = 0; bz < bn[2]; ++bz)
        for (int by = 0; by < bn[1]; ++by)
            for (int bx = 0; bx < bn[0]; ++bx) {
                float m = 0;
                double sum = 0, count = 0;
                const int k1 = std::min((bz + 1) * kBrick, n[2] - 1), j1 = std::min((by + 1) * kBrick, n[1] - 1),
                          i1 = std::min((bx + 1) * kBrick, n[0] - 1);
                for (int k = bz * kBrick; k <= k1; ++k)
                    for (int j = by * kBrick; j <= j1; ++j)
                        for (int i = bx * kBrick; i <= i1; ++i) {
                            m = std::max(m, at(i, j, k));
                            sum += at(i, j, k);
                            count += 1;
                        }
                majorant[(size_t(bz) * bn[1] + by) * bn[0] + bx] = m;
                mean[(size_t(bz) * bn[1] + by) * bn[0] + bx] = float(sum / count);
            }
}

void GridPlacement::place(const Mat4& node) {
    // local = index − (lo − 1): a translation after world → index.
    Mat4 toLocal = (node * indexToWorld).affineInverse();
    for (int a = 0; a < 3; ++a) toLocal(a, 3) -= double(grid->lo[a] - 1);
    worldToLocal = toLocal;
}

}  // namespace brume
