#include "brume/integrators/path_tracer.h"

#include <algorithm>
#include <optional>

#include "brume/guiding/guided_distance.h"
#include "brume/guiding/guided_phase.h"
#include "brume/guiding/guided_survival.h"
#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/equiangular_segment.h"
#include "brume/integrators/light_numbers.h"
#include "brume/integrators/mis.h"
#include "brume/integrators/one_event_split.h"
#include "brume/integrators/sample_dimensions.h"
#include "brume/integrators/solid_angle_segment.h"
#include "brume/integrators/state_bytes.h"
#include "brume/integrators/strategy_densities.h"
#include "brume/integrators/visibility.h"
#include "brume/integrators/volume_light_sampling.h"
#include "brume/sampling/free_flight.h"
#include "brume/sampling/hg.h"
#include "brume/scene/bsdf.h"
#include "brume/scene/light_sampling.h"

namespace brume {

// Strategies for light reaching a path through a point on a medium segment. A light path
// x(t) → y is a pair (t on the segment, y on the light); four strategies can make it:
//   A  free-flight t, then a light sample y from x(t):      pA = p_ff(t) · P(light) · p_L(y|x)
//   B  free-flight t, then phase sampling hits y:           pB = p_ff(t) · p_phase(ω)
//   C  a light point first, t equi-angular towards it:      pC = P(light) · p_area(y|x) · p_ea(t|y)
//   D  t by the light's solid angle, then y as in A:        pD = P(light) · p_Ω(t) · p_L(y|x)
// All in the same measure (dt × solid angle at x(t)). p_L is sampleLight's solid-angle
// density: uniform in the solid angle an emissive triangle subtends (by area outside the
// spherical limits, or with --emitter-sampling area), the subtended cone of a sphere, a delta
// for point and spot lights (for which B is impossible). C's light point is drawn before x(t)
// exists, so by area on a triangle (p_area, in solid angle at x(t)); a sphere's anchor is its
// centre and C then samples y as A does. D (solid_angle_segment.h) is for emissive triangles
// in mis mode when the scene samples emitters by solid angle: close to a large emitter, where
// the 1/r² of C's random light point is nearly singular, Ω(x) is smooth; D then takes C's
// place (usesEquiAngular). Each estimate is weighted by the power heuristic p_self² / Σ p²
// over the strategies the mode turns on (mis: A, B and C, or A, B and D for emissive triangles
// sampled by solid angle). At surfaces only A and B.
namespace {

// Where the bidirectional tracer renders single scattering with this tracer as its camera
// family (one_event_split.h): the family's weight W_C of the path a connection made, asked
// for by the connections that make one-event paths in media.
struct FamilyShare {
    const OneEventSplit* split = nullptr;
    float* weight = nullptr;
    // x in m, y on light li; p: the density per unit length with which x was placed, at t on
    // seg. Beside a sphere light every strategy takes C's density there (one_event_split.h).
    void weigh(const Scene& scene, Vec3 x, const Medium& m, int li, Vec3 y, double p, const MediumSegment& seg, float t) const {
        if (!split || split->q <= 0 || split->kappa <= 0) return;  // (W_C = 1: no light tracing)
        const Light& light = scene.lights()[size_t(li)];
        if (light.kind == LightKind::Sphere) p = split->cameraDensityOn(light, seg, t);
        *weight = split->cameraFamilyWeight(scene, x, m, li, y, p);
    }
};

// Where a medium vertex came from: needed to weigh strategies that could have made it.
struct MediumOrigin {
    MediumSegment seg;
    float t = 0;
    float pFreeFlight = 0;  // p_ff(t) within the segment
};

// The solid-angle distance tables (strategy D) of one medium piece, per light (one for both
// halves of a rectangle): D and the weights of A on the same piece (and of B at the next hit)
// ask for the same light's table.
struct SolidAngleTables {
    static constexpr int kSlots = 4;
    int light[kSlots];
    bool valid[kSlots];
    SolidAngleDistance table[kSlots];
    int count = 0, next = 0;

    const SolidAngleDistance* get(const Scene& scene, int li, const MediumSegment& seg) {
        const Light& l = scene.lights()[size_t(li)];
        if (l.partner >= 0 && l.partner < l.triangle) li = scene.triangleLight(l.mesh, l.partner);  // one table a rectangle
        for (int i = 0; i < count; ++i)
            if (light[i] == li) return valid[i] ? &table[i] : nullptr;
        const int i = count < kSlots ? count++ : (next++ % kSlots);
        light[i] = li;
        valid[i] = solidAngleDistanceOn(scene, scene.lights()[size_t(li)], seg, &table[i]);
        return valid[i] ? &table[i] : nullptr;
    }
    void clear() { count = next = 0; }
};

// A scattering vertex as next-event estimation sees it.
struct Vertex {
    Vec3 p;
    Vec3 wo;                         // towards the previous vertex
    const Bsdf* bsdf = nullptr;      // surface vertex
    Vec3 ng;                         // surface vertex: geometric normal
    const MediumOrigin* origin = nullptr;  // medium vertex
    const GuidedPhase* guided = nullptr;   // medium vertex: its direction sampler
    const GuidingCell* cell = nullptr;     // surface vertex: its guide, with share α > 0
    float surfaceShare = 0;

    // The density is that of the walk's own direction sampling; the guided mixture's only
    // where it is needed (`guidedPdf`: a light that direction sampling can reach).
    Spectrum eval(Vec3 wi, float* pdf, bool guidedPdf) const {
        if (bsdf) {
            *pdf = bsdf->pdf(wo, wi);
            if (cell && guidedPdf) *pdf = surfaceShare * cell->surface.pdf(wi) + (1.0f - surfaceShare) * *pdf;
            return bsdf->eval(wo, wi);
        }
        float p = hgPhase(dot(-wo, wi), origin->seg.medium->g);
        *pdf = guided && guidedPdf ? guided->pdf(wi) : p;
        return Spectrum(p);
    }
};

bool usesDensity(ConnectMode m, const Light& l) { return !variantOnly(m) || l.atInfinity(); }
// D: in mis mode, for emissive triangles sampled by solid angle, on segments that pass close
// to them (solidAngleDistanceApplies). It takes C's place there (docs/path-tracer.md: where D
// is nearly exact, each further strategy adds to the MIS estimate's variance; C, whose 1/r²
// towards a random light point is nearly singular close to the emitter, added 6–9×).
bool usesSolidAngle(const Scene& scene, ConnectMode m, const Light& l, const MediumSegment& seg) {
    return m == ConnectMode::Mis && l.isPlanar() && scene.emitterSampling() == EmitterSampling::SolidAngle &&
           solidAngleDistanceApplies(scene, l, seg);
}
bool usesEquiAngular(const Scene& scene, ConnectMode m, const Light& l, const MediumSegment& seg) {
    return m != ConnectMode::Density && !l.atInfinity() && !usesSolidAngle(scene, m, l, seg);
}

// A light path through a medium vertex: the light, the point y on it, and the densities the
// caller already knows (a negative c or d: not known, computed here).
struct MediumPath {
    const Light* light;
    float pick;     // P(light): in a medium A, C and D all pick along the segment (light_selection.h)
    Vec3 y;         // the light point (position of a point or spot light)
    int yLight;     // the light y lies on (the picked one, or the other half of its rectangle)
    float pL;       // p_L(y|x)
    bool delta;     // point or spot light
    float phase;    // p_phase(ω) of the direction to y
    double c = -1, d = -1;
};

// noVertex: free flight makes no vertex where this path scatters (the walk passes through the
// segment, or a mode without A), so A's density is 0. made: the shares the path is made with
// (ConnectionShares::madeWith).
StrategyDensities densitiesOf(const Scene& scene, const MediumOrigin& o, const MediumPath& path, ConnectMode mode,
                               SolidAngleTables& tables, ConnectionShares::Shares q, bool noVertex = false,
                               ConnectionShares::Shares* made = nullptr) {
    const Light& light = *path.light;
    StrategyDensities p;
    if (usesDensity(mode, light)) p.a = double(o.pFreeFlight) * path.pick * path.pL;
    if (!path.delta) p.b = double(o.pFreeFlight) * path.phase;
    if (path.c >= 0) {
        p.c = path.c;
    } else if (usesEquiAngular(scene, mode, light, o.seg)) {
        // C draws its light point on the light it picked: y's own.
        const Light& yl = scene.lights()[size_t(path.yLight)];
        const Vec3 x = o.seg.o + o.seg.d * o.t;
        const bool onSurface = yl.isPlanar();  // C's anchor is its light point (lightAnchor)
        const float pArea = onSurface ? lightPdfByArea(scene, yl, x, path.y, Vec3(0.0f)) : path.pL;
        const float pick = onSurface ? scene.lightSelection().pmfAlong(o.seg.o, o.seg.d, o.seg.tEnd, path.yLight) : path.pick;
        EquiAngular ea;
        const Vec3 anchor = onSurface ? path.y : yl.position;
        if (pArea > 0 && equiAngularTowards(yl, anchor, o.seg, connectAnisotropy(mode, o.seg.medium->g), &ea))
            p.c = double(pick) * pArea * equiAngularPdf(ea, o.t);
    }
    // D's density needs its table: not built where D is not made (qD = 0 and another strategy
    // makes the path; madeWith reads D's density only times qD).
    auto solidAngleDensity = [&] {
        if (path.d >= 0) {
            p.d = path.d;
        } else if (usesSolidAngle(scene, mode, light, o.seg)) {
            if (const SolidAngleDistance* sd = tables.get(scene, int(&light - scene.lights().data()), o.seg))
                p.d = double(path.pick) * solidAngleDistancePdf(*sd, o.t) * path.pL;
        }
    };
    if (q.solidAngle > 0) solidAngleDensity();
    if (noVertex) p.a = 0;
    // A, C and D made with probabilities qA, qC and qD (connection_shares.h): densities q·p; a
    // share of 0 only where another strategy makes the path.
    const ConnectionShares::Shares e = ConnectionShares::madeWith(q, p);
    if (!(q.solidAngle > 0) && e.solidAngle > 0) solidAngleDensity();
    p.a *= double(e.vertex);
    p.c *= double(e.segment);
    p.d *= double(e.solidAngle);
    if (made) *made = e;
    return p;
}

// What a light connection in a medium leaves for learning its shares (connection_shares.h):
// null outside the learning passes.
struct ShareNotes {
    ConnectionShares::Shares q;
    std::vector<ConnectionShares::Record>* records = nullptr;
    Spectrum beta{1.0f};  // the throughput the estimates noted will be multiplied by
    // Records the estimate `value` = u·w of technique t (u: unweighted).
    void note(ConnectionShares::Technique t, const Spectrum& value, float w, const StrategyDensities& p) const {
        if (!records || !(w > 0)) return;
        const Spectrum v = value * beta;
        records->push_back(ConnectionShares::Record{t, double(v.x + v.y + v.z) / 3.0 / double(w), p});
    }
    ShareNotes scaled(const Spectrum& b) const { return ShareNotes{q, records, b}; }
};

// The density with which the walk, had it scattered at x travelling along d, would have
// continued along w: the guided mixture where the field guides (guided_phase.h), else the
// phase function `phase` itself.
float directionPdfAt(const GuidingField* field, Vec3 x, Vec3 d, float g, Vec3 w, float phase) {
    if (!field) return phase;
    const GuidedPhase gp = GuidedPhase::at(field, x, d, g);
    return gp.share > 0 ? gp.pdf(w) : phase;
}

// The density with which the walk's distance sampling on a piece would have stopped at t
// (what strategies C and D need for A's and B's densities): free flight's (tr: the transit
// over [0, t]), or the guided mixture's where the piece is guided (guided_distance.h).
float distanceDensity(const Medium& m, const MediumTransit& tr, Spectrum channels, const GuidedDistance* gd, float t) {
    if (gd) return float(gd->pdf(t));
    return float(m.grey() ? tr.fwd[0] : tr.fwd.mix(channels));
}

// Strategy A: next-event estimation from a surface or free-flight medium vertex.
Spectrum sampleDirect(const Scene& scene, const Vertex& v, const MediumStack& media, ConnectMode mode,
                      const Sampler& sampler, uint32_t dims, SolidAngleTables& tables, PathStats& stats,
                      const ShareNotes& shares, const FamilyShare& family = FamilyShare{}) {
    if (scene.lightDistribution().empty()) return Spectrum(0.0f);
    float pick;
    // In a medium the vertex picks as its segment does (light_selection.h), else from its point.
    int li = v.origin ? pickLightAlong(scene, sampler, dims, 0, v.origin->seg.o, v.origin->seg.d, v.origin->seg.tEnd, &pick)
                      : pickLightAt(scene, sampler, dims, 0, v.p, &pick);
    const Light& light = scene.lights()[li];
    if (v.origin && !usesDensity(mode, light)) return Spectrum(0.0f);  // C's job in this mode
    // A share of 0 at a medium vertex (the caller made this call whatever its number): made
    // only towards a light no other strategy reaches (ConnectionShares::madeWith: a delta
    // light that C cannot sample and D does not take).
    if (v.origin && shares.q.vertex <= 0 &&
        (!light.isDelta() || usesEquiAngular(scene, mode, light, v.origin->seg) || usesSolidAngle(scene, mode, light, v.origin->seg)))
        return Spectrum(0.0f);
    LightSample ls;
    if (!sampleLight(scene, light, v.p, lightPointNumbers(light, sampler, dims + dim::kLightPoint, 0), &ls) || isBlack(ls.Le)) return Spectrum(0.0f);
    float scatterPdf;
    Spectrum f = v.eval(ls.wi, &scatterPdf, !ls.isDelta);
    if (isBlack(f)) return Spectrum(0.0f);
    float w;
    StrategyDensities p;
    float q = 1;  // A's share at a medium vertex (connection_shares.h)
    if (v.origin) {
        ConnectionShares::Shares made;
        p = densitiesOf(scene, *v.origin, MediumPath{&light, pick, ls.p, landedLight(li, ls), ls.pdf, ls.isDelta, scatterPdf},
                        mode, tables, shares.q, false, &made);
        w = powerWeight(p.a, p);
        q = made.vertex;
    } else {
        w = ls.isDelta ? 1.0f : powerHeuristic(pick * ls.pdf, scatterPdf);
    }
    if (w == 0) return Spectrum(0.0f);
    WalkSegment seg = leaving(v.p, v.bsdf ? v.ng : Vec3(0.0f), ls.wi, ls.dist, !ls.isDelta, lightTarget(scene, landedLight(li, ls)));
    Spectrum T = transmittanceAlong(scene, seg, media, stats);
    const Spectrum value = f * ls.Le * T * (w / (q * pick * ls.pdf));
    if (v.origin) shares.note(ConnectionShares::Technique::Vertex, value, w, p);
    if (v.origin) family.weigh(scene, v.p, *v.origin->seg.medium, li, ls.p, v.origin->pFreeFlight, v.origin->seg, v.origin->t);
    return value;
}

// Next-event estimation towards emissive media (volume_light_sampling.h) from vertex `depth`
// (ng: its surface's geometric normal, or 0 in a medium): f·e·T / (|x − y|²·p_n(y)), weighted
// against the gathering along the walk's next ray (its direction density: the guided mixture
// where the walk is guided).
Spectrum volumeDirect(const Scene& scene, const Vertex& v, Vec3 ng, const MediumStack& media, const Sampler& sampler,
                      int depth, PathStats& stats) {
    VolumeLightConnection c;
    if (!connectVolumeLight(scene, v.p, ng, media, sampler, dim::volumeLight(depth), stats, &c)) return Spectrum(0.0f);
    float pdir;
    const Spectrum f = v.eval(c.wi, &pdir, true);
    return f * c.Le * volumeLightWeight(true, c.pdf, pdir, c.stratumLength, c.dist);
}

// The in-scattered estimate at x(t) on seg from a light sample, weighted w / p_self:
// T(0, t)·σs(x)·phase·Le·T(x, y). `tr` is the transit over [0, t].
Spectrum inScattered(const Scene& scene, const MediumSegment& seg, const MediumTransit& tr, Vec3 x, const LightSample& ls,
                     int li, float phase, float weightOverPdf, const MediumStack& media, PathStats& stats) {
    Spectrum T = transmittanceAlong(
        scene, leaving(x, Vec3(0.0f), ls.wi, ls.dist, !ls.isDelta, lightTarget(scene, landedLight(li, ls))), media, stats);
    if (isBlack(T)) return T;
    return tr.T * seg.medium->sigmaSAt(x) * ls.Le * T * (phase * weightOverPdf);
}

// Strategy C: a light and its anchor first, then t equi-angularly on the segment, then the
// connection. Returns the estimate to be multiplied by the throughput at the segment start.
// passing: the walk passes through this segment (PathTracer::sample), so free flight makes no
// vertex on it and C stands alone, as in the equiangular and product modes.
Spectrum equiAngularDirect(const Scene& scene, const MediumSegment& seg, const MediumStack& media,
                           ConnectMode mode, Spectrum channels, const Sampler& sampler, uint32_t dims, uint32_t repeat,
                           SolidAngleTables& tables, bool passing, const GuidingField* field, const GuidedDistance* gd,
                           PathStats& stats, const ShareNotes& shares, const FamilyShare& family = FamilyShare{}) {
    if (scene.lightDistribution().empty()) return Spectrum(0.0f);
    float pick;
    int li = pickLightAlong(scene, sampler, dims, repeat, seg.o, seg.d, seg.tEnd, &pick);
    const Light& light = scene.lights()[li];
    if (!usesEquiAngular(scene, mode, light, seg)) return Spectrum(0.0f);
    // Numbers only for what this light needs: a triangle's anchor (also its light point), a
    // sphere's light point.
    const bool onSurface = light.isPlanar();  // the anchor is a point on the emitter (lightAnchor)
    const Sample2 uAnchor = onSurface ? sampler.get2D(dims + dim::kAnchor, repeat) : Sample2{0, 0};
    const float uT = sampler.get1D(dims + dim::kEquiAngular, repeat);
    Vec3 anchor;
    EquiAngular ea;
    if (!lightAnchor(light, uAnchor, &anchor) ||
        !equiAngularTowards(light, anchor, seg, connectAnisotropy(mode, seg.medium->g), &ea))
        return Spectrum(0.0f);
    MediumOrigin origin{seg, sampleEquiAngular(ea, uT), 0.0f};
    float pea = equiAngularPdf(ea, origin.t);
    if (!(pea > 0) || !std::isfinite(pea)) return Spectrum(0.0f);
    Vec3 x = seg.o + seg.d * origin.t;
    // A triangle's light point by area from the same numbers lands exactly on the anchor.
    LightSample ls;
    if (!sampleLightByArea(scene, light, x, onSurface ? uAnchor : lightPointNumbers(light, sampler, dims + dim::kLightPoint, repeat),
                           &ls) || isBlack(ls.Le))
        return Spectrum(0.0f);
    const Medium& m = *seg.medium;
    float phase = hgPhase(dot(seg.d, ls.wi), m.g);
    const Ray ray{seg.o, seg.d, seg.tEnd};
    MediumTransit tr = m.transit(ray, 0.0f, origin.t, false, true);
    origin.pFreeFlight = distanceDensity(m, tr, channels, gd, origin.t);
    // (B cannot reach a point or spot light: its density, guided or not, is then not needed.)
    MediumPath path{&light, pick, ls.p, li, ls.pdf, ls.isDelta, ls.isDelta ? phase : directionPdfAt(field, x, seg.d, m.g, ls.wi, phase)};
    path.c = double(pick) * ls.pdf * pea;
    if (onSurface) path.pL = lightPdf(scene, light, x, ls.p, Vec3(0.0f));  // A's and D's p_L
    // equiangular, product, passing: C replaces A
    const StrategyDensities p = densitiesOf(scene, origin, path, mode, tables, shares.q, mode != ConnectMode::Mis || passing);
    float w = powerWeight(p.c, p);
    if (w == 0) return Spectrum(0.0f);
    const Spectrum value = inScattered(scene, seg, tr, x, ls, li, phase, float(w / p.c), media, stats);
    shares.note(ConnectionShares::Technique::Segment, value, w, p);
    family.weigh(scene, x, m, li, ls.p, pea, seg, origin.t);
    return value;
}

// Strategy D: t in proportion to the solid angle of an emissive triangle, then a light point
// from x(t) as in A (uniform in that solid angle).
Spectrum solidAngleDirect(const Scene& scene, const MediumSegment& seg, const MediumStack& media, ConnectMode mode,
                          Spectrum channels, const Sampler& sampler, uint32_t dims, uint32_t repeat,
                          SolidAngleTables& tables, const GuidingField* field, const GuidedDistance* gd, PathStats& stats,
                          const ShareNotes& shares) {
    if (scene.lightDistribution().empty()) return Spectrum(0.0f);
    float pick;
    int li = pickLightAlong(scene, sampler, dims, repeat, seg.o, seg.d, seg.tEnd, &pick);
    const Light& light = scene.lights()[li];
    if (!usesSolidAngle(scene, mode, light, seg)) return Spectrum(0.0f);
    const SolidAngleDistance* sd = tables.get(scene, li, seg);
    if (!sd) return Spectrum(0.0f);
    MediumOrigin origin{seg, sampleSolidAngleDistance(*sd, sampler.get1D(dims + dim::kEquiAngular, repeat)), 0.0f};
    const float pOmega = solidAngleDistancePdf(*sd, origin.t);
    if (!(pOmega > 0) || !std::isfinite(pOmega)) return Spectrum(0.0f);
    const Vec3 x = seg.o + seg.d * origin.t;
    LightSample ls;
    if (!sampleLight(scene, light, x, sampler.get2D(dims + dim::kLightPoint, repeat), &ls) || isBlack(ls.Le))
        return Spectrum(0.0f);
    const Medium& m = *seg.medium;
    const float phase = hgPhase(dot(seg.d, ls.wi), m.g);
    MediumTransit tr = m.transit(Ray{seg.o, seg.d, seg.tEnd}, 0.0f, origin.t, false, true);
    origin.pFreeFlight = distanceDensity(m, tr, channels, gd, origin.t);
    MediumPath path{&light, pick, ls.p, landedLight(li, ls), ls.pdf, false, directionPdfAt(field, x, seg.d, m.g, ls.wi, phase)};
    path.d = double(pick) * pOmega * ls.pdf;
    const StrategyDensities p = densitiesOf(scene, origin, path, mode, tables, shares.q);
    const float w = powerWeight(p.d, p);
    if (w == 0) return Spectrum(0.0f);
    const Spectrum value = inScattered(scene, seg, tr, x, ls, li, phase, float(w / p.d), media, stats);
    shares.note(ConnectionShares::Technique::SolidAngle, value, w, p);
    return value;
}

// A recording walk's training records (path_guide.h), with the throughput after each
// recorded vertex and the radiance gathered before it; at most 16 a walk.
struct TrainingWalk {
    static constexpr int kMaxRecords = 16;
    GuideRecord records[kMaxRecords];
    Spectrum beta[kMaxRecords], L[kMaxRecords];
    int count = 0;
    void add(const GuideRecord& r, const Spectrum& betaAfter, const Spectrum& before) {
        if (count == kMaxRecords) return;
        records[count] = r;
        beta[count] = betaAfter;
        L[count++] = before;
    }
};

// Counts the rays a part of a sample traces, and its calls (PathTracerCounts).
// tracing: also counts the calls that traced a ray (PathTracerCounts::segmentTracingCalls).
struct PartMeter {
    PathStats& stats;
    uint64_t& rays;
    uint64_t* tracing;
    uint64_t start;
    PartMeter(PathStats& s, uint64_t& raysCount, uint64_t& callsCount, uint64_t* tracingCalls = nullptr)
        : stats(s), rays(raysCount), tracing(tracingCalls), start(s.rays) {
        ++callsCount;
    }
    ~PartMeter() {
        rays += stats.rays - start;
        if (tracing && stats.rays > start) ++*tracing;
    }
};

}  // namespace

bool PathTracer::pointLikeLightInMedium(const Scene& scene) {
    if (!scene.hasMedia()) return false;
    for (const Light& light : scene.lights())
        if ((light.kind == LightKind::Point || light.kind == LightKind::Spot || light.kind == LightKind::Sphere) &&
            scene.mediaAt(light.position).current() >= 0)
            return true;
    return false;
}

Spectrum PathTracer::sample(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                            PathStats& stats, const OneEventSplit* split) const {
    const bool nee = options_.nextEventEstimation;
    const ConnectMode mode = options_.connect;
    const int maxDepth = options_.maxDepth < 0 ? 1 << 30 : options_.maxDepth;
    const Ray cameraRay = scene.camera().generateRay(fx, fy, width, height);
    const uint64_t rays0 = stats.rays, connections0 = stats.counts.pt.connectionRays();
    WalkSegment ray = leaving(cameraRay.o, Vec3(0.0f), cameraRay.d);
    MediumStack media = scene.cameraMedia();
    Spectrum L(0.0f), beta(1.0f);
    int depth = 0;                 // scattering events so far: the index of the last vertex
    bool specularBounce = true;    // the last direction came from a delta distribution (or the camera)
    float prevPdf = 0;             // solid-angle density of the last sampled direction
    Vec3 prevP = ray.o;
    MediumOrigin prevOrigin;       // valid when the last vertex was in a medium
    bool prevInMedium = false;
    SolidAngleTables tables;       // of the piece being walked; prevTables: of prevOrigin's piece
    SolidAngleTables prevTables;
    // What each technique adds to the pixel (--stats, technique_sums.h).
    TechniqueSample techniques;
    // Path guiding: the field this pass reads, and the walk's training records with the
    // throughput after each recorded vertex and the radiance gathered before it (their
    // difference, divided by the throughput, is the radiance that came back, path_guide.h).
    const GuidingField* field = guide_ ? guide_->field() : nullptr;
    const uint32_t pixel = uint32_t(std::min(std::max(int(fy), 0), height - 1)) * uint32_t(width) +
                           uint32_t(std::min(std::max(int(fx), 0), width - 1));
    const bool training = guide_ && guide_->records(pixel, width, height);
    // Guided survival (below): the pixel's value as training saw it, and at the last vertex
    // the throughput before its scattering and what its cell says a walk brings back.
    const float pixelValue = field ? guide_->pixelEstimate(pixel, width, height) : -1.0f;
    Spectrum betaBefore(0.0f);
    float adjoint = -1;
    // Made only for a walk that records (an unguided sample does not fill 1.4 KB for nothing).
    std::optional<TrainingWalk> train;
    if (training) train.emplace();
    auto counted = [&](PathTracerTechnique t, const Spectrum& v) {
        techniques.add(techniqueSlot(t), v);
        return v;
    };

    // With --max-depth m, as in the bidirectional tracer (docs/mis.md, "Passing through
    // media at the last event"): past the last event only an emitter hit could count, so the
    // walk stops there when no emitter can be hit; and on the ray towards the last event,
    // where every light has a position (point and spot lights only), the equi-angular
    // connection covers the whole medium part, so the walk passes through it (weight T)
    // instead of sampling a collision that would serve only the free-flight connection, and
    // reaches the surface behind.
    const bool limited = options_.maxDepth >= 0;
    // An emissive medium's pieces count however the walk ends, so neither shortcut applies.
    const bool hittable = scene.hasHittableLights() || scene.hasEmissiveMedia();
    // Next-event estimation towards emissive media with grids (volume_light_sampling.h): from
    // every vertex that is not specular, MIS-weighted against what the ray leaving that vertex
    // gathers from those media (below).
    const bool volumeNee = nee && options_.volumeLights && !scene.volumeLights().empty();
    const bool passLast = limited && nee && mode != ConnectMode::Density && !hittable &&
                          !scene.hasDirectionalLights() && !scene.hasInvisibleBoundaries();

    // How often the light connections in media are made (connection_shares.h), and their
    // records while the shares are learnt.
    thread_local std::vector<ConnectionShares::Record> shareRecords;
    shareRecords.clear();
    const bool learningShares = shares_ && shares_->learning() && !sharesPaused_ && mode == ConnectMode::Mis;
    // (Records only where the learning replays the samples: its lattice of pixels.)
    const ShareNotes notes{shares_ ? shares_->shares() : options_.shares,
                           learningShares && ConnectionShares::learnsAt(width, height, pixel) ? &shareRecords : nullptr};
    uint32_t mediumVertexCalls = 0;
    uint32_t passingSegmentCalls = 0;  // segment calls that traced where the walk passes through
    // Emission of the emitter at `hit`, reached along `ray` from the last vertex (strategy B),
    // weighted against the light connections that could have made the same path.
    auto emitterWeight = [&](const SurfaceHit& hit, const Spectrum& Le) {
        if (!nee || specularBounce) return 1.0f;
        const int li = hit.sphereLight >= 0 ? hit.sphereLight : scene.triangleLight(hit.mesh, hit.triangle);
        const Light& light = scene.lights()[li];
        const LightSelection& selection = scene.lightSelection();
        const MediumSegment& seg = prevOrigin.seg;
        const float pick = prevInMedium ? selection.pmfAlong(seg.o, seg.d, seg.tEnd, li) : selection.pmfAt(prevP, li);
        const float pL = lightPdf(scene, light, prevP, hit.p, hit.ng);
        if (!prevInMedium) return powerHeuristic(prevPdf, pick * pL);
        const StrategyDensities p = densitiesOf(scene, prevOrigin, MediumPath{&light, pick, hit.p, li, pL, false, prevPdf},
                                                mode, prevTables, notes.q);
        const float w = powerWeight(p.b, p);
        notes.note(ConnectionShares::Technique::Emitter, beta * Le * w, w, p);
        return w;
    };
    auto emitterHit = [&](const SurfaceHit& hit) {
        const Spectrum Le = scene.emission(hit, -ray.d);
        if (isBlack(Le)) return;
        Spectrum value = beta * Le * emitterWeight(hit, Le);
        // A sphere light hit from the one event x: the camera family's share of the path
        // (one_event_split.h, "Sphere lights").
        if (split && depth == 1 && prevInMedium && hit.sphereLight >= 0) {
            float share = 1;
            FamilyShare{split, &share}.weigh(scene, prevP, *prevOrigin.seg.medium, hit.sphereLight, hit.p, 0.0, prevOrigin.seg,
                                             prevOrigin.t);
            value = split->share(value, share);
        }
        L += counted(PathTracerTechnique::EmitterHit, value);
    };
    // A transparent emitter the ray crosses (Material::transparent; a boundary piece's end):
    // its emission, as if the ray had ended there, and the walk goes on unchanged. Nothing
    // from one the camera does not see reaches the pinhole straight (depth 0).
    auto crossing = [&](const BoundaryPiece& piece) {
        const Material* m = piece.boundary ? scene.transparentEmitter(piece.hit) : nullptr;
        if (m && (depth > 0 || m->cameraVisible)) emitterHit(piece.hit);
    };

    for (int guard = 0; guard < 100000; ++guard) {
        if (limited && depth >= maxDepth && !hittable) break;
        const bool passing = passLast && depth + 1 == maxDepth;
        // The ray leaves vertex `depth`; its pieces between invisible boundaries are walked
        // one by one, each with the equi-angular strategy and free flight of its own.
        const uint32_t dims = dim::walkVertex(dim::Side::Camera, depth);
        const uint32_t eaDims = dim::equiAngularSegment(depth);
        BoundaryWalk walk(scene, ray, media, stats);
        BoundaryPiece piece;
        bool scattered = false;
        while (walk.next(&piece)) {
            const uint32_t repeat = uint32_t(piece.index);
            const Medium* m = piece.medium;
            if (!m) {
                if (!piece.boundary) break;
                crossing(piece);
                continue;
            }
            MediumSegment seg{ray.o + ray.d * piece.t0, ray.d, piece.t1 - piece.t0, m};
            tables.clear();
            // What the piece emits back to its start (medium_emission.cpp), before its free
            // flight (counted with the emitter hits in --stats). After a vertex that sampled
            // the volume lights, each point of a medium they sample is weighted against that
            // (volume_light_sampling.h); elsewhere only a camera walk makes these paths.
            if (m->emissive()) {
                const int mi = scene.mediumIndex(m);
                const Medium::PointWeight weight = gatheringWeight(scene, mi, prevPdf);
                const bool weighted = volumeNee && !specularBounce && scene.volumeLights().samples(mi);
                L += counted(PathTracerTechnique::EmitterHit,
                             beta * m->emitted(Ray{ray.o, ray.d}, piece.t0, piece.t1,
                                               sampler.get1D(dim::mediumEmission(depth) + dim::kEmission, repeat),
                                               weighted ? &weight : nullptr));
            }
            // In a coloured medium the channel that drives the distance is drawn in proportion
            // to the throughput (medium.h): no channel's weight can then grow along the path.
            const Spectrum channels = m->grey() ? Spectrum(1.0f / 3.0f) : throughputChannels(beta);
            // Guided distances on this piece (guided_distance.h): in homogeneous grey media,
            // where the field knows the piece and guiding lowers the predicted variance.
            const GuidedDistance guidedDistance =
                field && !passing && depth <= options_.guidedDistanceDepth && !m->heterogeneous() && m->grey()
                    ? GuidedDistance::on(field, seg.o, seg.d, seg.tEnd, m->sigmaT().x, guide_->settings().fixedShare)
                    : GuidedDistance{};
            const GuidedDistance* gd = guidedDistance.share() > 0 ? &guidedDistance : nullptr;
            // C, made with probability qC (connection_shares.h; always outside mis mode, and
            // with a share of 0 only where the walk passes through: ConnectionShares::madeWith).
            const bool makeC = mode != ConnectMode::Mis || notes.q.segment >= 1 ||
                               (notes.q.segment <= 0 ? passing : sampler.get1D(eaDims + dim::kConnect, repeat) < notes.q.segment);
            if (nee && mode != ConnectMode::Density && depth + 1 <= maxDepth && makeC) {
                const uint64_t tracing = stats.counts.pt.segmentTracingCalls;
                {
                    const PartMeter meter(stats, stats.counts.pt.segmentRays, stats.counts.pt.segmentCalls,
                                          &stats.counts.pt.segmentTracingCalls);
                    float share = 1;
                    const Spectrum value =
                        beta * equiAngularDirect(scene, seg, walk.media(), mode, channels, sampler, eaDims, repeat, tables,
                                                 passing, field, gd, stats, notes.scaled(beta),
                                                 FamilyShare{depth == 0 ? split : nullptr, &share});
                    L += counted(PathTracerTechnique::OnSegment, split ? split->share(value, share) : value);
                }
                if (passing && stats.counts.pt.segmentTracingCalls != tracing) ++passingSegmentCalls;
            }
            // D, made unless its share is 0 (with triangle lights the walk never passes through:
            // passLast; so A and B make its paths then: ConnectionShares::madeWith).
            if (nee && mode == ConnectMode::Mis && depth + 1 <= maxDepth && scene.hasTriangleLights() &&
                (notes.q.solidAngle > 0 || passing)) {
                const PartMeter meter(stats, stats.counts.pt.solidAngleRays, stats.counts.pt.solidAngleCalls);
                L += counted(PathTracerTechnique::BySolidAngle,
                             beta * solidAngleDirect(scene, seg, walk.media(), mode, channels, sampler,
                                                     dim::solidAngleSegment(depth), repeat, tables, field, gd, stats,
                                                     notes.scaled(beta)));
            }

            if (passing) {  // (above) weight T
                beta *= m->transmittance(Ray{ray.o, ray.d}, piece.t0, piece.t1);
                if (isBlack(beta) || !piece.boundary) break;
                crossing(piece);
                continue;
            }
            // Free flight over the piece: weight T·σs/p_scatter or T/P_pass, p the mixture
            // over the channels.
            const float uChannel = m->grey() ? 0.0f : sampler.get1D(dims + dim::kChannel, repeat);
            const float uDistance = sampler.get1D(dims + dim::kDistance, repeat);
            MediumSample ms;
            if (gd) {  // the guided mixture: weight T·σs / p, or 1 for a pass (guided_distance.h)
                const GuidedDistanceSample g = gd->sample(uDistance);
                ms.scattered = g.scattered;
                ms.t = piece.t0 + g.t;
                ms.pdf = g.pdf;
                ms.weight = g.scattered ? m->sigmaS * g.weight : Spectrum(1.0f);
            } else {
                ms = m->sampleDistance(Ray{ray.o, ray.d}, piece.t0, piece.t1, uDistance, uChannel, channels, false);
            }
            beta *= ms.weight;
            if (ms.scattered) {
                scattered = true;
                prevOrigin = MediumOrigin{seg, ms.t - piece.t0, float(ms.pdf)};
                break;
            }
            if (isBlack(ms.weight)) break;  // flew to infinity through a medium: T = 0
            if (!piece.boundary) break;
            crossing(piece);
        }
        media = walk.media();
        if (scattered) {
            if (++depth > maxDepth) break;
            const Medium* m = prevOrigin.seg.medium;
            Vertex v;
            v.p = prevOrigin.seg.o + prevOrigin.seg.d * prevOrigin.t;
            v.wo = -ray.d;
            v.origin = &prevOrigin;
            const GuidedPhase guided = GuidedPhase::at(field, v.p, ray.d, m->g);
            v.guided = guided.share > 0 ? &guided : nullptr;
            betaBefore = beta;
            adjoint = guided.cell ? guided.cell->mediumAdjoint : -1.0f;
            Spectrum direct(0.0f);  // per unit of throughput (a training record keeps it)
            // A, made with probability qA in mis mode (connection_shares.h; with a share of 0
            // sampleDirect makes it only where no other strategy can).
            const uint32_t aDims = dim::connection(1, depth + 1);
            if (nee && (mode != ConnectMode::Mis || notes.q.vertex >= 1 || notes.q.vertex <= 0 ||
                        sampler.get1D(aDims + dim::kConnect) < notes.q.vertex)) {
                const PartMeter meter(stats, stats.counts.pt.vertexRays, stats.counts.pt.vertexCalls);
                float share = 1;
                direct = sampleDirect(scene, v, media, mode, sampler, aDims, tables, stats, notes.scaled(beta),
                                      FamilyShare{depth == 1 ? split : nullptr, &share});
                L += counted(PathTracerTechnique::AtVertex, split ? split->share(beta * direct, share) : beta * direct);
                ++mediumVertexCalls;
            }
            if (volumeNee) L += counted(PathTracerTechnique::AtVertex, beta * volumeDirect(scene, v, Vec3(0.0f), media, sampler, depth, stats));
            if (scene.hasTriangleLights() && mode == ConnectMode::Mis) prevTables = tables;
            Vec3 wi;
            if (guided.share > 0) {  // weight phase / p, p the mixture (guided_phase.h)
                wi = guided.sample(sampler.get2D(dims + dim::kDirection));
                prevPdf = guided.pdf(wi);
                beta *= prevPdf > 0 ? hgPhase(dot(ray.d, wi), m->g) / prevPdf : 0.0f;
            } else {
                wi = sampleHG(ray.d, m->g, sampler.get2D(dims + dim::kDirection));  // phase/pdf = 1
                prevPdf = hgPhase(dot(ray.d, wi), m->g);
            }
            if (train) {
                const float phase = hgPhase(dot(ray.d, wi), m->g);
                GuideRecord r{v.p, ray.d, wi, m->g, prevPdf, 0.0f, phase, phase, 0, pixel, uint32_t(depth)};
                r.direct = (direct.x + direct.y + direct.z) / 3.0f;
                train->add(r, beta, L);
            }
            prevP = v.p;
            prevInMedium = true;
            specularBounce = false;
            ray = leaving(v.p, Vec3(0.0f), wi);
            if (!isFinite(beta) || isBlack(beta)) break;
        } else {
            const SurfaceHit& hit = piece.hit;  // what ended the walk
            if (!hit.valid() || piece.boundary || isBlack(beta)) break;

            // Emission reached by the camera ray or by BSDF/phase sampling (strategy B).
            emitterHit(hit);
            if (hit.sphereLight >= 0) break;  // sphere lights are opaque emitters
            if (++depth > maxDepth) break;

            const Mesh& mesh = scene.mesh(hit.mesh);
            Bsdf bsdf = scene.surfaceBsdf(hit.mesh, hit.u, hit.v, hit.ng, hit.ns);
            Vertex v;
            v.p = hit.p;
            v.wo = -ray.d;
            v.bsdf = &bsdf;
            v.ng = hit.ng;
            // Guided at an opaque surface (guided_phase.h, the same mixture with the BSDF in the
            // phase function's place and the radiance mixture itself as the guide):
            //   p(ω) = α · p_guide(ω) + (1 − α) · p_bsdf(ω),  weight f·|cos| / p.
            const GuidingCell* cell = field && !bsdf.isSpecular() ? field->lookup(hit.p) : nullptr;
            const float share = cell ? cell->surfaceShare : 0.0f;
            if (share > 0) {
                v.cell = cell;
                v.surfaceShare = share;
            }
            adjoint = cell ? cell->surfaceAdjoint : -1.0f;
            if (nee && !bsdf.isSpecular()) {
                const PartMeter meter(stats, stats.counts.pt.vertexRays, stats.counts.pt.vertexCalls);
                L += counted(PathTracerTechnique::AtVertex,
                             beta * sampleDirect(scene, v, media, mode, sampler, dim::connection(1, depth + 1), tables, stats,
                                                 ShareNotes{notes.q}));
            }
            if (volumeNee && !bsdf.isSpecular())
                L += counted(PathTracerTechnique::AtVertex, beta * volumeDirect(scene, v, hit.ng, media, sampler, depth, stats));

            BsdfSample bs;
            if (share > 0) {  // u.u picks the technique, rescaled (guided_phase.h: sample)
                Sample2 u = sampler.get2D(dims + dim::kDirection);
                if (u.u < share) {
                    bs.wi = cell->surface.sample(Sample2{std::min(u.u / share, 0x1.fffffep-1f), u.v});
                } else if (!bsdf.sample(v.wo, sampler.get1D(dims + dim::kLobe),
                                        Sample2{std::min((u.u - share) / (1.0f - share), 0x1.fffffep-1f), u.v}, &bs)) {
                    break;
                }
                bs.pdf = share * cell->surface.pdf(bs.wi) + (1.0f - share) * bsdf.pdf(v.wo, bs.wi);
                const Spectrum f = bsdf.eval(v.wo, bs.wi);
                bs.weight = bs.pdf > 0 ? f / bs.pdf : Spectrum(0.0f);
                bs.specular = bs.transmitted = false;  // (opaque, not specular)
            } else if (!bsdf.sample(v.wo, sampler.get1D(dims + dim::kLobe), sampler.get2D(dims + dim::kDirection), &bs)) {
                break;
            }
            betaBefore = beta;
            beta *= bs.weight;
            if (train && !bs.specular && bs.pdf > 0) {
                const Spectrum f = bs.weight * bs.pdf;
                train->add(GuideRecord{hit.p, ray.d, bs.wi, 0.0f, bs.pdf, 0.0f, (f.x + f.y + f.z) / 3.0f,
                                       share > 0 ? bsdf.pdf(v.wo, bs.wi) : bs.pdf, 1, pixel, uint32_t(depth)},
                           beta, L);
            }
            if (bs.transmitted && mesh.interiorMedium >= 0) media.toggle(mesh.interiorMedium);
            specularBounce = bs.specular;
            prevPdf = bs.pdf;
            prevP = hit.p;
            prevInMedium = false;
            ray = leaving(hit.p, hit.ng, bs.wi);
            if (!isFinite(beta) || isBlack(beta)) break;
        }

        // Guided survival (guided_survival.h) after training. During training the larger of
        // it and the throughput roulette: guided survival alone cut the records of a
        // single-scattering scene to a few, while the throughput roulette alone made the
        // training passes the noisiest part of the image (on a lamp behind a doorway, each
        // had 3.2 times a guided pass's variance).
        const bool coloured = scene.mediumChannels() > 1;
        const bool guided = adjoint >= 0 && pixelValue > 0 && !coloured && depth < kGuidedSurvivalDepth;
        if (guided || depth >= 3) {  // (throughput roulette after three events, sample_dimensions.h: kRoulette)
            float survive = depth >= 3 ? rouletteSurvival(beta, 1.0f, depth, coloured) : 1.0f;
            if (guided) {
                const float g = guidedSurvival(betaBefore, adjoint, pixelValue);
                survive = guide_->training() ? std::max(survive, g) : g;
            }
            if (survive < 1 && sampler.get1D(dims + dim::kRoulette) >= survive) break;
            beta /= survive;
        }
    }
    if (train && train->count > 0) {
        // L_i(p, ω) = (L − L_before) / β_after per channel, their mean. Records that saw no
        // light (along ω, nor by their next-event estimate when guided distances learn it)
        // teach nothing but the cells' means; they are kept one in 8, counting 8
        // (guiding_field.h).
        TrainingWalk& t = *train;
        int kept = 0;
        for (int i = 0; i < t.count; ++i) {
            double sum = 0;
            int channels = 0;
            for (int c = 0; c < 3; ++c)
                if (t.beta[i][c] > 0) {
                    sum += (double(L[c]) - t.L[i][c]) / t.beta[i][c];
                    ++channels;
                }
            const float radiance = channels > 0 ? float(sum / channels) : 0.0f;
            if (!std::isfinite(radiance) || radiance < 0) continue;
            float count = 1;
            if (!(radiance > 0) && !(guide_->settings().inscatter && t.records[i].direct > 0)) {
                if (sampler.get1D(dim::walkVertex(dim::Side::Camera, int(t.records[i].vertex)) + dim::kKeep) >= 0.125f) continue;
                count = 8;
            }
            t.records[kept] = t.records[i];
            t.records[kept].count = count;
            t.records[kept++].radiance = radiance;
        }
        if (kept > 0) guide_->add(t.records, kept);
    }
    if (learningShares)
        shares_->addSample(width, height, pixel, double(L.x + L.y + L.z) / 3.0, shareRecords.data(), int(shareRecords.size()),
                           mediumVertexCalls, passingSegmentCalls);
    ++stats.counts.pt.samples;
    techniques.addTo(stats.techniques);
    stats.counts.pt.walkRays += (stats.rays - rays0) - (stats.counts.pt.connectionRays() - connections0);
    return L;
}

// The guide's state (empty where there is none yet: --guiding auto before it started), then
// the shares' after its length.
std::string PathTracer::saveState() const {
    const std::string guide = guide_ ? guide_->saveState() : std::string();
    if (!shares_) return guide;
    std::string out;
    putBytes(out, uint64_t(guide.size()));
    return out + guide + shares_->saveState();
}

void PathTracer::loadState(const std::string& state) {
    // A guide that --guiding auto had started by then is started again, then restored.
    auto loadGuide = [&](const std::string& bytes, const char* what) {
        if (bytes.empty()) {
            if (options_.guidingAuto) guide_.reset();
            else if (guide_) throw std::runtime_error("guiding state is malformed");
            return;
        }
        if (options_.guidingAuto) startGuide();
        if (!guide_) throw std::runtime_error(what);
        guide_->loadState(bytes);
    };
    if (!shares_) return loadGuide(state, "this integrator keeps no state");
    StateReader reader{state, 0};
    const uint64_t n = reader.get<uint64_t>();
    if (n > state.size() - reader.at) throw std::runtime_error("path tracer state is malformed");
    loadGuide(state.substr(reader.at, size_t(n)), "path tracer state is malformed");
    shares_->loadState(state.substr(reader.at + size_t(n)));
}

}  // namespace brume
