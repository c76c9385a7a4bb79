#include "brume/integrators/allocation_statistics.h"

#include <cmath>
#include <cstring>

#include "brume/integrators/bdpt_allocation.h"

namespace brume {

MisSettings allocationSettings(MisSettings st, const BdptAllocation& a) {
    st.generalConnection = a.lightSubpaths ? a.generalConnection : 0.0;
    st.cameraConnection = a.lightSubpaths && a.lightTracing ? 1.0 : 0.0;
    st.equiAngularLight = a.equiAngularLight;
    st.equiAngularCamera = a.equiAngularCamera;
    return st;
}

namespace {

// u for every record under settings `st`: the subpaths' sums recomputed, then each record's
// weight with its own vertices in place.
void perCounts(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight, MisSettings st,
               const std::vector<WeightRecord>& records, std::vector<double>& u) {
    misPrefixes(scene, camera, nCamera, true, st);
    misPrefixes(scene, light, nLight, false, st);
    u.resize(records.size());
    for (size_t i = 0; i < records.size(); ++i) {
        const WeightRecord& r = records[i];
        PathVertex* slot = r.moved ? (r.t >= 2 ? &camera[r.t - 1] : &light[r.s - 1]) : nullptr;
        alignas(PathVertex) unsigned char saved[sizeof(PathVertex)];
        if (slot) {
            std::memcpy(saved, static_cast<const void*>(slot), sizeof(PathVertex));
            std::memcpy(static_cast<void*>(slot), static_cast<const void*>(&r.vertex), sizeof(PathVertex));
        }
        PathVertex* lightPath = r.hasLightVertex ? const_cast<PathVertex*>(&r.lightVertex) : light;
        double pc = 0;
        strategyWeight(scene, lightPath, r.s, camera, r.t, r.join, st, &pc);
        u[i] = pc;
        if (slot) std::memcpy(static_cast<void*>(slot), saved, sizeof(PathVertex));
    }
}

}  // namespace

void accumulateMoments(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight,
                       MisSettings pilot, const std::vector<BdptAllocation>& candidates,
                       const std::vector<WeightRecord>& records, const PixelWeights& weights, int ownX, int ownY,
                       double* sums) {
    if (records.empty()) return;
    thread_local std::vector<double> base, u, term;
    pilot.heuristic = MisHeuristic::Balance;
    perCounts(scene, camera, nCamera, light, nLight, pilot, records, base);
    // (f/p_t)² · u(pilot), relative per pixel and channel: the part every candidate shares.
    term.resize(records.size());
    for (size_t i = 0; i < records.size(); ++i) {
        const WeightRecord& r = records[i];
        const float* w = r.x >= 0 ? weights.at(r.x, r.y) : weights.at(ownX, ownY);
        double v2 = 0;
        for (int c = 0; c < 3; ++c) v2 += double(w[c]) * double(r.value[c]) * double(r.value[c]);
        term[i] = std::isfinite(base[i]) ? v2 * base[i] : 0.0;  // (weight 0 in the pilot: no sample)
    }
    for (size_t j = 0; j < candidates.size(); ++j) {
        perCounts(scene, camera, nCamera, light, nLight, allocationSettings(pilot, candidates[j]), records, u);
        double m = 0;
        for (size_t i = 0; i < records.size(); ++i)
            if (term[i] > 0) m += term[i] * u[i];  // (term 0: u may be ∞, the product is still 0)
        sums[j] += m;
    }
}

}  // namespace brume
