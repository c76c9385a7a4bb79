// The BDPT's MIS weights against weights recomputed from first principles for each full path
// it weighs: every strategy's path density as a product of one-step densities (direction
// density × geometry × free-flight density), the power heuristic over the strategies that can
// make the path. Equal weights for every strategy imply that the weights of a path sum to one.
// In a coloured medium every strategy has a density per colour channel (the channel driving
// free flight), and the heuristic runs over strategies × channels; the tracer's weight is
// that of its hero channel times the channel count.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/direct_light_tracing.h"
#include "brume/integrators/bdpt_allocation.h"
#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/equiangular_segment.h"
#include "brume/integrators/light_numbers.h"
#include "brume/integrators/path_vertex.h"
#include "brume/integrators/path_guide.h"
#include "brume/integrators/visibility.h"
#include "brume/sampling/equiangular.h"
#include "brume/sampling/free_flight.h"
#include "brume/sampling/hg.h"
#include "brume/sampling/vmf.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"
#include "support/film_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr int kW = 8;

bool isAreaLike(const PathVertex& v) {
    return v.kind == VertexKind::Surface || (v.kind == VertexKind::Light && dot(v.ng, v.ng) > 0);
}

struct Checker : BdptObserver {
    const Scene* scene = nullptr;
    MisHeuristic heuristic = MisHeuristic::Power;
    ConnectMode connect = ConnectMode::Density;
    bool exact = false;  // exact equi-angular densities (BdptOptions::exactEquiAngular)
    bool general = false;  // general connections have equi-angular variants (BdptOptions::generalEquiAngular)
    int maxDepth = 4;      // BdptOptions::maxDepth
    double connectP = 1;   // BdptOptions::generalConnection (0 without light subpaths)
    double cameraCount = 1;  // camera connections made per sample (0: no light tracing or no light subpaths)
    bool eaLight = true, eaCamera = true;  // BdptOptions::equiAngularLight, equiAngularCamera
    bool eaOnly = false;  // BdptAllocation::equiAngularOnly: an equi-angular variant replaces the free-flight one
    // Light tracing's share of one-event paths (MisSettings::directLightTracing): this, or
    // the integrator's learned factor in force (direct_light_tracing.h).
    double directFactor = 1;
    const BdptIntegrator* integrator = nullptr;
    // With --max-depth 1 light subpaths are made as often as light tracing's learned share.
    double lightSubpathsMade() const { return integrator ? integrator->lightSubpathsMade() : 1.0; }
    double lightTracingFactor() const {
        const DirectLightTracing* d = integrator ? integrator->directLightTracing() : nullptr;
        return d ? d->factor() : directFactor;
    }
    mutable std::mutex mutex;
    mutable double worst = 0, worstTolerance = 1e-4;  // the worst error relative to its tolerance
    mutable long paths = 0;
    mutable std::string worstInfo;

    // The camera walk's guide (BdptOptions::guiding): its frozen field after the training
    // passes, which weigh no bidirectional path.
    const GuidingField* guide() const { return integrator && integrator->guide() ? integrator->guide()->field() : nullptr; }
    mutable long guidedDensities = 0;  // camera-walk densities that were guided mixtures

    // Density at x[j] of the direction towards x[to], given it came from x[from] (−1: none).
    // cameraWalk: the camera walk's density, which a guide makes the mixture
    // α · p_guide + (1 − α) · p_phase/bsdf with α the share of the cell at x[j] (guided_phase.h).
    double dirPdf(const std::vector<PathVertex>& x, int j, int from, int to, bool cameraWalk) const {
        const PathVertex& v = x[j];
        Vec3 wTo = normalize(x[to].p - v.p);
        const GuidingField* field = cameraWalk ? guide() : nullptr;
        const GuidingCell* cell = field && v.kind != VertexKind::Camera && v.kind != VertexKind::Light ? field->lookup(v.p) : nullptr;
        switch (v.kind) {
        case VertexKind::Camera: return cameraPdfDir(scene->camera(), wTo, kW, kW);
        case VertexKind::Light: {
            float pos, dir;
            emissionPdf(*scene, scene->lights()[v.light], v.p, v.ng, wTo, &pos, &dir);
            return dir;
        }
        case VertexKind::Medium: {
            const Vec3 d = -normalize(x[from].p - v.p);
            const double phase = hgPhase(dot(d, wTo), v.medium->g);
            VmfMixture product;
            if (!cell || !(cell->share > 0) || !vmfProduct(cell->medium, hgAsVmf(d, v.medium->g), &product)) return phase;
            ++guidedDensities;
            return cell->share * product.pdf(wTo) + (1 - cell->share) * phase;
        }
        case VertexKind::Surface: {
            if (v.delta) return 0;
            const Bsdf bsdf = vertexBsdf(*scene, v);
            const double pdf = bsdf.pdf(normalize(x[from].p - v.p), wTo);
            if (!cell || bsdf.isSpecular() || !(cell->surfaceShare > 0)) return pdf;
            ++guidedDensities;
            return cell->surfaceShare * cell->surface.pdf(wTo) + (1 - cell->surfaceShare) * pdf;
        }
        }
        return 0;
    }

    // Geometry × free flight for a walk from x[j] stopping at x[i] (passing: geometry alone,
    // a walk that samples no collision).
    Channels stepFactor(const std::vector<PathVertex>& x, int j, int i, bool passing = false) const {
        const PathVertex& a = x[j];
        const PathVertex& b = x[i];
        Vec3 d = b.p - a.p;
        double dist = length(d);
        Vec3 w = d / float(dist);
        double g = 1.0 / (dist * dist);
        if (isAreaLike(b)) g *= std::abs(dot(b.ng, w));
        MediumStack media = a.media;
        if (a.isSurface() && a.mesh >= 0) {
            int interior = scene->mesh(a.mesh).interiorMedium;
            if (interior >= 0 && dot(a.wo, a.ng) * dot(w, a.ng) < 0) media.toggle(interior);
        }
        PathStats stats;
        ShadowTarget target;
        if (b.mesh >= 0) target.mesh = b.mesh, target.triangle = b.triangle;
        WalkSegment seg = leaving(a.p, isAreaLike(a) ? a.ng : Vec3(0.0f), w, float(dist), isAreaLike(b), target);
        Connection c = connectPoints(*scene, seg, media, a.isMedium(), b.isMedium(), stats);
        return passing ? Channels(g) : g * c.freeFlightToB;
    }

    // Whether the segment p → v passes an invisible medium boundary (no equi-angular variant).
    bool crossesBoundary(const PathVertex& p, const PathVertex& v) const {
        Vec3 w = normalize(v.p - p.p);
        MediumStack media = p.media;
        if (p.isSurface() && p.mesh >= 0) {
            int interior = scene->mesh(p.mesh).interiorMedium;
            if (interior >= 0 && dot(p.wo, p.ng) * dot(w, p.ng) < 0) media.toggle(interior);
        }
        PathStats stats;
        WalkSegment seg = leaving(p.p, isAreaLike(p) ? p.ng : Vec3(0.0f), w, length(v.p - p.p));
        return connectPoints(*scene, seg, media, p.isMedium(), true, stats).crossed;
    }

    // p_ea of v on the ray from p aimed at `anchor`: over the unbounded ray (the stand-in), or
    // with `exact` over the ray's first medium segment, clipped to the light's cone or front
    // half-space (clip) or to the frustum (toCamera).
    double eaPdf(const PathVertex& p, const PathVertex& v, Vec3 anchor, const Light* clip, bool toCamera) const {
        Vec3 e = v.p - p.p;
        float dist = length(e);
        Vec3 w = e / dist;
        // Product sampling (--connect product|mis): the phase of v's medium in the density.
        const float g = connectAnisotropy(connect, v.medium->g);
        if (!exact) return equiAngularStandInPdf(p.p, w, anchor, dist, g);
        // The walk's ray from p's own position, to where its first piece ends.
        Vec3 o = p.p;
        PathStats stats;
        BoundaryPiece first;
        BoundaryWalk(*scene, leaving(p.p, isAreaLike(p) ? p.ng : Vec3(0.0f), w), p.media, stats).next(&first);
        float a = 0, b = first.t1;
        if (clip && clip->kind == LightKind::Spot && !clipToSpotCone(*clip, o, w, &a, &b)) return 0;
        if (clip && clip->kind == LightKind::Triangle && !scene->material(clip->mesh).doubleSided) {
            const Mesh& mesh = scene->mesh(clip->mesh);
            const uint32_t* idx = &mesh.indices[3 * clip->triangle];
            Vec3 p0 = mesh.positions[idx[0]];
            Vec3 n = cross(mesh.positions[idx[1]] - p0, mesh.positions[idx[2]] - p0);
            float h = dot(n, o - p0), dn = dot(n, w);  // front side: h + t·dn > 0
            if (dn > 0) a = std::max(a, -h / dn);
            else if (dn < 0) b = std::min(b, -h / dn);
            else if (h <= 0) return 0;
        }
        if (toCamera && !clipToFrustum(scene->camera(), kW, kW, o, w, &a, &b)) return 0;
        if (!(a < b)) return 0;
        return equiAngularPdf(makeEquiAngular(o, w, anchor, a, b, g), length(v.p - o));
    }

    // ρ = p_ea / p_ff for x[m] reached from x[m−1] and aimed at x[m+1] (0 if no such variant):
    // the light's anchor for a light vertex.
    WideChannels equiAngularRatio(const std::vector<PathVertex>& x, int m, bool lastIsLight) const {
        const PathVertex& v = x[m];
        const PathVertex& p = x[m - 1];
        const PathVertex& a = x[m + 1];
        if (!v.isMedium() || p.delta || crossesBoundary(p, v)) return WideChannels(0.0L);
        Vec3 e = v.p - p.p;
        float dist = length(e);
        Vec3 w = e / dist;
        Vec3 anchor = a.p;
        const Light* clip = nullptr;
        if (lastIsLight && m + 1 == int(x.size()) - 1) {
            const Light& l = scene->lights()[a.light];
            if (l.kind == LightKind::Directional) return WideChannels(0.0L);
            if (l.kind != LightKind::Triangle) anchor = l.position;
            clip = &l;
        }
        (void)w;
        return ratios(eaPdf(p, v, anchor, clip, false), p, v);
    }

    // ρ_c = p_ea / p_ff,c, p_ff,c the free-flight density of v from p in the one medium
    // between them: σt_c·exp(−σt_c·d) in a homogeneous medium, the stand-in of a density grid
    // (0 where p_ff,c is). In long double, as the products below: a dense channel's densities
    // leave double's range.
    static WideChannels ratios(double pea, const PathVertex& p, const PathVertex& v) {
        WideChannels rho(0.0L);
        const float dist = length(v.p - p.p);
        const Channels ff = v.medium->transit(Ray{p.p, (v.p - p.p) / dist, dist}, 0.0f, dist, false, true).fwd;
        for (int c = 0; c < 3; ++c) {
            double pff = ff[c];
            rho[c] = pff > 0 ? pea / (long double)pff : 0;
        }
        return rho;
    }

    // The same for the camera as a point light: x[1] reached from x[2], aimed at the pinhole x[0].
    WideChannels cameraEquiAngularRatio(const std::vector<PathVertex>& x) const {
        const PathVertex& v = x[1];
        const PathVertex& p = x[2];
        if (!v.isMedium() || p.delta || crossesBoundary(p, v)) return WideChannels(0.0L);
        return ratios(eaPdf(p, v, x[0].p, nullptr, true), p, v);
    }

    void onWeight(const PathVertex* light, int s, const PathVertex* camera, int t, float weight,
                  bool equiAngular, int hero) const override {
        std::vector<PathVertex> x;
        for (int i = 0; i < t; ++i) x.push_back(camera[i]);
        for (int i = s - 1; i >= 0; --i) x.push_back(light[i]);
        const int k = int(x.size()) - 1;
        // The emitter end: for s = 0 the camera walk's last vertex, seen as the light vertex.
        int li = x[k].light;
        const Light& L = scene->lights()[li];
        bool directional = L.kind == LightKind::Directional;
        bool hittable = L.kind == LightKind::Triangle || L.kind == LightKind::Sphere;
        // A directional light's vertex has no position: put it far up the beam, so that
        // directions towards it are right.
        if (directional) x[k].p = x[k - 1].p - L.direction * 1000.0f;
        std::vector<Channels> fwd(k + 1, Channels(1.0)), rev(k + 1, Channels(1.0));
        for (int i = 1; i <= k; ++i) fwd[i] = dirPdf(x, i - 1, i - 2, i, true) * stepFactor(x, i - 1, i);
        // The camera walk passes through media to its vertex past the last scattering event
        // --max-depth allows (only an emitter hit, s = 0, uses it).
        if (k == maxDepth + 1) fwd[k] = dirPdf(x, k - 1, k - 2, k, true) * stepFactor(x, k - 1, k, true);
        // So does it to its last scattering event x(m), m = maxDepth, after a vertex that is not
        // specular, where equi-angular light connections cover the medium (no directional
        // light, no invisible boundary): it reaches a surface there with free-flight density 1
        // and never makes a medium vertex there.
        const int m = maxDepth;
        const bool lastPasses = connect != ConnectMode::Density && eaLight && m >= 1 && m <= k && !scene->hasInvisibleBoundaries() &&
                                !scene->hasDirectionalLights() && !(x[m - 1].isSurface() && x[m - 1].delta);
        if (lastPasses && !x[m].isMedium()) fwd[m] = dirPdf(x, m - 1, m - 2, m, true) * stepFactor(x, m - 1, m, true);
        const bool lastMediumUnmade = lastPasses && x[m].isMedium();
        float pos, dir;
        {
            PathVertex end = x[k];
            end.kind = VertexKind::Light;
            std::vector<PathVertex> y = x;
            y[k] = end;
            emissionPdf(*scene, L, end.p, end.ng, normalize(x[k - 1].p - end.p), &pos, &dir);
            rev[k] = Channels(scene->lightDistribution().pmf(li) * (directional ? 1.0f : pos));
            for (int i = k - 1; i >= 1; --i) {
                if (i == k - 1 && directional) {
                    // Parallel light: the disk's area density projected onto x(k−1), |cos| and no
                    // 1/d², times the free flight from outside the scene to x(k−1).
                    PathStats stats;
                    Vec3 up = -L.direction;
                    WalkSegment seg = leaving(y[i].p, isAreaLike(y[i]) ? y[i].ng : Vec3(0.0f), up);
                    Connection c = connectPoints(*scene, seg, y[i].media, y[i].isMedium(), false, stats);
                    rev[i] = pos * (isAreaLike(y[i]) ? std::abs(dot(y[i].ng, up)) : 1.0) * c.freeFlightToA;
                    continue;
                }
                rev[i] = dirPdf(y, i + 1, i + 2 <= k ? i + 2 : -1, i, false) * stepFactor(y, i + 1, i);
            }
        }
        auto remap = [](double p) { return p != 0 ? p : 1.0; };
        auto connectible = [&](int i) { return !(x[i].isSurface() && x[i].delta); };
        std::vector<double> p(k + 2, 0.0);  // by t' = 1 … k + 1
        long double sum = 0, self = 0;
        auto pw = [&](long double r) { return heuristic == MisHeuristic::Power ? r * r : r; };
        const int channels = scene->mediumChannels();
        for (int tt = 1; tt <= k + 1; ++tt) {
            int ss = k + 1 - tt;
            bool valid = ss == 0 ? hittable : (connectible(tt - 1) && connectible(tt));
            if (!valid) continue;
            // Free-flight and equi-angular variants of the strategy.
            WideChannels rho(0.0L);
            if (connect != ConnectMode::Density && tt >= 2 && ((ss == 1 && eaLight) || (ss >= 2 && general)))
                rho = equiAngularRatio(x, tt - 1, true);
            if (connect != ConnectMode::Density && eaCamera && tt == 1 && k >= 2) rho = cameraEquiAngularRatio(x);
            for (int c = 0; c < channels; ++c) {
                long double prod = 1;
                for (int i = 1; i <= tt - 1; ++i) prod *= remap(fwd[i][c]);
                for (int i = tt; i <= k; ++i) prod *= remap(rev[i][c]);
                bool eaOn = rho[c] > 0, ffOn = !((variantOnly(connect) || eaOnly) && eaOn);
                if (lastMediumUnmade && tt - 1 >= m) ffOn = false;  // the camera walk cannot make x(m)
                // A general connection is made with probability connectP: its densities count that much.
                if (tt >= 2 && ss >= 2) prod *= connectP;
                // A camera connection is made cameraCount times (1 or 0).
                if (tt == 1) prod *= cameraCount * lightSubpathsMade();
                // On paths of one scattering event, times light tracing's share.
                if (tt == 1 && k == 2) prod *= lightTracingFactor();
                // The light connection picks its light by where it starts (from x(k−1), or
                // along the ray x(k−2) → x(k−1) in a medium), every other strategy by power.
                if (ss == 1 && tt >= 2) prod *= lightConnectionPickRatio(*scene, x[k - 2].p, x[k - 1].p, x[k - 1].isMedium(), li);
                long double termFf = ffOn ? pw(prod) : 0, termEa = eaOn ? pw(prod * rho[c]) : 0;
                sum += termFf + termEa;
                if (tt == t && c == hero) self = equiAngular ? termEa : termFf;
            }
        }
        double expected = sum > 0 ? double(channels * self / sum) : 0;
        if (std::getenv("BRUME_DEBUG_WEIGHTS") && std::abs(expected - weight) > 1e-3) {
            std::printf("s=%d t=%d hero %d weight %g expected %g\n", s, t, hero, weight, expected);
            for (int i = 0; i <= k; ++i)
                std::printf("  x%d kind %d fwd %g %g %g rev %g %g %g | vtx fwd %g %g %g rev %g %g %g ratio %g %g %g\n", i, int(x[i].kind),
                            fwd[i][0], fwd[i][1], fwd[i][2], rev[i][0], rev[i][1], rev[i][2], x[i].pdfFwd[0], x[i].pdfFwd[1],
                            x[i].pdfFwd[2], x[i].pdfRev[0], x[i].pdfRev[1], x[i].pdfRev[2], x[i].channelRatio[0],
                            x[i].channelRatio[1], x[i].channelRatio[2]);
        }
        // Positions are floats: an edge of length ℓ between points of size |p| has its length
        // and direction known to ~2^-23·|p|/ℓ only, and so do the densities the weights are
        // made of. So has the cosine at a surface or area-light vertex b seen from its
        // neighbour a, |n·(a − b)|/ℓ: its numerator h (a's height above b's plane, ≤ ℓ) is
        // known to ~2^-23·|p|, a relative 2^-23·|p|/h. (A medium vertex that close to its
        // neighbour's plane is also on an undetermined side of it, e.g. of an emitter, which
        // decides the visibility and free flight of its other edge.) 1e-4 is asked of every
        // path whose edges and heights resolve that well (≥ ~5 mm per metre of |p|); any
        // other path is held to its own precision.
        double minEdge = kInfinity, maxCoord = 1;  // minEdge: the smallest edge or height
        for (int i = 0; i <= (directional ? k - 1 : k); ++i) {  // (a directional light's vertex is made up)
            maxCoord = std::max(maxCoord, double(maxComponent(vmax(x[i].p, -x[i].p))));
            if (i == 0) continue;
            const Vec3 e = x[i].p - x[i - 1].p;
            minEdge = std::min(minEdge, double(length(e)));
            if (isAreaLike(x[i])) minEdge = std::min(minEdge, double(std::abs(dot(x[i].ng, e))));
            if (isAreaLike(x[i - 1])) minEdge = std::min(minEdge, double(std::abs(dot(x[i - 1].ng, e))));
        }
        const double tolerance = std::max(1e-4, 4 * 0x1p-23 * maxCoord / minEdge);
        std::lock_guard<std::mutex> lock(mutex);
        ++paths;
        double err = std::abs(expected - double(weight));
        if (err / tolerance > worst / worstTolerance) {
            worst = err;
            worstTolerance = tolerance;
            worstInfo = "s=" + std::to_string(s) + " t=" + std::to_string(t) + " weight " + std::to_string(weight) +
                        " expected " + std::to_string(expected) + " tolerance " + std::to_string(tolerance);
        }
    }
};

}  // namespace

namespace {

void checkWeights(const char* file, int spp, ConnectMode connect = ConnectMode::Density, bool exact = false,
                  bool general = false, float connectP = 1, const BdptAllocation* allocation = nullptr,
                  double directFactor = -1, int maxDepth = 4, bool guiding = false) {
    for (MisHeuristic h : {MisHeuristic::Power, MisHeuristic::Balance}) {
        auto scene = loadTestScene(file);
        Checker checker;
        checker.maxDepth = maxDepth;
        checker.scene = scene.get();
        checker.heuristic = h;
        checker.connect = connect;
        checker.exact = exact;
        checker.general = general;
        checker.connectP = connectP;
        BdptOptions opt{checker.maxDepth, h};
        opt.connect = connect;
        opt.exactEquiAngular = exact;
        opt.generalEquiAngular = general;
        opt.allocation.generalConnection = connectP;
        if (allocation) {
            opt.allocation = *allocation;
            checker.connectP = allocation->lightSubpaths ? allocation->generalConnection : 0;
            checker.cameraCount = allocation->lightSubpaths && allocation->lightTracing ? 1 : 0;
            checker.eaLight = allocation->equiAngularLight;
            checker.eaCamera = allocation->equiAngularCamera;
            checker.eaOnly = allocation->equiAngularOnly;
        }
        opt.directLightTracing = directFactor;
        opt.guiding = guiding;
        opt.guideShare = guiding ? 0.5f : -1.0f;  // (a learned share may be 0 on so few records)
        if (directFactor >= 0) checker.directFactor = directFactor;
        opt.hooks.observer = &checker;
        Film film(kW, kW);
        RenderOptions o;
        o.width = o.height = kW;
        o.spp = spp;
        o.seed = 3;
        BdptIntegrator integrator(opt);
        checker.integrator = &integrator;
        render(*scene, integrator, o, film);
        INFO(file << (h == MisHeuristic::Power ? " power" : " balance") << (allocation ? " " + allocation->name() : "")
                  << ": " << checker.paths
                  << " weighted paths, worst |w − w_expected| = " << checker.worst << " (" << checker.worstInfo << ")");
        CHECK(checker.paths > 100);
        CHECK(checker.worst < checker.worstTolerance);
        if (guiding) {  // the guide must have guided, or the test proves nothing
            INFO(checker.guidedDensities << " guided camera-walk densities");
            CHECK(checker.guidedDensities > 100);
        }
    }
}

}  // namespace

TEST_CASE("bdpt MIS weights equal the heuristic over all strategies' path densities", "[bdpt][mis]") {
    checkWeights("quad_light_fog.gltf", 4);
    checkWeights("single_near.gltf", 4);
    checkWeights("area_sphere.gltf", 4);
    checkWeights("bdpt_window_fog.gltf", 16);  // directional light, bounded fog
    checkWeights("bdpt_glass_sphere.gltf", 4);  // specular chains, spot light
}

TEST_CASE("bdpt MIS weights where the light connection picks by where it starts", "[bdpt][mis][light_selection]") {
    // Six lights of four kinds (light_selection.h): the light connection's pick differs from
    // the light subpath's by up to 30x, from surface and medium vertices.
    for (ConnectMode m : {ConnectMode::Density, ConnectMode::Mis, ConnectMode::EquiAngular}) checkWeights("many_lights.gltf", 4, m);
}

TEST_CASE("bdpt MIS weights with equi-angular light connections (mis, equiangular and product modes)", "[bdpt][mis]") {
    for (ConnectMode m : {ConnectMode::Mis, ConnectMode::EquiAngular, ConnectMode::Product}) {
        checkWeights("quad_light_fog.gltf", 4, m);
        checkWeights("single_near.gltf", 4, m);
        checkWeights("single_spot.gltf", 4, m);
        checkWeights("area_sphere.gltf", 4, m);
        checkWeights("bdpt_window_fog.gltf", 16, m);
        checkWeights("bdpt_glass_sphere.gltf", 4, m);
    }
}

// Transparent emitters (emitter_crossing.h): a crossing is weighed as the emitter hit s = 0
// of a camera path that ends on it; every other strategy's path passes through it.
TEST_CASE("bdpt MIS weights with transparent emitters", "[bdpt][mis][transparent]") {
    for (ConnectMode m : {ConnectMode::Density, ConnectMode::Mis}) checkWeights("transparent_panels_fog.gltf", 4, m);
}

// Coloured fog (extinction ratio 11 between channels): the weights run over strategies ×
// channels, each channel's densities its own.
TEST_CASE("bdpt MIS weights in a coloured medium", "[bdpt][mis][chromatic]") {
    checkWeights("quad_light_fog_chromatic.gltf", 4);
    checkWeights("quad_light_fog_chromatic.gltf", 4, ConnectMode::Mis);
    checkWeights("quad_light_fog_chromatic.gltf", 4, ConnectMode::EquiAngular);
    checkWeights("furnace_chromatic.gltf", 1);
}

TEST_CASE("bdpt MIS weights with equi-angular variants of general connections too", "[bdpt][mis]") {
    for (ConnectMode m : {ConnectMode::Mis, ConnectMode::EquiAngular}) {
        checkWeights("quad_light_fog.gltf", 4, m, false, true);
        checkWeights("single_spot.gltf", 4, m, false, true);
        checkWeights("bdpt_quad_fogbox.gltf", 4, m, false, true);
        checkWeights("quad_light_fog_chromatic.gltf", 4, m, false, true);
    }
    checkWeights("bdpt_glass_sphere.gltf", 4, ConnectMode::Mis, true, true);
}

// Probabilistic general connections: each made with probability p, its densities p times.
TEST_CASE("bdpt MIS weights with general connections made with probability p", "[bdpt][mis]") {
    for (ConnectMode m : {ConnectMode::Density, ConnectMode::Mis}) {
        checkWeights("quad_light_fog.gltf", 4, m, false, false, 0.3f);
        checkWeights("bdpt_glass_sphere.gltf", 4, m, false, false, 0.3f);
        checkWeights("quad_light_fog_chromatic.gltf", 4, m, false, false, 0.3f);
    }
    checkWeights("bdpt_quad_fogbox.gltf", 4, ConnectMode::Mis, false, true, 0.3f);
}

TEST_CASE("bdpt MIS weights with exact (bounded, clipped) equi-angular densities", "[bdpt][mis]") {
    checkWeights("quad_light_fog.gltf", 4, ConnectMode::Mis, true);
    checkWeights("single_spot.gltf", 4, ConnectMode::Mis, true);   // cone clipping
    checkWeights("area_sphere.gltf", 4, ConnectMode::Mis, true);
    checkWeights("bdpt_glass_sphere.gltf", 4, ConnectMode::Mis, true);
}

// With the camera outside an invisible fog boundary. (This once differed by 1.2e-4: rays left
// surfaces from points pushed off them and restarted at each boundary, so the fog length of an
// edge depended on which end it was traced from; boundary_walk.h now measures exact segments.)
TEST_CASE("bdpt MIS weights through an invisible boundary", "[bdpt][mis]") {
    checkWeights("bdpt_quad_fogbox.gltf", 4);
    checkWeights("bdpt_quad_fogbox.gltf", 4, ConnectMode::Mis);
    checkWeights("bdpt_quad_fogbox.gltf", 4, ConnectMode::EquiAngular);
    checkWeights("bdpt_quad_fogbox.gltf", 4, ConnectMode::Product);
}

// Strongly forward- and back-scattering fog: the product densities vary over orders of
// magnitude along a ray.
TEST_CASE("bdpt MIS weights with product sampling in anisotropic fog", "[bdpt][mis]") {
    for (ConnectMode m : {ConnectMode::Mis, ConnectMode::Product}) {
        checkWeights("single_forward.gltf", 4, m);
        checkWeights("area_sphere_back.gltf", 4, m);
        checkWeights("single_forward.gltf", 4, m, true);
    }
}

// Every allocation the efficiency-aware tracer may choose (bdpt_allocation.h): strategies
// switched off (light tracing, equi-angular variants, light subpaths altogether) and unequal
// counts (general connections with probability 0, 1/4 or 1). The weights of the strategies
// left must still be the heuristic over exactly those, with their counts.
TEST_CASE("bdpt MIS weights under every candidate allocation", "[bdpt][mis][allocation]") {
    for (const BdptAllocation& a : candidateAllocations(ConnectMode::Mis)) {
        if (a.pathTracer) continue;  // (the path tracer's own weights: test_pt_oracles.cpp)
        checkWeights("quad_light_fog.gltf", 4, ConnectMode::Mis, false, false, 1, &a);
        checkWeights("bdpt_glass_sphere.gltf", a.lightSubpaths ? 16 : 64, ConnectMode::Mis, false, false, 1, &a);
    }
    for (const BdptAllocation& a : candidateAllocations(ConnectMode::Density))
        if (!a.pathTracer) checkWeights("area_sphere.gltf", 4, ConnectMode::Density, false, false, 1, &a);
    const std::vector<BdptAllocation> all = candidateAllocations(ConnectMode::Mis);
    for (const BdptAllocation& a : {all[0], all[3], all.back()})  // pt+ea, the pilot, the last
        checkWeights("quad_light_fog_chromatic.gltf", 4, ConnectMode::Mis, false, false, 1, &a);
}

// Heterogeneous media: the free-flight densities are the stand-ins of a density grid
// (docs/mis.md, "heterogeneous media"), recomputed here from the medium interface as the
// walks recorded them; a density gradient in a box, the strongly varying furnace grid moved
// by its node, and the coloured furnace grid (hero channels over stand-ins).
TEST_CASE("bdpt MIS weights in heterogeneous media", "[bdpt][mis][heterogeneous]") {
    for (ConnectMode m : {ConnectMode::Density, ConnectMode::Mis, ConnectMode::Product}) {
        checkWeights("single_gradient.gltf", 4, m);
        checkWeights("furnace_grid_bounded.gltf", 1, m);
    }
    checkWeights("single_gradient.gltf", 4, ConnectMode::Mis, false, true);
    checkWeights("furnace_grid_chromatic.gltf", 1, ConnectMode::Mis);
}

// Light tracing's share of paths of one scattering event (direct_light_tracing.h): given, and
// learned in the first passes (then in force from the fifth), in every connect mode.
TEST_CASE("bdpt MIS weights with light tracing's share of one-event paths scaled", "[bdpt][mis]") {
    for (ConnectMode m : {ConnectMode::Density, ConnectMode::Mis, ConnectMode::EquiAngular, ConnectMode::Product}) {
        checkWeights("quad_light_fog.gltf", 4, m, false, false, 0.25f, nullptr, 0.05);
        checkWeights("single_spot.gltf", 4, m, false, false, 0.25f, nullptr, 0.05);
        checkWeights("area_sphere.gltf", 4, m, false, false, 0.25f, nullptr, 0.05);
        checkWeights("bdpt_glass_sphere.gltf", 16, m, false, false, 0.25f);  // learned
        checkWeights("quad_light_fog_chromatic.gltf", 8, m, false, false, 0.25f);  // learned
        // Single scattering: light subpaths then made as often as the learned share too.
        checkWeights("single_near.gltf", 16, m, false, false, 0.25f, nullptr, -1, 1);
        checkWeights("quad_light_fog.gltf", 16, m, false, false, 0.25f, nullptr, -1, 1);
    }
}

// Guided camera walks (`--guiding on`): after the guide's training passes the camera walk
// samples directions from the guided mixture at medium and surface vertices, and every
// weight reads that mixture wherever a density is the camera walk's (path_vertex.h).
TEST_CASE("bdpt MIS weights with guided camera walks", "[bdpt][mis][guiding]") {
    for (ConnectMode m : {ConnectMode::Density, ConnectMode::Mis}) {
        checkWeights("quad_light_fog.gltf", 20, m, false, false, 1, nullptr, -1, 4, true);
        checkWeights("bdpt_quad_fogbox.gltf", 20, m, false, true, 0.3f, nullptr, -1, 4, true);
    }
    checkWeights("quad_light_fog_chromatic.gltf", 20, ConnectMode::Mis, false, false, 1, nullptr, -1, 4, true);
    // --max-depth 2: the camera walk passes through media at its last events (passedLightPrefix).
    checkWeights("quad_light_fog.gltf", 20, ConnectMode::Mis, false, false, 0.25f, nullptr, -1, 2, true);
}
