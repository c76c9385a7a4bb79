#include "brume/integrators/allocation_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

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

namespace {

// A record's denominator T(n) = Σ_k n_k p_k / p_own in parts, each a switch of the allocation
// (below).
struct DenominatorParts {
    double t1 = 0, eaL = 0, cam = 0, eaC = 0, gen = 0, ffL = 0, ffC = 0;
    double total(const BdptAllocation& a) const {
        const double lt = a.lightSubpaths && a.lightTracing ? 1.0 : 0.0, p = a.lightSubpaths ? a.generalConnection : 0.0;
        const double only = a.equiAngularOnly ? 1.0 : 0.0;
        return t1 + (a.equiAngularLight ? eaL - only * ffL : 0.0) + lt * (cam + (a.equiAngularCamera ? eaC - only * ffC : 0.0)) +
               p * gen;
    }
};

// How often candidate a makes the record's strategy (and variant) per sample, over how often
// the pilot made it: 0 where a leaves it out, a general connection's probability ratio.
double countRatio(const WeightRecord& r, const BdptAllocation& a, const BdptAllocation& pilot) {
    const bool general = r.s >= 2 && r.t >= 2;
    if (general) return a.lightSubpaths && pilot.generalConnection > 0 ? double(a.generalConnection) / double(pilot.generalConnection) : 0.0;
    const bool camera = r.t == 1;
    if (camera && !(a.lightSubpaths && a.lightTracing)) return 0.0;
    if (r.s == 0) return 1.0;
    const bool eaOn = camera ? a.equiAngularCamera : a.equiAngularLight;
    if (r.join.equiAngular) return eaOn ? 1.0 : 0.0;
    return r.replaceable && eaOn && a.equiAngularOnly ? 0.0 : 1.0;
}

}  // namespace

// For the balance heuristic a path's denominator Σ_k n_k p_k / p_t is linear in the counts,
// and every candidate's counts are 1 for the emitter hit and the free-flight light connection
// and, for the rest, products of its switches (bdpt_allocation.h):
//   T(n) = T_1 + eaLight·(T_ea,L − only·T_ff,L) + cam·(T_cam + eaCamera·(T_ea,C − only·T_ff,C)) + p·T_gen,
// cam = light tracing, only = equiAngularOnly, T_ff the free-flight variants' terms at the
// vertices where the equi-angular one replaces them. So seven settings give every
// candidate's: with everything else off, T_1; then each of the four parts on alone; then
// each equi-angular part on alone again, ea-only. (--connect equiangular is ea-only
// everywhere: auto does not take that mode.)
void accumulateMoments(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight,
                       MisSettings pilot, const std::vector<BdptAllocation>& candidates,
                       const std::vector<WeightRecord>& records, const PixelWeights& weights, int ownX, int ownY,
                       AllocationMoments& moments) {
    double* sums = moments.candidate;
    if (records.empty()) return;
    constexpr int kParts = 7;
    thread_local std::vector<double> u[kParts];
    pilot.heuristic = MisHeuristic::Balance;
    MisSettings basis[kParts];
    for (int b = 0; b < kParts; ++b) {
        basis[b] = pilot;
        basis[b].generalConnection = b == 4 ? 1.0 : 0.0;
        basis[b].cameraConnection = b == 2 || b == 3 || b == 6 ? 1.0 : 0.0;
        basis[b].equiAngularLight = b == 1 || b == 5;
        basis[b].equiAngularCamera = b == 3 || b == 6;
        basis[b].equiAngularOnly = b >= 5;
        perCounts(scene, camera, nCamera, light, nLight, basis[b], records, u[b]);
    }
    // The denominators T = 1/u of the seven settings (u: misWeight's perCount), as parts.
    auto partsOf = [&](size_t i) {
        double T[kParts];
        for (int b = 0; b < kParts; ++b) T[b] = std::isfinite(u[b][i]) && u[b][i] > 0 ? 1.0 / u[b][i] : 0.0;
        DenominatorParts d;
        d.t1 = T[0];
        d.eaL = std::max(0.0, T[1] - T[0]);
        d.cam = std::max(0.0, T[2] - T[0]);
        d.eaC = std::max(0.0, T[3] - T[2]);
        d.gen = std::max(0.0, T[4] - T[0]);
        d.ffL = std::max(0.0, T[1] - T[5]);
        d.ffC = std::max(0.0, T[3] - T[6]);
        return d;
    };
    BdptAllocation in;  // the counts the sample was made with
    in.lightSubpaths = pilot.generalConnection > 0 || pilot.cameraConnection > 0;
    in.lightTracing = pilot.cameraConnection > 0;
    in.generalConnection = float(pilot.generalConnection);
    in.equiAngularLight = pilot.equiAngularLight;
    in.equiAngularCamera = pilot.equiAngularCamera;
    in.equiAngularOnly = pilot.equiAngularOnly;
    thread_local std::vector<DenominatorParts> parts;
    thread_local std::vector<size_t> order;
    parts.resize(records.size());
    order.clear();
    for (size_t i = 0; i < records.size(); ++i) {
        const WeightRecord& r = records[i];
        const float* w = r.x >= 0 ? weights.at(r.x, r.y) : weights.at(ownX, ownY);
        double v2 = 0;
        for (int c = 0; c < 3; ++c) v2 += double(w[c]) * double(r.value[c]) * double(r.value[c]);
        if (!(v2 > 0)) continue;
        parts[i] = partsOf(i);
        const double base = parts[i].total(in);
        if (!(base > 0)) continue;  // (weight 0 in the pilot: no sample)
        order.push_back(i);
        // M: (f/p_t)² · u(pilot) · u(candidate), u = 1/T.
        for (size_t j = 0; j < candidates.size(); ++j) {
            const double tj = parts[i].total(candidates[j]);
            sums[j] += tj > 0 ? v2 / (base * tj) : std::numeric_limits<double>::infinity();
        }
    }
    // C: the products of the sample's contributions to one pixel, two by two, as each
    // candidate would weight them (header): (Σ_r e_r)² − Σ_r e_r² per pixel and channel,
    // e_r = value · u_r(candidate) · n_r(candidate) / n_r(pilot).
    auto pixel = [&](size_t i) {
        const WeightRecord& r = records[i];
        return r.x >= 0 ? std::make_pair(r.y, r.x) : std::make_pair(ownY, ownX);
    };
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return pixel(a) < pixel(b); });
    for (size_t g = 0; g < order.size();) {
        size_t h = g + 1;
        while (h < order.size() && pixel(order[h]) == pixel(order[g])) ++h;
        if (h - g >= 2) {
            const float* w = weights.at(pixel(order[g]).second, pixel(order[g]).first);
            for (size_t j = 0; j < candidates.size(); ++j) {
                double sum[3] = {0, 0, 0}, squares[3] = {0, 0, 0};
                for (size_t q = g; q < h; ++q) {
                    const WeightRecord& r = records[order[q]];
                    const double tj = parts[order[q]].total(candidates[j]);
                    const double n = countRatio(r, candidates[j], in);
                    if (!(tj > 0) || n == 0) continue;
                    for (int c = 0; c < 3; ++c) {
                        const double e = double(r.value[c]) * n / tj;
                        sum[c] += e;
                        squares[c] += e * e;
                    }
                }
                for (int c = 0; c < 3; ++c) sums[j] += double(w[c]) * (sum[c] * sum[c] - squares[c]);
            }
        }
        g = h;
    }
}

}  // namespace brume
