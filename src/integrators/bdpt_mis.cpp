#include "brume/integrators/bdpt_mis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "brume/integrators/bdpt_equiangular.h"
#include "brume/integrators/light_numbers.h"
#include "brume/sampling/equiangular.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"

// Notation (docs/mis.md): the full path x0 (pinhole) … xk (light); strategy (s, t) has camera
// vertices z_i = x_i, i < t, and light vertices y_i = x(k−i), i < s. With r_m the density
// ratio pdfRev/pdfFwd at a vertex and V_j the variant factor of the strategy with j camera
// vertices (1, or more with an equi-angular variant), the weight's denominator is
//   own + Σ_{i=1}^{t−1} Π_{m=i}^{t−1} r(z_m)^β V_i + c · Σ_{i=0}^{s−1} Π_{m=i}^{s−1} r(y_m)^β V_{t+s−i}
// (c = ρ_own^−β for an equi-angular light connection, else 1; terms whose connection has a
// specular end are left out). Both sums obey P(j) = r_j^β (V_j + P(j−1)); a connection alters
// only r and V at the two vertices next to it on each side (their pdfRev and the variant
// anchors), so P up to three vertices away comes from the subpath alone: misPrefixes.
namespace brume {

namespace {

// The MIS sums kept in the vertices: without coloured media one sum in double; with them one
// per channel, computed in long double (ratios between channels are what leaves double's
// range) and stored as its logarithm in double, to keep the vertices small.
template <class Real> struct Sums;
template <> struct Sums<double> {
    template <class V> static double prefix(const V& v, int) { return v.misPrefixGrey; }
    template <class V> static ChannelsOf<double> variant(const V& v) { return ChannelsOf<double>(v.misVariantGrey); }
    static void set(PathVertex& v, int, double prefix) { v.misPrefixGrey = prefix; }
    static void setVariant(PathVertex& v, const ChannelsOf<double>& V) { v.misVariantGrey = V[0]; }
};
// A stored logarithm back to its value, and a value to its logarithm: in double where the
// value lies inside double's range, which is nearly always so (long double's exp and log cost
// about 5× double's: a quarter of a coloured pass went to them), in long double beyond it.
// (Sums of zero, log −∞, are common: strategies a lane leaves out.)
long double wideExp(double x) {
    if (std::fabs(x) < 700.0) return (long double)std::exp(x);
    return x == -std::numeric_limits<double>::infinity() ? 0.0L : std::exp((long double)x);
}
double wideLog(long double v) {
    if (v > 1e-300L && v < 1e300L) return std::log(double(v));
    return v == 0.0L ? -std::numeric_limits<double>::infinity() : double(std::log(v));  // (logl(0) takes libm's error path)
}

template <> struct Sums<long double> {  // kept as natural logarithms in double (log 0 = −∞)
    template <class V> static long double prefix(const V& v, int c) { return wideExp(v.misPrefix[c]); }
    template <class V> static WideChannels variant(const V& v) {
        return WideChannels(wideExp(v.misVariant[0]), wideExp(v.misVariant[1]), wideExp(v.misVariant[2]));
    }
    static void set(PathVertex& v, int c, long double prefix) { v.misPrefix[c] = wideLog(prefix); }
    static void setVariant(PathVertex& v, const WideChannels& V) {
        for (int c = 0; c < 3; ++c) v.misVariant[c] = wideLog(V[c]);
    }
};

// Where misWeight reads the subpaths' sums: in the vertices (one setting), or per lane in
// copies (misPerCountLanes; the vertex at index i of a side, under lane ℓ's settings).
struct VertexSums {
    const PathVertex& at(const PathVertex* path, bool, int i, int) const { return path[i]; }
};
struct LaneSums {
    const MisSums* camera;
    int cameraStride;
    const MisSums* light;
    int lightStride;
    const MisSums& at(const PathVertex*, bool cameraSide, int i, int lane) const {
        return cameraSide ? camera[size_t(lane) * size_t(cameraStride) + size_t(i)] : light[size_t(lane) * size_t(lightStride) + size_t(i)];
    }
};

double remap0(double f) { return f != 0 ? f : 1.0; }

// r^β at a vertex in channel c; zero densities (specular vertices) are mapped to 1 so that
// they cancel.
template <class Real>
Real ratioPow(MisHeuristic h, const PathVertex& v, int c) {
    return misPower(h, Real(remap0(v.pdfRev[c])) / Real(remap0(v.pdfFwd[c])));
}

// ρ_c = p_ea / p_ff,c for a camera-side medium vertex v reached from p and joined to a. In
// Real, as all the sums below: far along a ray a dense channel's free-flight density
// can be 1e-180 where the equi-angular one is 1e-10, and ρ² leaves double's range.
template <class Real, int N>
ChannelsOf<Real> equiAngularRatio(const Scene& scene, const PathVertex& p, const PathVertex& v, const PathVertex& a,
                              bool aEndsPath, MisSettings st) {
    using RC = ChannelsOf<Real>;
    if (!v.isMedium() || p.delta) return RC(Real(0));
    EquiAngularAim aim = equiAngularAim(scene, a, aEndsPath);
    if (!aim.valid) return RC(Real(0));
    float dist = length(v.p - p.p);
    if (!(dist > 0)) return RC(Real(0));
    Channels pff = v.medium->transit(Ray{p.p, (v.p - p.p) / dist, dist}, 0.0f, dist, false, true).fwd;
    RC rho(Real(0));
    Real pea = -1;
    for (int c = 0; c < N; ++c) {
        if (!(pff[c] > 0)) continue;
        if (pea < 0) pea = equiAngularDensity(scene, p, v, aim, st);
        rho[c] = pea / pff[c];
    }
    return rho;
}

// V for the strategy whose connection vertex v (camera side, reached from prev over an edge
// that crossed a boundary or not) is joined to `anchor` (the path's last vertex or not):
// [free flight on] + [equi-angular on] · ρ^β, per channel, under each of L settings (lanes,
// misPerCountLanes: they share ρ and the light's pick; a lane's count of camera connections is
// cameraCount[ℓ]). rho[ℓ] receives ρ (0: no equi-angular variant). `general`: the strategy is a
// general connection (s, t ≥ 2), which has an equi-angular variant only with
// MisSettings::generalEquiAngular and is made with probability MisSettings::generalConnection.
// freeFlightOff: v is the camera walk's vertex MisSettings::passFirstAt, which it never makes
// in a medium.
template <class Real, int N, int L>
void variantFactors(const Scene& scene, const PathVertex& prev, const PathVertex& v, const PathVertex& anchor,
                    bool anchorEndsPath, bool general, bool edgeCrossed, const MisSettings* st, const double* cameraCount,
                    ChannelsOf<Real>* V, ChannelsOf<Real>* rho, bool freeFlightOff = false) {
    using RC = ChannelsOf<Real>;
    // The strategy's kind: a general connection, a light connection (s = 1: the anchor ends
    // the path) or a camera connection (t = 1), and whether the allocation gives it an
    // equi-angular variant.
    const bool cameraConnection = !general && !anchorEndsPath;
    bool eaAllowed[L], anyAllowed = false;
    for (int l = 0; l < L; ++l) {
        eaAllowed[l] = general ? st[l].generalEquiAngular : anchorEndsPath ? st[l].equiAngularLight : st[l].equiAngularCamera;
        anyAllowed = anyAllowed || eaAllowed[l];
    }
    const bool eaPossible = st[0].connect != ConnectMode::Density && v.isMedium() && !edgeCrossed;
    RC r(Real(0));
    if (eaPossible && anyAllowed) r = equiAngularRatio<Real, N>(scene, prev, v, anchor, anchorEndsPath, st[0]);
    // A general connection is made with probability p: its densities count p times; a camera
    // connection as often as the allocation makes it (0 or 1). A light connection picks its
    // light by where it starts, every other strategy by power: its density is the light
    // subpath's start (the anchor's pdfFwd) times λ = its pick over power's (light_numbers.h).
    const bool picks = anchorEndsPath && anchor.light >= 0;
    const double pick = picks ? lightConnectionPickRatio(scene, prev.p, v.p, v.isMedium(), anchor.light) : 1.0;
    for (int l = 0; l < L; ++l) {
        const RC rl = eaAllowed[l] ? r : RC(Real(0));
        if (rho) rho[l] = rl;
        RC Vl(Real(1));
        for (int c = 0; c < N; ++c) {
            bool eaOn = rl[c] > 0;
            bool ffOn = !((equiAngularReplacesFreeFlight(st[l]) || freeFlightOff) && eaOn);
            Vl[c] = (ffOn ? Real(1) : Real(0)) + (eaOn ? misPower(st[l].heuristic, rl[c]) : Real(0));
        }
        double count = general ? st[l].generalConnection : cameraConnection ? cameraCount[l] : 1.0;
        if (picks) count *= pick;
        if (count != 1.0) Vl *= misPower(st[l].heuristic, Real(count));
        V[l] = Vl;
    }
}

// The same under one setting.
template <class Real, int N>
ChannelsOf<Real> variantFactor(const Scene& scene, const PathVertex& prev, const PathVertex& v, const PathVertex& anchor,
                               bool anchorEndsPath, bool general, bool edgeCrossed, MisSettings st, ChannelsOf<Real>* rho,
                               bool freeFlightOff = false) {
    ChannelsOf<Real> V;
    variantFactors<Real, N, 1>(scene, prev, v, anchor, anchorEndsPath, general, edgeCrossed, &st, &st.cameraConnection, &V,
                               rho, freeFlightOff);
    return V;
}

template <class Real, int N>
void misPrefixesIn(const Scene& scene, PathVertex* path, int n, bool cameraSide, MisSettings st) {
    using RC = ChannelsOf<Real>;
    const MisHeuristic h = st.heuristic;
    if (cameraSide) {
        // V_j (j camera vertices): z(j−1) reached from z(j−2), joined to z(j); for j = 1 the
        // camera connection: x1 reached from x2, joined to the pinhole.
        if (n > 0) {
            for (int c = 0; c < N; ++c) Sums<Real>::set(path[0], c, Real(0));
            Sums<Real>::setVariant(path[0], RC(Real(1)));
        }
        for (int j = 1; j < n; ++j) {
            // (Prefixes are read only up to z(t−3), so z(j) never ends the path here: for j ≥ 2
            // the strategy is a general connection.)
            const RC V = j >= 2 ? variantFactor<Real, N>(scene, path[j - 2], path[j - 1], path[j], false, true, path[j - 1].edgeCrossed, st, nullptr)
                         : n >= 3   ? variantFactor<Real, N>(scene, path[2], path[1], path[0], false, false, path[2].edgeCrossed, st, nullptr)
                                    : RC(misPower(h, Real(st.cameraConnection)));
            Sums<Real>::setVariant(path[j], V);
            const bool on = !path[j].delta && !path[j - 1].delta;
            for (int c = 0; c < N; ++c)
                Sums<Real>::set(path[j], c, ratioPow<Real>(h, path[j], c) * ((on ? V[c] : Real(0)) + Sums<Real>::prefix(path[j - 1], c)));
        }
        return;
    }
    // Light side, y_i moved to the camera side: y_i reached from y(i+1), joined to y(i−1)
    // (no variant for i = 0: the strategy would have no light vertex to aim at).
    for (int i = 0; i < n; ++i) {
        const RC V = i >= 1 && i + 1 < n
                         ? variantFactor<Real, N>(scene, path[i + 1], path[i], path[i - 1], i == 1, i >= 2, path[i + 1].edgeCrossed, st, nullptr)
                         : RC(Real(1));
        Sums<Real>::setVariant(path[i], V);
        bool deltaBefore = i > 0 ? path[i - 1].delta : path[0].deltaLight;
        const bool on = !path[i].delta && !deltaBefore;
        for (int c = 0; c < N; ++c)
            Sums<Real>::set(path[i], c, ratioPow<Real>(h, path[i], c) *
                                           ((on ? V[c] : Real(0)) + (i > 0 ? Sums<Real>::prefix(path[i - 1], c) : Real(0))));
    }
}

// The light subpath's prefix P(j) (misPrefixes) for a path of k + 1 vertices some of whose
// light vertices the camera walk would reach by passing through media (MisSettings::passFrom,
// passFirstAt): their reverse densities then lose their free-flight factor (a medium vertex
// at passFirstAt keeps it, and its strategy loses its free-flight variant instead), and a
// medium vertex at passFirstAt rules out the emitter hit beyond it (s = 0). Summed afresh for
// every channel at once, O(j), into q[ℓ] for each lane; only the longest paths a --max-depth
// allows need it.
template <class Real, int N, int L, class Store>
void passedLightPrefix(const Scene& scene, const PathVertex* light, int j, int k, bool emitterHitOff,
                       const MisSettings* st, const double* cameraCount, const Store& sums, ChannelsOf<Real>* q) {
    using RC = ChannelsOf<Real>;
    const MisSettings& s0 = st[0];  // (what the lanes share)
    for (int l = 0; l < L; ++l) q[l] = RC(Real(0));
    for (int i = 0; i <= j; ++i) {
        const int ci = k - i;  // y_i as the camera walk's vertex
        const bool passes = cameraWalkPasses(s0, ci, light[i + 1].delta) && !(light[i].isMedium() && ci < s0.passFrom);
        double rev = -1;  // the camera walk's density without free flight (−1: the stored one serves)
        if (passes && !(i == 0 && light[0].deltaLight)) {
            // y_i made from y(i+1), which the camera walk reached from y(i+2) (i ≤ j ≤ s − 3).
            Vec3 w = light[i + 1].p - light[i].p;
            const float d = length(w);
            w = d > 0 ? w / d : Vec3(0.0f);
            rev = solidAngleToArea(
                light[i], w,
                vertexDirectionPdf(scene, light[i + 1], normalize(light[i + 2].p - light[i + 1].p), -w, s0.width, s0.height,
                                   s0.cameraGuide),
                d);
        }
        const bool deltaBefore = i > 0 ? light[i - 1].delta : light[0].deltaLight;
        const bool on = !light[i].delta && !deltaBefore && !(i == 0 && emitterHitOff);
        RC V[L];
        for (int l = 0; l < L; ++l) V[l] = RC(Real(0));
        if (on) {
            if (i >= 1 && ci == s0.passFirstAt)
                variantFactors<Real, N, L>(scene, light[i + 1], light[i], light[i - 1], i == 1, i >= 2, light[i + 1].edgeCrossed,
                                           st, cameraCount, V, nullptr, true);
            else
                for (int l = 0; l < L; ++l) V[l] = Sums<Real>::variant(sums.at(light, false, i, l));
        }
        for (int l = 0; l < L; ++l)
            for (int c = 0; c < N; ++c) {
                const MisHeuristic h = st[l].heuristic;
                const Real r = rev >= 0 ? misPower(h, Real(remap0(rev)) / Real(remap0(light[i].pdfFwd[c])))
                                        : ratioPow<Real>(h, light[i], c);
                q[l][c] = r * (V[l][c] + q[l][c]);
            }
    }
}

// The weight of strategy (s, t) under each of L settings (lanes; one for misWeight): weight[ℓ]
// and perCount[ℓ] (misWeight's *perCount). The settings differ only in what misPerCountLanes
// allows; the subpaths' sums are read through `sums`.
template <class Real, int N, int L, class Store>
void misWeightIn(const Scene& scene, const PathVertex* light, const PathVertex* camera, int s, int t, const MisSettings* st,
                 bool ownEquiAngular, bool connectionCrossed, double ownEquiAngularDensity, const Store& sums, double* weight,
                 double* perCount) {
    using RC = ChannelsOf<Real>;
    const MisSettings& s0 = st[0];  // (what the lanes share)
    const int k = s + t - 1;  // vertices x0 … xk
    // Paths of one scattering event: the camera connection's count times the learned factor
    // (no prefix is read for them, so every term below sees it), or 0 for the camera side
    // alone.
    const bool lightTracingAlone = k == 2 && s0.directAlone == MisSettings::Alone::LightTracing;
    double cameraCount[L];
    for (int l = 0; l < L; ++l) {
        cameraCount[l] = st[l].cameraConnection;
        if (k == 2) cameraCount[l] *= st[l].directAlone == MisSettings::Alone::CameraSide ? 0.0 : st[l].directLightTracing;
    }
    auto at = [&](int m) -> const PathVertex& { return m < t ? camera[m] : light[k - m]; };
    auto crossed = [&](int m) {  // the edge x(m−1)–x(m)
        if (m < t) return camera[m].edgeCrossed;
        if (m - 1 >= t) return at(m - 1).edgeCrossed;  // light subpath: stored on its later vertex
        return connectionCrossed;
    };
    // V_tt on the joined path (tt camera vertices), per lane.
    auto variants = [&](int tt, RC* V, RC* rho) {
        if (tt >= 2 && k + 1 - tt >= 1) {
            variantFactors<Real, N, L>(scene, at(tt - 2), at(tt - 1), at(tt), tt == k, tt < k, crossed(tt - 1), st,
                                       cameraCount, V, rho, tt - 1 == s0.passFirstAt);
        } else if (tt == 1 && k >= 2) {
            variantFactors<Real, N, L>(scene, at(2), at(1), at(0), false, false, crossed(2), st, cameraCount, V, rho);
        } else {
            for (int l = 0; l < L; ++l) {
                if (rho) rho[l] = RC(Real(0));
                V[l] = RC(tt == 1 ? misPower(st[l].heuristic, Real(cameraCount[l])) : Real(1));
            }
        }
    };
    // The V terms next to the connection, per channel (each may cost an equi-angular density).
    RC rhoOwn[L];
    RC ownV[L];  // (not read for an equi-angular sample)
    for (int l = 0; l < L; ++l) rhoOwn[l] = ownV[l] = RC(Real(0));
    if (ownEquiAngular && ownEquiAngularDensity > 0) {
        // ρ of the moved vertex from its placement: p_ea over the free flight of its edge.
        const Channels& pff = (t >= 2 ? camera[t - 1] : light[s - 1]).edgeFwdFreeFlight;
        for (int l = 0; l < L; ++l)
            for (int c = 0; c < N; ++c) rhoOwn[l][c] = pff[c] > 0 ? Real(ownEquiAngularDensity) / Real(pff[c]) : Real(0);
    } else {
        variants(t, ownV, rhoOwn);
    }
    RC camV[2][L], lightV[2][L];
    bool camOn[2] = {false, false}, lightOn[2] = {false, false};
    // A medium vertex at the camera walk's index passFirstAt, which that walk never makes:
    // the emitter hit beyond it (s = 0) cannot make this path.
    const bool emitterHitOff = k == s0.passFirstAt + 1 && at(k - 1).isMedium() && !at(k - 2).delta;
    for (int i = std::max(1, t - 2); i <= t - 1; ++i) {
        int reads = std::max(i, 2);  // the last camera vertex V_i looks at
        bool own = (reads < t - 1 || (reads == t - 1 && !ownEquiAngular && s >= 1)) && i - 1 != s0.passFirstAt;
        int slot = i - (t - 2);
        camOn[slot] = !camera[i].delta && !camera[i - 1].delta;
        if (!camOn[slot]) continue;
        if (own)
            for (int l = 0; l < L; ++l) camV[slot][l] = Sums<Real>::variant(sums.at(camera, true, i, l));
        else
            variants(i, camV[slot], nullptr);
    }
    for (int i = std::max(0, s - 2); i <= s - 1; ++i) {
        bool own = i == s - 2 && !(t == 1 && ownEquiAngular) && t + s - i - 1 != s0.passFirstAt;
        bool deltaBefore = i > 0 ? light[i - 1].delta : light[0].deltaLight;
        int slot = i - (s - 2);
        lightOn[slot] = !light[i].delta && !deltaBefore && !(i == 0 && emitterHitOff);
        if (!lightOn[slot]) continue;
        if (own)
            for (int l = 0; l < L; ++l) lightV[slot][l] = Sums<Real>::variant(sums.at(light, false, i, l));
        else
            variants(t + s - i, lightV[slot], nullptr);
    }
    // The own strategy's density in channel c relative to the hero channel's (path_vertex.h).
    const Channels own = s >= 1 ? camera[t - 1].channelRatio * light[s - 1].channelRatio : camera[t - 1].channelRatio;

    // The own strategy's count (a general connection is made with probability p, a camera
    // connection 0 or 1 times): the numerator of its weight, and a factor of its own terms
    // (ownV has it already). Its equi-angular variant's count is 1 or 0 on top of that.
    // A light connection's own density has its pick's λ too (variantFactor), which ownV holds.
    const double ownPick = s == 1 && t >= 2 && light[0].light >= 0
                               ? lightConnectionPickRatio(scene, camera[t - 2].p, camera[t - 1].p, camera[t - 1].isMedium(),
                                                          light[0].light)
                               : 1.0;
    // The light prefix P(s − 3), summed afresh where the camera walk passes through media at
    // the indices of its vertices (passedLightPrefix).
    const bool passedPrefix = s >= 3 && (k >= s0.passFrom || k == s0.passFirstAt || k == s0.passFirstAt + 1);
    RC passedQ[L];
    if (passedPrefix) passedLightPrefix<Real, N, L>(scene, light, s - 3, k, emitterHitOff, st, cameraCount, sums, passedQ);
    for (int l = 0; l < L; ++l) {
        const MisHeuristic h = st[l].heuristic;
        const Real ownCount =
            misPower(h, Real((s >= 2 && t >= 2 ? st[l].generalConnection : t == 1 ? cameraCount[l] : 1.0) * ownPick));
        const bool ownEaAllowed = t == 1 ? st[l].equiAngularCamera : s == 1 ? st[l].equiAngularLight : st[l].generalEquiAngular;
        Real total = 0;
        for (int c = 0; c < N; ++c) {
            // The equi-angular sample's z(t−1) carries its equi-angular density as pdfFwd (the
            // free-flight one may underflow far from where free flight goes), so all ratios are
            // then relative to the equi-angular variant: its own term is 1 and the free-flight
            // one 1/ρ.
            Real sum = ownV[l][c];
            if (ownEquiAngular) {
                bool ffOn = !(equiAngularReplacesFreeFlight(st[l]) && ownEaAllowed) && t - 1 != s0.passFirstAt;
                sum = ownCount * (Real(ownEaAllowed ? 1 : 0) +
                                  (ffOn && rhoOwn[l][c] > 0 ? misPower(h, Real(1) / rhoOwn[l][c]) : Real(0)));
            }
            // Camera side: P(t−1) from P(t−3). V_i is the subpath's own unless it reads z(t−1)
            // moved by an equi-angular sample, or z(t−1) ends the path on an emitter (s = 0: the
            // subpath's V treats no camera vertex as the light), or (for i = 1, t = 2) the light
            // side.
            Real p = t - 3 >= 1 ? Sums<Real>::prefix(sums.at(camera, true, t - 3, l), c) : Real(0);
            for (int i = std::max(1, t - 2); i <= t - 1; ++i) {
                int slot = i - (t - 2);
                p = ratioPow<Real>(h, camera[i], c) * ((camOn[slot] ? camV[slot][l][c] : Real(0)) + p);
            }
            sum += p;
            // Light side: P(s−1) from P(s−3). Strategies with more camera vertices keep z(t−1) on
            // the camera side, made by free flight: relative to an equi-angular light connection
            // that is a factor 1/ρ_own. (For t = 1 the equi-angular vertex is y(s−1), which every
            // other strategy moves to the camera side.) V for y(s−2) is the subpath's own unless
            // y(s−1) is an equi-angular camera connection's.
            Real q = s - 3 >= 0 ? (passedPrefix ? passedQ[l][c] : Sums<Real>::prefix(sums.at(light, false, s - 3, l), c))
                                : Real(0);
            for (int i = std::max(0, s - 2); i <= s - 1; ++i) {
                int slot = i - (s - 2);
                q = ratioPow<Real>(h, light[i], c) * ((lightOn[slot] ? lightV[slot][l][c] : Real(0)) + q);
            }
            Real cf = ownEquiAngular && t >= 2 && rhoOwn[l][c] > 0 ? misPower(h, Real(1) / rhoOwn[l][c]) : Real(1);
            // (Light tracing alone: t = 1, and q holds every other strategy.)
            if (!lightTracingAlone) sum += cf * q;
            // Over channels: the other channels' densities of every strategy relative to the
            // hero's of this one (docs/mis.md, "coloured media").
            total += misPower(h, Real(own[c])) * sum;
        }
        // One channel of st.channels was drawn: the estimate is divided by its probability.
        // (The weight over the own count alone: a light connection's λ stays in it.)
        perCount[l] = total > 0 ? double(N * misPower(h, Real(ownPick)) / total) : double(kInfinity);
        weight[l] = total > 0 ? double(N * ownCount / total) : 0.0;
    }
}

}  // namespace

void misPrefixes(const Scene& scene, PathVertex* path, int n, bool cameraSide, MisSettings st) {
    if (st.channels == 1) misPrefixesIn<double, 1>(scene, path, n, cameraSide, st);
    else misPrefixesIn<long double, 3>(scene, path, n, cameraSide, st);
}

double misWeight(const Scene& scene, const PathVertex* light, const PathVertex* camera, int s, int t, MisSettings st,
                 bool ownEquiAngular, bool connectionCrossed, double ownEquiAngularDensity, double* perCount) {
    double w = 0, pc = 0;
    if (st.channels == 1)
        misWeightIn<double, 1, 1>(scene, light, camera, s, t, &st, ownEquiAngular, connectionCrossed, ownEquiAngularDensity,
                                  VertexSums{}, &w, &pc);
    else
        misWeightIn<long double, 3, 1>(scene, light, camera, s, t, &st, ownEquiAngular, connectionCrossed,
                                       ownEquiAngularDensity, VertexSums{}, &w, &pc);
    if (perCount) *perCount = pc;
    return w;
}

void copyMisSums(const PathVertex* path, int n, MisSums* out) {
    for (int i = 0; i < n; ++i) {
        out[i].misPrefixGrey = path[i].misPrefixGrey;
        out[i].misVariantGrey = path[i].misVariantGrey;
        out[i].misPrefix = path[i].misPrefix;
        out[i].misVariant = path[i].misVariant;
    }
}

void misPerCountLanes(const Scene& scene, const PathVertex* light, const PathVertex* camera, int s, int t,
                      const MisSettings* settings, int lanes, bool ownEquiAngular, bool connectionCrossed,
                      double ownEquiAngularDensity, const MisSums* cameraSums, int cameraStride, const MisSums* lightSums,
                      int lightStride, double* perCount) {
    const LaneSums sums{cameraSums, cameraStride, lightSums, lightStride};
    double w[kMaxMisLanes];
    const bool grey = settings[0].channels == 1;
    if (lanes == 7 && grey)
        misWeightIn<double, 1, 7>(scene, light, camera, s, t, settings, ownEquiAngular, connectionCrossed,
                                  ownEquiAngularDensity, sums, w, perCount);
    else if (lanes == 7)
        misWeightIn<long double, 3, 7>(scene, light, camera, s, t, settings, ownEquiAngular, connectionCrossed,
                                       ownEquiAngularDensity, sums, w, perCount);
    else if (lanes == 14 && grey)
        misWeightIn<double, 1, 14>(scene, light, camera, s, t, settings, ownEquiAngular, connectionCrossed,
                                   ownEquiAngularDensity, sums, w, perCount);
    else if (lanes == 14)
        misWeightIn<long double, 3, 14>(scene, light, camera, s, t, settings, ownEquiAngular, connectionCrossed,
                                        ownEquiAngularDensity, sums, w, perCount);
    else
        throw std::logic_error("misPerCountLanes: 7 or 14 lanes");
}

// The reverse densities a connection determines, with w the unit direction z(t−1) → y(s−1)
// and d their distance; every one is (direction density at the vertex that would make it) ×
// (solid angle → area) × (free flight of that step), as in randomWalk (the direction
// densities of y(s−1) and y(s−2) are the camera walk's: guided with MisSettings::cameraGuide):
//   z(t−1)  made from y(s−1) (which came from y(s−2), or is on the light): the connection's
//           free flight towards the camera; for s = 0, z(t−1) lies on the light and would have
//           been its start: pick · position density;
//   y(s−1)  made from z(t−1) (which came from z(t−2), or is the pinhole): the connection's
//           free flight towards the light; 0 on a delta light (no walk can hit it);
//   z(t−2)  made from z(t−1) arriving from y(s−1) (for s = 0, emitted from the light there);
//   y(s−2)  made from y(s−1) arriving from z(t−1);
// the last two over their own edges, whose free flight the walks stored.
namespace {
// Whether the camera walk's density of making v as its vertex j (after a connection vertex,
// never specular) has free-flight factor 1. A medium vertex at passFirstAt keeps its factor:
// its strategy's free-flight variant is dropped instead (variantFactor).
bool passesTo(const MisSettings& st, int j, const PathVertex& v) {
    return cameraWalkPasses(st, j, false) && !(v.isMedium() && j < st.passFrom);
}
}  // namespace

void connectionReverseDensities(const Scene& scene, PathVertex* light, int s, PathVertex* camera, int t,
                                const StrategyJoin& join, MisSettings st) {
    const int W = st.width, H = st.height;
    PathVertex& z = camera[t - 1];
    if (s == 0) {
        const Light& l = scene.lights()[z.light];
        float pos, dir;
        emissionPdf(scene, l, z.p, z.ng, z.wo, &pos, &dir);
        z.pdfRev = Channels(scene.lightDistribution().pmf(z.light) * pos);
        PathVertex& zm = camera[t - 2];
        zm.pdfRev = solidAngleToArea(zm, z.wo, dir, z.edgeDist) * z.edgeRevFreeFlight;
        return;
    }
    PathVertex& y = light[s - 1];
    Vec3 w = y.p - z.p;
    const float d = length(w);
    w = d > 0 ? w / d : Vec3(0.0f);
    const bool directional = y.kind == VertexKind::Light && scene.lights()[y.light].atInfinity();
    if (t >= 2) {
        if (directional) {
            // Parallel rays: the emission disk's area density projects onto z(t−1), no 1/d².
            float pos, dir;
            emissionPdf(scene, scene.lights()[y.light], y.p, y.ng, -w, &pos, &dir);
            z.pdfRev = double(pos * (z.isSurface() ? std::abs(dot(z.ng, w)) : 1.0f)) * join.freeFlightToCamera;
        } else {
            z.pdfRev = solidAngleToArea(z, w, vertexDirectionPdf(scene, y, y.wo, -w, W, H), d) * join.freeFlightToCamera;
        }
        PathVertex& zm = camera[t - 2];
        zm.pdfRev = solidAngleToArea(zm, z.wo, vertexDirectionPdf(scene, z, w, z.wo, W, H), z.edgeDist) * z.edgeRevFreeFlight;
    }
    // y(s−1) and y(s−2) as the camera walk would make them: its vertices t and t + 1, reached
    // by passing through media from st.passFrom on.
    y.pdfRev = y.kind == VertexKind::Light && y.deltaLight
                   ? Channels(0.0)
                   : solidAngleToArea(y, w, vertexDirectionPdf(scene, z, z.wo, w, W, H, st.cameraGuide), d) *
                         (passesTo(st, t, y) ? Channels(1.0) : join.freeFlightToLight);
    if (s >= 2) {
        PathVertex& ym = light[s - 2];
        ym.pdfRev = solidAngleToArea(ym, y.wo, vertexDirectionPdf(scene, y, -w, y.wo, W, H, st.cameraGuide), y.edgeDist) *
                    (passesTo(st, t + 1, ym) ? Channels(1.0) : y.edgeRevFreeFlight);
    }
}

void connectionNeighbours(PathVertex* light, int s, PathVertex* camera, int t, PathVertex* out[4]) {
    out[0] = &camera[t - 1];
    out[1] = t >= 2 ? &camera[t - 2] : nullptr;
    out[2] = s >= 1 ? &light[s - 1] : nullptr;
    out[3] = s >= 2 ? &light[s - 2] : nullptr;
}

double strategyWeight(const Scene& scene, PathVertex* light, int s, PathVertex* camera, int t, const StrategyJoin& join,
                      MisSettings st, double* perCount) {
    // The four densities are the subpaths' own outside this connection: put them back after.
    Channels saved[4];
    PathVertex* touched[4];
    connectionNeighbours(light, s, camera, t, touched);
    for (int i = 0; i < 4; ++i)
        if (touched[i]) saved[i] = touched[i]->pdfRev;
    connectionReverseDensities(scene, light, s, camera, t, join, st);
    double w = misWeight(scene, light, camera, s, t, st, join.equiAngular, join.crossed, join.ownEquiAngularDensity, perCount);
    for (int i = 0; i < 4; ++i)
        if (touched[i]) touched[i]->pdfRev = saved[i];
    return w;
}

}  // namespace brume
