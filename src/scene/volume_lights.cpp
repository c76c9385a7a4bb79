#include "brume/scene/volume_lights.h"

#include <algorithm>
#include <cmath>

#include "brume/scene/density_grid.h"

namespace brume {

VolumeLights::VolumeLights(const std::vector<Medium>& media) {
    sampled_.assign(media.size(), false);
    gridOf_.assign(media.size(), -1);
    std::vector<float> power;
    for (size_t i = 0; i < media.size(); ++i) {
        const Medium& m = media[i];
        if (!m.emissive() || !m.emissionGrid.grid) continue;
        const DensityGrid& g = *m.emissionGrid.grid;
        Grid grid;
        grid.medium = int(i);
        grid.localToWorld = m.emissionGrid.worldToLocal.affineInverse();
        const Mat4& w = grid.localToWorld;
        const double det = w(0, 0) * (w(1, 1) * w(2, 2) - w(1, 2) * w(2, 1)) -
                           w(0, 1) * (w(1, 0) * w(2, 2) - w(1, 2) * w(2, 0)) +
                           w(0, 2) * (w(1, 0) * w(2, 1) - w(1, 1) * w(2, 0));
        const double B = DensityGrid::kBrick;
        grid.brickVolume = float(std::abs(det) * B * B * B);
        grid.bn[0] = g.bn[0];
        grid.bn[1] = g.bn[1];
        std::vector<float> weights;
        double total = 0;
        for (size_t b = 0; b < g.brick.size(); ++b) {
            if (g.brick[b] == DensityGrid::kEmptyBrick || !(g.majorant[b] > 0)) continue;
            const Spectrum e = m.emissionOf(g.majorant[b]);
            const double wgt = (std::abs(double(e.x)) + std::abs(e.y) + std::abs(e.z)) / 3 * grid.brickVolume;
            grid.slot.push_back(uint32_t(b));
            weights.push_back(float(wgt));
            total += wgt;
        }
        if (!(total > 0)) continue;
        grid.bricks = Distribution1D(weights);
        gridOf_[i] = int(grids_.size());
        grids_.push_back(std::move(grid));
        power.push_back(float(total));
        sampled_[i] = true;
    }
    if (grids_.empty()) return;
    media_ = Distribution1D(power);
    for (size_t gi = 0; gi < grids_.size(); ++gi) {
        Grid& g = grids_[gi];
        g.pdf.assign(media[size_t(g.medium)].emissionGrid.grid->brick.size(), 0.0f);
        for (size_t k = 0; k < g.slot.size(); ++k)
            g.pdf[g.slot[k]] = media_.pmf(int(gi)) * g.bricks.pmf(int(k)) / g.brickVolume;
    }
}

bool VolumeLights::sample(float uPick, Vec3 u3, VolumeLightSample* s) const {
    if (grids_.empty()) return false;
    float pGrid;
    const int gi = media_.sample(uPick, &pGrid);
    // Rescale uPick within the chosen grid's share of [0, 1) for the brick choice.
    double below = 0;
    for (int i = 0; i < gi; ++i) below += media_.pmf(i);
    const float u = std::min(float((uPick - below) / pGrid), 0x1.fffffep-1f);
    const Grid& g = grids_[size_t(gi)];
    float pBrick;
    const int k = g.bricks.sample(std::max(0.0f, u), &pBrick);
    const uint32_t b = g.slot[size_t(k)];
    const int bx = int(b % uint32_t(g.bn[0])), by = int((b / uint32_t(g.bn[0])) % uint32_t(g.bn[1]));
    const int bz = int(b / (uint32_t(g.bn[0]) * uint32_t(g.bn[1])));
    const float B = float(DensityGrid::kBrick);
    const Vec3 local((bx + u3.x) * B, (by + u3.y) * B, (bz + u3.z) * B);
    s->p = g.localToWorld.point(local);
    s->medium = g.medium;
    s->brick = b;
    s->pdf = g.pdf[b];
    return s->pdf > 0;
}

size_t VolumeLights::memoryBytes() const {
    size_t bytes = 0;
    for (const Grid& g : grids_)
        bytes += g.slot.size() * (sizeof(uint32_t) + sizeof(float) + sizeof(double)) + g.pdf.size() * sizeof(float);
    return bytes;
}

}  // namespace brume
