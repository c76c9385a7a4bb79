#include "brume/integrators/integrator.h"

namespace brume {

Spectrum SplattingIntegrator::sample(const Scene& scene, float fx, float fy, int width, int height,
                                     Sampler& sampler, PathStats& stats) const {
    thread_local SplatList discarded;
    discarded.clear();
    return sampleWithSplats(scene, fx, fy, width, height, sampler, stats, discarded);
}

}  // namespace brume
