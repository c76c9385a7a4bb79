#include "brume/integrators/bdpt_strategies.h"

#include <cstring>
#include <type_traits>

#include "brume/integrators/allocation_planner.h"
#include "brume/integrators/bdpt_equiangular.h"
#include "brume/integrators/bdpt_subpaths.h"
#include "brume/integrators/light_numbers.h"
#include "brume/integrators/random_walk.h"
#include "brume/integrators/sample_dimensions.h"
#include "brume/integrators/visibility.h"
#include "brume/integrators/volume_light_sampling.h"
#include "brume/sampling/hg.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"
#include "brume/scene/light_sampling.h"

namespace brume {

namespace {

// Keeps a subpath vertex while a variant's own vertex stands in its slot, and puts it back
// when the variant ends. Its storage is left uninitialised until used: most variants
// (free flight) move nothing, and a vertex is 400-odd bytes.
class VertexSwap {
public:
    VertexSwap() = default;
    VertexSwap(const VertexSwap&) = delete;
    VertexSwap& operator=(const VertexSwap&) = delete;
    ~VertexSwap() {
        if (target_) std::memcpy(static_cast<void*>(target_), storage_, sizeof(PathVertex));
    }
    // Saves *target, which the caller then overwrites; returns the saved copy.
    const PathVertex& save(PathVertex* target) {
        target_ = target;
        std::memcpy(storage_, static_cast<const void*>(target), sizeof(PathVertex));
        return *reinterpret_cast<const PathVertex*>(storage_);
    }

private:
    static_assert(std::is_trivially_copyable<PathVertex>::value, "a vertex is moved by memcpy");
    PathVertex* target_ = nullptr;
    alignas(PathVertex) unsigned char storage_[sizeof(PathVertex)];
};

// A SurfaceHit describing a surface or light vertex, for emission and textures.
SurfaceHit vertexHit(const PathVertex& v) {
    SurfaceHit h;
    h.p = v.p;
    h.ng = v.ng;
    h.ns = v.ns;
    h.u = v.u;
    h.v = v.v;
    h.mesh = v.mesh;
    h.triangle = v.triangle;
    if (v.mesh < 0) h.sphereLight = v.light;
    return h;
}

// Emission leaving a light vertex, or a surface vertex on an emitter, in direction w:
// radiance for area and sphere lights, intensity (with the spot cone) for point and spot.
Spectrum emitted(const Scene& scene, const PathVertex& v, Vec3 w) {
    const Light& l = scene.lights()[v.light];
    return l.isDelta() ? deltaEmission(l, w) : scene.emission(vertexHit(v), w);
}

// f·|cos| (surface), phase (medium) for light arriving from wLight and leaving along wCamera
// towards the camera side. Light subpaths evaluate the adjoint (shading-normal correction).
Spectrum scatter(const Scene& scene, const PathVertex& v, Vec3 wCamera, Vec3 wLight, TransportMode mode) {
    if (v.isMedium()) return Spectrum(hgPhase(dot(-wCamera, wLight), v.medium->g));
    Bsdf bsdf = vertexBsdf(scene, v);
    if (mode == TransportMode::Radiance) return bsdf.eval(wCamera, wLight);
    // Light subpath: wo = v.wo points to the light side, the connection to the camera side.
    return bsdf.eval(wLight, wCamera) * shadingNormalCorrection(wLight, wCamera, v.ng, v.ns);
}

// The media on the side of a vertex that direction w leaves into.
MediumStack mediaTowards(const Scene& scene, const PathVertex& v, Vec3 w) {
    MediumStack m = v.media;
    if (v.isSurface() && v.mesh >= 0) {
        int interior = scene.mesh(v.mesh).interiorMedium;
        if (interior >= 0 && dot(v.wo, v.ng) * dot(w, v.ng) < 0) m.toggle(interior);
    }
    return m;
}

// Sphere lights are opaque emitters: a path that reaches one ends there.
bool scatters(const PathVertex& v) { return v.isMedium() || (v.isSurface() && v.mesh >= 0 && !v.delta); }

// Direction from path[i] back to path[i − 1] (its own wo at a subpath's start).
Vec3 towardsPrevious(const PathVertex* path, int i) {
    return i >= 1 ? normalize(path[i - 1].p - path[i].p) : path[i].wo;
}

bool onSurfaceOrAreaLight(const PathVertex& v) {
    return v.kind == VertexKind::Surface || (v.kind == VertexKind::Light && dot(v.ng, v.ng) > 0);
}

// The surface normal a segment leaving v starts from (zero: v is not on a surface).
Vec3 surfaceNormal(const PathVertex& v) { return onSurfaceOrAreaLight(v) ? v.ng : Vec3(0.0f); }

// Transmittance and free-flight densities between camera-side z and light-side y, and what
// the weight needs of them.
Connection connectVertices(const Scene& scene, const PathVertex& z, const PathVertex& y, PathStats& stats) {
    Vec3 d = y.p - z.p;
    float dist = length(d);
    if (!(dist > 0)) return Connection{};
    d /= dist;
    ShadowTarget target;
    if (y.light >= 0 && y.mesh < 0) target.sphereLight = y.light;
    if (y.mesh >= 0) target.mesh = y.mesh, target.triangle = y.triangle;
    return connectPoints(scene, leaving(z.p, surfaceNormal(z), d, dist, onSurfaceOrAreaLight(y), target),
                         mediaTowards(scene, z, d), z.isMedium(), y.isMedium(), stats);
}

StrategyJoin joinOf(const Connection& conn, bool equiAngular, double equiAngularDensity) {
    return StrategyJoin{conn.freeFlightToA, conn.freeFlightToB, conn.crossed, equiAngular, equiAngular ? equiAngularDensity : 0.0};
}

// Whether the equi-angular variant (on) replaces a connection's free-flight variant at v: where
// it could have made the same medium vertex, with --connect equiangular or an ea-only
// allocation.
bool replaceableByEquiAngular(const PathVertex& v, bool equiAngularOn) {
    return equiAngularOn && v.isMedium() && !v.edgeCrossed;
}
bool replacedByEquiAngular(const MisSettings& st, const PathVertex& v, bool equiAngularOn) {
    return equiAngularReplacesFreeFlight(st) && replaceableByEquiAngular(v, equiAngularOn);
}

// Whether a connection's free-flight variant runs: the vertex must scatter, and not be
// replaced by the equi-angular variant.
bool freeFlightVariantOn(const MisSettings& st, bool real, const PathVertex& v, bool equiAngularOn) {
    return real && scatters(v) && !replacedByEquiAngular(st, v, equiAngularOn);
}

// Variant 0 (free flight) or 1 (equi-angular), as BdptOptions::onlyVariant allows.
bool variantWanted(const StrategyContext& c, int variant, bool on) {
    return on && (c.options.hooks.onlyVariant < 0 || c.options.hooks.onlyVariant == variant);
}

// The equi-angular variant of path[i] (a camera or light subpath): the vertex placed on the
// ray its walk traced from path[i − 1], towards `aim`, with the number u, swapped in for as
// long as `swap` lives. False if no vertex can be placed.
bool swapInEquiAngular(const StrategyContext& c, PathVertex* path, int i, const EquiAngularAim& aim, float u,
                       VertexSwap& swap, double* density) {
    const PathVertex& edge = swap.save(&path[i]);
    return equiAngularVertex(c.scene, edge, path[i - 1], towardsPrevious(path, i - 1), aim, c.mis, u, &path[i], density);
}

// A weighted estimate of a strategy, counted for the pass statistics.
Spectrum counted(const StrategyContext& c, StrategyKind kind, bool equiAngular, Spectrum value) {
    if (!isBlack(value)) ++c.stats.counts.bdpt.contribution(kind, equiAngular);
    // (--stats: a camera connection's splat is its whole share of the pixel it lands in; the
    // others add to the sample's own pixel.)
    if (c.techniques && kind != StrategyKind::CameraConnection) c.techniques->add(techniqueSlot(kind, equiAngular), value);
    else c.stats.techniques.addAlone(techniqueSlot(kind, equiAngular), value);
    return value;
}

// Attributes the rays traced while it lives to a connection's count (BidirectionalCounts).
class RayMeter {
public:
    // also: a second counter of the same rays (or none).
    RayMeter(PathStats& stats, StrategyKind kind, bool equiAngular, uint64_t* also = nullptr)
        : stats_(stats), counter_(stats.counts.bdpt.rays(kind, equiAngular)), also_(also), start_(stats.rays) {}
    ~RayMeter() {
        counter_ += stats_.rays - start_;
        if (also_) *also_ += stats_.rays - start_;
    }

private:
    PathStats& stats_;
    uint64_t& counter_;
    uint64_t* also_;
    uint64_t start_;
};

// The rays of a light (0) or camera (1) connection's free-flight variant that an ea-only
// allocation would not trace, counted apart for the planner's cost of it.
uint64_t* replaceableRays(const StrategyContext& c, int which, bool equiAngular, const PathVertex& v, bool equiAngularOn) {
    return !equiAngular && replaceableByEquiAngular(v, equiAngularOn) ? &c.stats.counts.bdpt.replaceableRays[which] : nullptr;
}

// While statistics are gathered: the contribution `value` (unweighted, for one sample of the
// strategy) with what its weight can be recomputed from under another allocation.
// Returns its index, or −1.
int record(const StrategyContext& c, const PathVertex* lightVertex, int s, int t, const StrategyJoin& join,
           Spectrum value, int x = -1, int y = -1) {
    if (!c.records) return -1;
    c.records->emplace_back();
    WeightRecord& r = c.records->back();
    r.s = s;
    r.t = t;
    r.join = join;
    r.value = value;
    r.x = x;
    r.y = y;
    r.moved = join.equiAngular;
    if (r.moved) r.vertex = t >= 2 ? c.camera[t - 1] : c.light[s - 1];
    r.hasLightVertex = lightVertex != nullptr;  // (light connections: the sampled y0)
    if (lightVertex) r.lightVertex = *lightVertex;
    return int(c.records->size()) - 1;
}

// Marks the free-flight variant's record (index, −1: none) as one an ea-only allocation would
// not make (allocation_statistics.h), where its vertex is `replaceable`.
void markReplaceable(const StrategyContext& c, int recorded, bool replaceable) {
    if (c.records && recorded >= 0 && replaceable) (*c.records)[size_t(recorded)].replaceable = true;
}

// The weight of the joined sample, told to the observer; 1 when unweighted.
float weigh(const StrategyContext& c, PathVertex* light, int s, int t, const StrategyJoin& join) {
    if (!c.weighted) return 1.0f;
    float w = float(strategyWeight(c.scene, light, s, c.camera, t, join, c.mis));
    if (c.options.hooks.observer) c.options.hooks.observer->onWeight(light, s, c.camera, t, w, join.equiAngular, c.mis.hero);
    return w;
}

// direct_light_tracing.h: a contribution to a path of one scattering event, weighted as if
// its family of strategies were alone, into the learning images ((fx, fy): where light
// tracing's lands).
void learnDirect(const StrategyContext& c, PathVertex* light, int s, int t, const StrategyJoin& join, const Spectrum& value,
                 float fx = 0, float fy = 0) {
    if (!c.direct || s + t - 1 != 2) return;
    MisSettings st = c.mis;
    st.directAlone = t == 1 ? MisSettings::Alone::LightTracing : MisSettings::Alone::CameraSide;
    const double w = strategyWeight(c.scene, light, s, c.camera, t, join, st);
    if (!(w > 0) || !std::isfinite(w)) return;
    if (t == 1)
        c.direct->addLight(int(fx), int(fy), value * float(w));
    else
        *c.directCamera += value * float(w);
}

}  // namespace

Spectrum mediumEmission(const StrategyContext& c) {
    Spectrum L(0.0f);
    for (int i = 1; i < c.nCamera; ++i) L += c.camera[i].edgeEmission;
    if (c.nCamera < kMaxSubpathVertices && c.camera[c.nCamera].ghost) L += c.camera[c.nCamera].edgeEmission;
    return isBlack(L) ? L : counted(c, StrategyKind::EmitterHit, false, L);
}

Spectrum volumeLightConnections(const StrategyContext& c, int upTo) {
    Spectrum L(0.0f);
    for (int i = 1; i < c.nCamera && i <= upTo; ++i) {
        const PathVertex& z = c.camera[i];
        if (z.delta || (z.isSurface() && z.mesh < 0)) continue;  // (a sphere light ends the walk)
        VolumeLightConnection conn;
        if (!connectVolumeLight(c.scene, z.p, z.isSurface() ? z.ng : Vec3(0.0f), z.media, c.sampler, dim::volumeLight(i),
                                c.stats, &conn))
            continue;
        const Spectrum f = scatter(c.scene, z, z.wo, conn.wi, TransportMode::Radiance);
        const float pdir = vertexDirectionPdf(c.scene, z, z.wo, conn.wi, c.width, c.height, c.mis.cameraGuide);
        L += z.beta * f * conn.Le * volumeLightWeight(true, conn.pdf, pdir, conn.stratumLength, conn.dist);
    }
    return isBlack(L) ? L : counted(c, StrategyKind::LightConnection, false, L);
}

Spectrum emitterHit(const StrategyContext& c, int t) {
    const PathVertex& z = c.camera[t - 1];
    if (!variantWanted(c, 0, t <= c.nCamera && z.light >= 0 && z.isSurface())) return Spectrum(0.0f);
    Spectrum contrib = z.beta * emitted(c.scene, z, z.wo);
    if (isBlack(contrib)) return contrib;
    float w = weigh(c, c.light, 0, t, StrategyJoin{});
    record(c, nullptr, 0, t, StrategyJoin{}, contrib);
    learnDirect(c, c.light, 0, t, StrategyJoin{}, contrib);
    return std::isfinite(w) ? counted(c, StrategyKind::EmitterHit, false, contrib * w) : Spectrum(0.0f);
}

// The camera path ending on the crossing: its vertices up to the ray's start, then the
// crossing's vertex, with their densities and MIS sums as the walk's own (emitter_crossing.h).
// Not recorded for the planner's statistics (they re-weigh records against the walk's own
// vertex array, which does not hold this one).
Spectrum crossedEmitterHit(const StrategyContext& c, const CrossingVertex& x) {
    const int t = x.index + 1;
    if (t == 2 && x.vertex.light >= 0 && !c.scene.cameraSees(x.vertex.light)) return Spectrum(0.0f);
    thread_local std::vector<PathVertex> path;
    path.assign(c.camera, c.camera + x.index);
    path.push_back(x.vertex);
    crossingPathDensities(c.scene, path.data(), t, c.width, c.height, c.mis.cameraGuide);
    if (c.weighted) misPrefixes(c.scene, path.data(), t, true, c.mis);
    const StrategyContext onPath{c.scene, c.options, c.mis, path.data(), t, c.light, c.nLight, c.weighted, c.sampler,
                                 c.stats, c.width, c.height, nullptr, c.direct, c.directCamera, c.techniques};
    return emitterHit(onPath, t);
}

Spectrum lightConnection(const StrategyContext& c, int t) {
    const Scene& scene = c.scene;
    if (scene.lightDistribution().empty()) return Spectrum(0.0f);
    const uint32_t dims = dim::connection(1, t);
    const PathVertex& zPrev = c.camera[t - 2];
    // The light, picked by where the connection starts (light_numbers.h, lightConnectionPmf):
    // the free-flight variant from z(t−1) itself, or along its ray in a medium; the
    // equi-angular variant along the ray it places z(t−1) on. One number serves both; where
    // picks are power's they are the same pick.
    const bool steered = scene.lightSelection().spatial();
    const float uPick = scene.lightDistribution().size() > 1 ? c.sampler.get1D(dims + dim::kPick) : 0.5f;
    struct Pick {
        int light = -1;
        float pmf = 0;
        Sample2 u{0.5f, 0.5f};  // the light point's numbers
    };
    auto pickFor = [&](bool ea) {
        Pick p;
        const PathVertex& z = c.camera[t - 1];
        p.light = !steered ? scene.lightDistribution().sample(uPick, &p.pmf)
                           : sampleLightConnection(scene, LightConnectionStart{zPrev.p, z.p, ea ? z.edgeDir : Vec3(0.0f), ea || z.isMedium()},
                                                   uPick, &p.pmf);
        p.u = lightPointNumbers(scene.lights()[size_t(p.light)], c.sampler, dims + dim::kLightPoint, 0);
        return p;
    };
    const bool eaPossible = c.mis.connect != ConnectMode::Density && c.mis.equiAngularLight && c.camera[t - 1].edgeMedium &&
                            !zPrev.delta;
    const Pick pickFf = pickFor(false);
    const Pick pickEa = steered && eaPossible ? pickFor(true) : pickFf;
    Vec3 anchor;
    const bool eaOn = eaPossible && lightAnchor(scene.lights()[size_t(pickEa.light)], pickEa.u, &anchor);
    const bool ffOn = freeFlightVariantOn(c.mis, t <= c.nCamera, c.camera[t - 1], eaOn);
    const bool replaceable = replaceableByEquiAngular(c.camera[t - 1], eaOn);
    Spectrum L(0.0f);
    int recordedFreeFlight = -1;  // its record's index (statistics)
    for (int variant = 0; variant < 2; ++variant) {
        const bool ea = variant == 1;
        if (!variantWanted(c, variant, ea ? eaOn : ffOn)) continue;
        RayMeter meter(c.stats, StrategyKind::LightConnection, ea, replaceableRays(c, 0, ea, c.camera[t - 1], eaOn));
        const Pick& picked = ea ? pickEa : pickFf;
        const int li = picked.light;
        const float pick = picked.pmf;
        const Light& l = scene.lights()[size_t(li)];
        const Sample2 uLight = picked.u;
        // The equi-angular variant: z(t−1) on its ray, towards the light's anchor.
        VertexSwap swap;
        double pea = 0;
        if (ea && !swapInEquiAngular(c, c.camera, t - 1, EquiAngularAim{true, anchor, &l, false},
                                     c.sampler.get1D(dims + dim::kEquiAngular), swap, &pea))
            continue;
        const PathVertex& z = c.camera[t - 1];
        // The equi-angular variant's light point is its anchor (by area, drawn before z(t−1)
        // moved); the free-flight variant samples the light as the path tracer does (by solid
        // angle on a triangle). The weights take y0's density as the light subpath's (area)
        // in both: a deterministic function of the path, so they still sum to one.
        LightSample ls;
        const bool sampled = ea ? sampleLightByArea(scene, l, z.p, uLight, &ls) : sampleLight(scene, l, z.p, uLight, &ls);
        if (!sampled || isBlack(ls.Le)) continue;
        // The light the point landed on (the other half of a rectangle, maybe): y0's light.
        const int yi = landedLight(li, ls);
        const Light& yl = scene.lights()[size_t(yi)];
        Spectrum f = scatter(scene, z, z.wo, ls.wi, TransportMode::Radiance);
        if (isBlack(f)) continue;
        // Stop just short of an emitting surface so it does not shadow itself.
        Connection conn = connectPoints(scene, leaving(z.p, surfaceNormal(z), ls.wi, ls.dist, l.hasSurface(), lightTarget(scene, yi)),
                                        mediaTowards(scene, z, ls.wi), z.isMedium(), false, c.stats);
        if (isBlack(conn.T)) continue;
        Spectrum contrib = z.beta * f * ls.Le * conn.T / (pick * ls.pdf);
        if (isBlack(contrib)) continue;
        float w = 1.0f;
        if (c.weighted) {
            // The sampled light vertex y0, with the light subpath's densities. A directional
            // light's vertex sits up its beam (its direction is all the weights read).
            const Vec3 n = lightNormalFacing(yl, ls.p, -ls.wi);
            Vec3 p = std::isinf(ls.dist) ? z.p + ls.wi * std::max(1.0f, 2.0f * scene.boundsRadius()) : ls.p;
            float pos, dir;
            emissionPdf(scene, yl, p, n, -ls.wi, &pos, &dir);
            PathVertex y0 = makeLightVertex(scene, yi, scene.lightDistribution().pmf(yi), p, n, pos);
            const StrategyJoin join = joinOf(conn, ea, pea);
            w = weigh(c, &y0, 1, t, join);
            const int r = record(c, &y0, 1, t, join, contrib);
            if (!ea) recordedFreeFlight = r;
            learnDirect(c, &y0, 1, t, join, contrib);
        }
        if (std::isfinite(w)) L += counted(c, StrategyKind::LightConnection, ea, contrib * w);
    }
    markReplaceable(c, recordedFreeFlight, replaceable);
    return L;
}

void cameraConnection(const StrategyContext& c, int s, SplatList& splats) {
    const Scene& scene = c.scene;
    const Camera& cam = scene.camera();
    const bool real = s <= c.nLight;
    const PathVertex& edge = c.light[s - 1];
    const PathVertex* yPrev = s >= 2 ? &c.light[s - 2] : nullptr;
    const bool eaOn = c.mis.connect != ConnectMode::Density && c.mis.equiAngularCamera && yPrev && edge.edgeMedium &&
                      !yPrev->delta && (real || edge.ghost);
    const bool ffOn = real && (edge.kind == VertexKind::Light || scatters(edge)) && !(s == 1 && edge.deltaLight) &&
                      !replacedByEquiAngular(c.mis, edge, eaOn);
    const bool replaceable = replaceableByEquiAngular(edge, eaOn);
    int recordedFreeFlight = -1;  // its record's index (statistics)
    for (int variant = 0; variant < 2; ++variant) {
        const bool ea = variant == 1;
        if (!variantWanted(c, variant, ea ? eaOn : ffOn)) continue;
        RayMeter meter(c.stats, StrategyKind::CameraConnection, ea, replaceableRays(c, 1, ea, edge, eaOn));
        // The equi-angular variant: y(s−1) on its ray, towards the pinhole (the camera as a
        // point light), within the view frustum.
        VertexSwap swap;
        double pea = 0;
        if (ea && !swapInEquiAngular(c, c.light, s - 1, equiAngularAim(scene, c.camera[0], false),
                                     c.sampler.get1D(dim::connection(s, 1) + dim::kEquiAngular), swap, &pea))
            continue;
        const PathVertex& y = c.light[s - 1];
        CameraConnection cc;
        if (!connectToCamera(cam, y.p, c.width, c.height, &cc)) continue;
        if (c.recordingPixelsOnly && !AllocationPlanner::collectsPixel(int(cc.fx), int(cc.fy))) continue;
        const Vec3 toCam = cc.wi;
        Spectrum f;
        if (y.kind == VertexKind::Light) {
            if (scene.lights()[y.light].atInfinity()) continue;
            if (!scene.cameraSees(y.light)) continue;  // (Material::cameraVisible)
            f = emitted(scene, y, toCam) * (dot(y.ng, y.ng) > 0 ? std::abs(dot(y.ng, toCam)) : 1.0f);
        } else {
            f = scatter(scene, y, toCam, y.wo, TransportMode::Importance);
        }
        if (isBlack(f)) continue;
        Connection conn = connectVertices(scene, c.camera[0], y, c.stats);
        if (isBlack(conn.T)) continue;
        const float cosCam = dot(-toCam, cam.forward);
        Spectrum value = y.beta * f * conn.T * (cc.We * cosCam / (cc.dist * cc.dist));
        if (isBlack(value)) continue;
        const StrategyJoin join = joinOf(conn, ea, pea);
        float w = weigh(c, c.light, s, 1, join);
        const int r = record(c, nullptr, s, 1, join, value, int(cc.fx), int(cc.fy));
        if (!ea) recordedFreeFlight = r;
        learnDirect(c, c.light, s, 1, join, value, cc.fx, cc.fy);
        // (Made cameraConnection ≤ 1 times per sample on average: counted 1/that.)
        if (std::isfinite(w))
            splats.splat(cc.fx, cc.fy, counted(c, StrategyKind::CameraConnection, ea, value * (w / float(c.mis.cameraConnection))),
                         c.width, c.height);
    }
    markReplaceable(c, recordedFreeFlight, replaceable);
}

Spectrum subpathConnection(const StrategyContext& c, int s, int t) {
    const Scene& scene = c.scene;
    const PathVertex& y = c.light[s - 1];
    if (!scatters(y)) return Spectrum(0.0f);
    // Made with probability p (BdptOptions::generalConnection), then counted 1/p.
    const float p = float(c.mis.generalConnection);
    if (p < 1 && c.sampler.get1D(dim::connection(s, t) + dim::kConnect) >= p) return Spectrum(0.0f);
    const PathVertex& zPrev = c.camera[t - 2];
    const bool eaOn = c.mis.connect != ConnectMode::Density && c.mis.generalEquiAngular && c.camera[t - 1].edgeMedium &&
                      !zPrev.delta;
    const bool ffOn = freeFlightVariantOn(c.mis, t <= c.nCamera, c.camera[t - 1], eaOn);
    Spectrum L(0.0f);
    for (int variant = 0; variant < 2; ++variant) {
        const bool ea = variant == 1;
        if (!variantWanted(c, variant, ea ? eaOn : ffOn)) continue;
        RayMeter meter(c.stats, StrategyKind::SubpathConnection, ea);
        // The equi-angular variant: z(t−1) on its ray, towards y(s−1).
        VertexSwap swap;
        double pea = 0;
        if (ea && !swapInEquiAngular(c, c.camera, t - 1, equiAngularAim(scene, y, false),
                                     c.sampler.get1D(dim::connection(s, t) + dim::kEquiAngular), swap, &pea))
            continue;
        const PathVertex& z = c.camera[t - 1];
        Vec3 d = y.p - z.p;
        const float dist = length(d);
        if (!(dist > 0)) continue;
        const Vec3 w = d / dist;  // from the camera side to the light side
        Spectrum fz = scatter(scene, z, z.wo, w, TransportMode::Radiance);
        Spectrum fy = scatter(scene, y, -w, y.wo, TransportMode::Importance);
        if (isBlack(fz) || isBlack(fy)) continue;
        Connection conn = connectVertices(scene, z, y, c.stats);
        if (isBlack(conn.T)) continue;
        Spectrum contrib = z.beta * fz * conn.T * fy * y.beta / (dist * dist);
        if (isBlack(contrib)) continue;
        const StrategyJoin join = joinOf(conn, ea, pea);
        float weight = weigh(c, c.light, s, t, join);
        record(c, nullptr, s, t, join, contrib);
        if (std::isfinite(weight)) L += counted(c, StrategyKind::SubpathConnection, ea, contrib * (weight / p));
    }
    return L;
}

}  // namespace brume
