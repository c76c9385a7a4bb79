#include "brume/integrators/allocation_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "brume/integrators/bdpt_allocation.h"

namespace brume {

namespace {

// u for every record under each of the settings `st` (lanes, at most kMaxMisLanes):
// u[ℓ][i] = misWeight's perCount of record i under st[ℓ]. The subpaths' sums are found under
// each setting once per sample; each record's vertex (where it moved one) and reverse densities
// are put in place once for all its settings (misPerCountLanes): before, fourteen weight
// evaluations per record, each putting them in place and finding ρ again, were 29 % of a
// partial pilot's time on the forward fog.
void perCounts(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight, const MisSettings* st,
               int lanes, const std::vector<WeightRecord>& records, std::vector<double>* u) {
    thread_local std::vector<MisSums> cameraSums, lightSums;
    cameraSums.resize(size_t(lanes) * size_t(nCamera));
    lightSums.resize(size_t(lanes) * size_t(nLight));
    for (int l = 0; l < lanes; ++l) {
        misPrefixes(scene, camera, nCamera, true, st[l]);
        misPrefixes(scene, light, nLight, false, st[l]);
        copyMisSums(camera, nCamera, cameraSums.data() + size_t(l) * size_t(nCamera));
        copyMisSums(light, nLight, lightSums.data() + size_t(l) * size_t(nLight));
        u[l].resize(records.size());
    }
    for (size_t i = 0; i < records.size(); ++i) {
        const WeightRecord& r = records[i];
        PathVertex* slot = r.moved ? (r.t >= 2 ? &camera[r.t - 1] : &light[r.s - 1]) : nullptr;
        alignas(PathVertex) unsigned char saved[sizeof(PathVertex)];
        if (slot) {
            std::memcpy(saved, static_cast<const void*>(slot), sizeof(PathVertex));
            std::memcpy(static_cast<void*>(slot), static_cast<const void*>(&r.vertex), sizeof(PathVertex));
        }
        PathVertex* lightPath = r.hasLightVertex ? const_cast<PathVertex*>(&r.lightVertex) : light;
        // As strategyWeight: the connection's reverse densities in place, put back after. (They
        // read the film, the guide and where the camera walk passes through media, which the
        // settings share.)
        PathVertex* touched[4];
        connectionNeighbours(lightPath, r.s, camera, r.t, touched);
        Channels before[4];
        for (int k = 0; k < 4; ++k)
            if (touched[k]) before[k] = touched[k]->pdfRev;
        connectionReverseDensities(scene, lightPath, r.s, camera, r.t, r.join, st[0]);
        double pc[kMaxMisLanes];
        misPerCountLanes(scene, lightPath, camera, r.s, r.t, st, lanes, r.join.equiAngular, r.join.crossed,
                         r.join.ownEquiAngularDensity, cameraSums.data(), nCamera, lightSums.data(), nLight, pc);
        for (int l = 0; l < lanes; ++l) u[l][i] = pc[l];
        for (int k = 0; k < 4; ++k)
            if (touched[k]) touched[k]->pdfRev = before[k];
        if (slot) std::memcpy(static_cast<void*>(slot), saved, sizeof(PathVertex));
    }
}

}  // namespace

namespace {

// A record's denominator T(n) = Σ_k n_k p_k / p_own in parts, each a switch of the allocation
// (below).
struct DenominatorParts {
    double t1 = 0, eaL = 0, cam = 0, eaC = 0, gen = 0, ffL = 0, ffC = 0;
    double total(const BdptAllocation& a, MisHeuristic h) const {
        const double lt = a.lightSubpaths && a.lightTracing ? 1.0 : 0.0, p = a.lightSubpaths ? misPower(h, a.generalConnection) : 0.0;
        const double only = a.equiAngularOnly ? 1.0 : 0.0;
        return t1 + (a.equiAngularLight ? eaL - only * ffL : 0.0) + lt * (cam + (a.equiAngularCamera ? eaC - only * ffC : 0.0)) +
               p * gen;
    }
};

// How often allocation a makes the record's strategy (and variant) per sample: 0 where it
// leaves it out, a general connection's probability.
double madeCount(const WeightRecord& r, const BdptAllocation& a) {
    const bool general = r.s >= 2 && r.t >= 2;
    if (general) return a.lightSubpaths ? double(a.generalConnection) : 0.0;
    const bool camera = r.t == 1;
    if (camera && !(a.lightSubpaths && a.lightTracing)) return 0.0;
    if (r.s == 0) return 1.0;
    const bool eaOn = camera ? a.equiAngularCamera : a.equiAngularLight;
    if (r.join.equiAngular) return eaOn ? 1.0 : 0.0;
    return r.replaceable && eaOn && a.equiAngularOnly ? 0.0 : 1.0;
}

}  // namespace

// A path's MIS denominator T(n) = Σ_k (n_k p_k / p_t)^β (β = 1 balance, 2 power; the own
// strategy's weight is n_t^β / T) is linear in the switches of an allocation: every
// candidate's counts are 1 for the emitter hit and the free-flight light connection and, for
// the rest, 0 or 1 by its switches (bdpt_allocation.h), but p for general connections:
//   T(n) = T_1 + eaLight·(T_ea,L − only·T_ff,L) + cam·(T_cam + eaCamera·(T_ea,C − only·T_ff,C)) + p^β·T_gen,
// cam = light tracing, only = equiAngularOnly, T_ff the free-flight variants' terms at the
// vertices where the equi-angular one replaces them. So seven settings give every
// candidate's: with everything else off, T_1; then each of the four parts on alone; then
// each equi-angular part on alone again, ea-only. (--connect equiangular is ea-only
// everywhere: auto does not take that mode.)
void accumulateMoments(const Scene& scene, PathVertex* camera, int nCamera, PathVertex* light, int nLight,
                       MisSettings pilot, const std::vector<BdptAllocation>& candidates,
                       const std::vector<WeightRecord>& records, const PixelWeights& weights, int ownX, int ownY,
                       AllocationMoments& moments, float* own) {
    const int group = AllocationMoments::group(ownX, ownY);
    double* alone = moments.candidate[group];  // M + C, M from the candidate's own strategies' samples alone
    double* combined = moments.combined[group];  // M + C, M through the pilot's weights
    if (records.empty()) return;
    constexpr int kParts = 7;
    // The render's heuristic (β) for the weights; β' = 2β − 1 for M through the pilot's
    // weights (below): Cube where the render's is the power heuristic.
    const MisHeuristic h = pilot.heuristic, hm = h == MisHeuristic::Power ? MisHeuristic::Cube : MisHeuristic::Balance;
    const int sets = hm == h ? 1 : 2;
    thread_local std::vector<double> u[2][kParts];
    MisSettings basis[2 * kParts];
    for (int k = 0; k < sets; ++k)
        for (int b = 0; b < kParts; ++b) {
            MisSettings& st = basis[k * kParts + b];
            st = pilot;
            st.heuristic = k == 0 ? h : hm;
            st.generalConnection = b == 4 ? 1.0 : 0.0;
            st.cameraConnection = b == 2 || b == 3 || b == 6 ? 1.0 : 0.0;
            st.equiAngularLight = b == 1 || b == 5;
            st.equiAngularCamera = b == 3 || b == 6;
            st.equiAngularOnly = b >= 5;
        }
    static_assert(2 * kParts <= kMaxMisLanes, "the settings are lanes of one evaluation");
    perCounts(scene, camera, nCamera, light, nLight, basis, sets * kParts, records, &u[0][0]);
    // The denominators T = 1/u of the seven settings (u: misWeight's perCount), as parts.
    auto partsOf = [&](int k, size_t i) {
        double T[kParts];
        for (int b = 0; b < kParts; ++b) T[b] = std::isfinite(u[k][b][i]) && u[k][b][i] > 0 ? 1.0 / u[k][b][i] : 0.0;
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
    // What candidate j would add to the pixel from record i, per unit of its unweighted value:
    // its weight w' = n'^β / T', over how often the pilot made the strategy, n (a connection
    // the pilot makes with probability p stands for one the candidate makes with p').
    // Negative: no strategy of the candidate makes the path (it would be biased).
    thread_local std::vector<double> factor;
    thread_local std::vector<size_t> order;
    const size_t nc = candidates.size();
    factor.assign(records.size() * nc, 0.0);
    order.clear();
    for (size_t i = 0; i < records.size(); ++i) {
        const WeightRecord& r = records[i];
        const float* w = r.x >= 0 ? weights.at(r.x, r.y) : weights.at(ownX, ownY);
        double v2 = 0;
        for (int c = 0; c < 3; ++c) v2 += double(w[c]) * double(r.value[c]) * double(r.value[c]);
        if (!(v2 > 0)) continue;
        const DenominatorParts d = partsOf(0, i), dm = sets == 2 ? partsOf(1, i) : d;
        const double n = madeCount(r, in), base = d.total(in, h);
        if (!(n > 0) || !(base > 0)) continue;  // (weight 0 in the pilot: no sample)
        order.push_back(i);
        // M (header). Combined: the pilot's weight n^β / T_pilot times G / (n p_t), which is
        // v2 · n^(β−1) · T'_{2β−1} / (T'_β² · T_pilot). Alone: the candidate's contribution
        // squared per sample it makes (n' of them, each n/n' times as likely in the pilot's
        // sample), v2 · w'² / (n · n').
        const double nb = h == MisHeuristic::Power ? n : 1.0;
        for (size_t j = 0; j < nc; ++j) {
            const double tj = d.total(candidates[j], h);
            if (!(tj > 0)) {
                alone[j] = combined[j] = std::numeric_limits<double>::infinity();
                factor[i * nc + j] = -1.0;
                continue;
            }
            combined[j] += v2 * nb * dm.total(candidates[j], hm) / (tj * tj * base);
            const double nj = madeCount(r, candidates[j]);
            if (nj == 0) continue;
            const double wj = misPower(h, nj) / tj;
            alone[j] += v2 * wj * wj / (n * nj);
            factor[i * nc + j] = wj / n;
            if (own && r.x < 0)
                for (int c = 0; c < 3; ++c) own[3 * j + size_t(c)] += float(double(r.value[c]) * wj / n);
        }
    }
    // C: the products of the sample's contributions to one pixel, two by two, as each
    // candidate would weight them (header): (Σ_r e_r)² − Σ_r e_r² per pixel and channel,
    // e_r = value · w'_r / n_r.
    auto pixel = [&](size_t i) {
        const WeightRecord& r = records[i];
        return r.x >= 0 ? std::make_pair(r.y, r.x) : std::make_pair(ownY, ownX);
    };
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return pixel(a) < pixel(b); });
    for (size_t g = 0; g < order.size();) {
        size_t e = g + 1;
        while (e < order.size() && pixel(order[e]) == pixel(order[g])) ++e;
        if (e - g >= 2) {
            const float* w = weights.at(pixel(order[g]).second, pixel(order[g]).first);
            for (size_t j = 0; j < nc; ++j) {
                double sum[3] = {0, 0, 0}, squares[3] = {0, 0, 0};
                for (size_t q = g; q < e; ++q) {
                    const WeightRecord& r = records[order[q]];
                    const double f = factor[order[q] * nc + j];
                    if (!(f > 0)) continue;
                    for (int c = 0; c < 3; ++c) {
                        const double v = double(r.value[c]) * f;
                        sum[c] += v;
                        squares[c] += v * v;
                    }
                }
                for (int c = 0; c < 3; ++c) {
                    alone[j] += double(w[c]) * (sum[c] * sum[c] - squares[c]);
                    combined[j] += double(w[c]) * (sum[c] * sum[c] - squares[c]);
                }
            }
        }
        g = e;
    }
}

}  // namespace brume
