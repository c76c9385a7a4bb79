#include "brume/integrators/allocation_statistics.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "brume/integrators/bdpt_allocation.h"

namespace brume {

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

// For the balance heuristic a path's denominator Σ_k n_k p_k / p_t is linear in the counts,
// and every candidate's counts are 1 for the emitter hit and the free-flight light connection
// and, for the rest, products of its switches (bdpt_allocation.h):
//   T(n) = T_1 + eaLight·T_ea,L + cam·(T_cam + eaCamera·T_ea,C) + p·T_gen,   cam = light tracing.
// So five settings give every candidate's: with everything else off, T_1; then each of the
// four parts on alone. (With --connect equiangular an equi-angular variant replaces the
// free-flight one instead of adding to it, which is not linear: auto does not take that mode.)
void accumulateMoments(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight,
                       MisSettings pilot, const std::vector<BdptAllocation>& candidates,
                       const std::vector<WeightRecord>& records, const PixelWeights& weights, int ownX, int ownY,
                       double* sums) {
    if (records.empty()) return;
    constexpr int kParts = 5;
    thread_local std::vector<double> u[kParts];
    pilot.heuristic = MisHeuristic::Balance;
    MisSettings basis[kParts];
    for (int b = 0; b < kParts; ++b) {
        basis[b] = pilot;
        basis[b].generalConnection = b == 4 ? 1.0 : 0.0;
        basis[b].cameraConnection = b == 2 || b == 3 ? 1.0 : 0.0;
        basis[b].equiAngularLight = b == 1;
        basis[b].equiAngularCamera = b == 3;
        perCounts(scene, camera, nCamera, light, nLight, basis[b], records, u[b]);
    }
    for (size_t i = 0; i < records.size(); ++i) {
        const WeightRecord& r = records[i];
        const float* w = r.x >= 0 ? weights.at(r.x, r.y) : weights.at(ownX, ownY);
        double v2 = 0;
        for (int c = 0; c < 3; ++c) v2 += double(w[c]) * double(r.value[c]) * double(r.value[c]);
        if (!(v2 > 0)) continue;
        // The denominators T = 1/u of the five settings (u: misWeight's perCount), and the parts.
        double T[kParts];
        for (int b = 0; b < kParts; ++b) T[b] = std::isfinite(u[b][i]) && u[b][i] > 0 ? 1.0 / u[b][i] : 0.0;
        const double t1 = T[0], tEaL = std::max(0.0, T[1] - T[0]), tCam = std::max(0.0, T[2] - T[0]),
                     tEaC = std::max(0.0, T[3] - T[2]), tGen = std::max(0.0, T[4] - T[0]);
        auto total = [&](const BdptAllocation& a) {
            const double cam = a.lightSubpaths && a.lightTracing ? 1.0 : 0.0, p = a.lightSubpaths ? a.generalConnection : 0.0;
            return t1 + (a.equiAngularLight ? tEaL : 0.0) + cam * (tCam + (a.equiAngularCamera ? tEaC : 0.0)) + p * tGen;
        };
        BdptAllocation in;  // the counts the sample was made with
        in.lightSubpaths = pilot.generalConnection > 0 || pilot.cameraConnection > 0;
        in.lightTracing = pilot.cameraConnection > 0;
        in.generalConnection = float(pilot.generalConnection);
        in.equiAngularLight = pilot.equiAngularLight;
        in.equiAngularCamera = pilot.equiAngularCamera;
        const double base = total(in);
        if (!(base > 0)) continue;  // (weight 0 in the pilot: no sample)
        // (f/p_t)² · u(pilot) · u(candidate), u = 1/T.
        for (size_t j = 0; j < candidates.size(); ++j) {
            const double tj = total(candidates[j]);
            sums[j] += tj > 0 ? v2 / (base * tj) : std::numeric_limits<double>::infinity();
        }
    }
}

}  // namespace brume
