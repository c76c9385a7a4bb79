// Samples taken on one exact film position, outside the renderer (which jitters inside the
// pixel, so it never hits a single ray): every returned value and every splat must be finite.
#pragma once
#include <cstdint>

#include "brume/integrators/bdpt.h"
#include "brume/film/film.h"
#include "brume/render/renderer.h"

namespace brume::test {

struct ExactRayResult {
    long samples = 0, nonFinite = 0, splatsDropped = 0;
    double mean = 0;  // of the returned values (channel average), splats not included
};

inline ExactRayResult sampleExactRay(const Scene& scene, const Integrator& integrator, float fx, float fy, int width,
                                     int height, int samples, uint64_t seed) {
    ExactRayResult r;
    PathStats stats;
    SplatList splats;
    const auto* splatting = dynamic_cast<const SplattingIntegrator*>(&integrator);
    for (int s = 0; s < samples; ++s) {
        Sampler sampler(seed, uint64_t(fy) * width + uint64_t(fx), uint64_t(s));
        splats.clear();
        Spectrum L = splatting ? splatting->sampleWithSplats(scene, fx, fy, width, height, sampler, stats, splats)
                               : integrator.sample(scene, fx, fy, width, height, sampler, stats);
        ++r.samples;
        if (!isFinite(L)) ++r.nonFinite;
        else r.mean += (double(L.x) + L.y + L.z) / 3.0;
        r.splatsDropped += long(splats.nonFinite());
    }
    r.mean /= double(r.samples);
    return r;
}

}  // namespace brume::test
