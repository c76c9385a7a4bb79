#include "brume/integrators/integrator.h"

namespace brume {

void addPassExact(const PassSummary& s, std::vector<FixedSum>& sums) {
    const size_t n = size_t(s.width) * size_t(s.height);
    if (sums.size() != 3 * n) sums.assign(3 * n, FixedSum(0));
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) sums[3 * i + size_t(c)] += toFixed(s.radiance[i][c]);
    for (int l = 0; l < s.splatLists; ++l)
        for (const SplatList::Record& r : s.splats[l].records())
            if (r.x >= 0 && r.y >= 0 && r.x < s.width && r.y < s.height)
                for (int c = 0; c < 3; ++c) sums[3 * (size_t(r.y) * size_t(s.width) + size_t(r.x)) + size_t(c)] += toFixed(r.value[c]);
}

Spectrum SplattingIntegrator::sample(const Scene& scene, float fx, float fy, int width, int height,
                                     Sampler& sampler, PathStats& stats) const {
    thread_local SplatList discarded;
    discarded.clear();
    return sampleWithSplats(scene, fx, fy, width, height, sampler, stats, discarded);
}

}  // namespace brume
