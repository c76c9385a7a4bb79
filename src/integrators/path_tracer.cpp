#include "brume/integrators/path_tracer.h"

#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/equiangular_segment.h"
#include "brume/integrators/light_numbers.h"
#include "brume/integrators/mis.h"
#include "brume/integrators/sample_dimensions.h"
#include "brume/integrators/visibility.h"
#include "brume/sampling/hg.h"
#include "brume/scene/bsdf.h"
#include "brume/scene/light_sampling.h"

namespace brume {

// Strategies for light reaching a path through a point on a medium segment. A light path
// x(t) → y is a pair (t on the segment, y on the light); three strategies can make it:
//   A  free-flight t, then a light sample y from x(t):      pA = p_ff(t) · P(light) · p_L(y|x)
//   B  free-flight t, then phase sampling hits y:           pB = p_ff(t) · p_phase(ω)
//   C  light anchor first, t equi-angular towards it, y:    pC = P(light) · p_L(y|x) · p_ea(t)
// All in the same measure (dt × solid angle at x(t)); p_L(y|x) is the same solid-angle
// density in A and C (uniform area on a triangle, whose point doubles as C's anchor; the
// subtended cone of a sphere, whose centre is C's anchor; a delta for point and spot lights,
// for which B is impossible). Each estimate is weighted by the power heuristic
// p_self² / (pA² + pB² + pC²) over the strategies the mode turns on. At surfaces only A and B.
namespace {

float powerWeight(float self, float other1, float other2) {
    float s = self * self, sum = s + other1 * other1 + other2 * other2;
    return sum > 0 ? s / sum : 0.0f;
}

// Where a medium vertex came from: needed to weigh strategies that could have made it.
struct MediumOrigin {
    MediumSegment seg;
    float t = 0;
    float pFreeFlight = 0;  // p_ff(t) within the segment
};

// A scattering vertex as next-event estimation sees it.
struct Vertex {
    Vec3 p;
    Vec3 wo;                         // towards the previous vertex
    const Bsdf* bsdf = nullptr;      // surface vertex
    Vec3 ng;                         // surface vertex: geometric normal
    const MediumOrigin* origin = nullptr;  // medium vertex

    Spectrum eval(Vec3 wi, float* pdf) const {
        if (bsdf) {
            *pdf = bsdf->pdf(wo, wi);
            return bsdf->eval(wo, wi);
        }
        float p = hgPhase(dot(-wo, wi), origin->seg.medium->g);
        *pdf = p;
        return Spectrum(p);
    }
};

// Equi-angular (or product) density of t on `origin`'s segment for a light whose sampled point is y.
float equiAngularDensity(const Scene& scene, const Light& light, Vec3 y, const MediumOrigin& origin, ConnectMode mode) {
    Vec3 anchor = light.kind == LightKind::Triangle ? y : light.position;
    EquiAngular ea;
    if (!equiAngularTowards(scene, light, anchor, origin.seg, connectAnisotropy(mode, origin.seg.medium->g), &ea))
        return 0.0f;
    return equiAngularPdf(ea, origin.t);
}

// Channel probabilities in proportion to the throughput β (uniform if β is black).
Spectrum throughputChannels(Spectrum beta) {
    float sum = beta.x + beta.y + beta.z;
    return sum > 0 ? beta / sum : Spectrum(1.0f / 3.0f);
}

bool usesDensity(ConnectMode m, const Light& l) { return !variantOnly(m) || l.kind == LightKind::Directional; }
bool usesEquiAngular(ConnectMode m, const Light& l) { return m != ConnectMode::Density && l.kind != LightKind::Directional; }

// Strategy A: next-event estimation from a surface or free-flight medium vertex.
Spectrum sampleDirect(const Scene& scene, const Vertex& v, const MediumStack& media, ConnectMode mode,
                      const Sampler& sampler, uint32_t dims, PathStats& stats) {
    if (scene.lightDistribution().empty()) return Spectrum(0.0f);
    float pick;
    int li = pickLight(scene, sampler, dims, 0, &pick);
    const Light& light = scene.lights()[li];
    if (v.origin && !usesDensity(mode, light)) return Spectrum(0.0f);  // C's job in this mode
    LightSample ls;
    if (!sampleLight(scene, light, v.p, lightPointNumbers(light, sampler, dims + dim::kLightPoint, 0), &ls) || isBlack(ls.Le)) return Spectrum(0.0f);
    float scatterPdf;
    Spectrum f = v.eval(ls.wi, &scatterPdf);
    if (isBlack(f)) return Spectrum(0.0f);
    float w;
    if (v.origin) {
        float pff = v.origin->pFreeFlight;
        float pA = pff * pick * ls.pdf;
        float pB = ls.isDelta ? 0.0f : pff * scatterPdf;
        float pC = usesEquiAngular(mode, light) ? pick * ls.pdf * equiAngularDensity(scene, light, ls.p, *v.origin, mode) : 0.0f;
        w = powerWeight(pA, pB, pC);
    } else {
        w = ls.isDelta ? 1.0f : powerHeuristic(pick * ls.pdf, scatterPdf);
    }
    if (w == 0) return Spectrum(0.0f);
    WalkSegment seg = leaving(v.p, v.bsdf ? v.ng : Vec3(0.0f), ls.wi, ls.dist, !ls.isDelta, lightTarget(scene, li));
    Spectrum T = transmittanceAlong(scene, seg, media, stats);
    return f * ls.Le * T * (w / (pick * ls.pdf));
}

// Strategy C: a light and its anchor first, then t equi-angularly on the segment, then the
// connection. Returns the estimate to be multiplied by the throughput at the segment start.
Spectrum equiAngularDirect(const Scene& scene, const MediumSegment& seg, const MediumStack& media,
                           ConnectMode mode, Spectrum channels, const Sampler& sampler, uint32_t dims, uint32_t repeat,
                           PathStats& stats) {
    if (scene.lightDistribution().empty()) return Spectrum(0.0f);
    float pick;
    int li = pickLight(scene, sampler, dims, repeat, &pick);
    const Light& light = scene.lights()[li];
    if (!usesEquiAngular(mode, light)) return Spectrum(0.0f);
    // Numbers only for what this light needs: a triangle's anchor (also its light point), a
    // sphere's light point.
    const Sample2 uAnchor = light.kind == LightKind::Triangle ? sampler.get2D(dims + dim::kAnchor, repeat) : Sample2{0, 0};
    const float uT = sampler.get1D(dims + dim::kEquiAngular, repeat);
    Vec3 anchor;
    EquiAngular ea;
    if (!equiAngularAnchor(scene, light, uAnchor, &anchor) ||
        !equiAngularTowards(scene, light, anchor, seg, connectAnisotropy(mode, seg.medium->g), &ea))
        return Spectrum(0.0f);
    MediumOrigin origin{seg, sampleEquiAngular(ea, uT), 0.0f};
    float pea = equiAngularPdf(ea, origin.t);
    if (!(pea > 0) || !std::isfinite(pea)) return Spectrum(0.0f);
    Vec3 x = seg.o + seg.d * origin.t;
    // A triangle's light sample from the same numbers lands exactly on the anchor.
    LightSample ls;
    if (!sampleLight(scene, light, x, light.kind == LightKind::Triangle ? uAnchor : lightPointNumbers(light, sampler, dims + dim::kLightPoint, repeat),
                     &ls) || isBlack(ls.Le))
        return Spectrum(0.0f);
    const Medium& m = *seg.medium;
    float phase = hgPhase(dot(seg.d, ls.wi), m.g);
    const Ray ray{seg.o, seg.d, seg.tEnd};
    MediumTransit tr = m.transit(ray, 0.0f, origin.t, false, true);
    origin.pFreeFlight = float(m.grey() ? tr.fwd[0] : tr.fwd.mix(channels));  // what free flight would have had
    float pC = pick * ls.pdf * pea;
    float pA = mode == ConnectMode::Mis ? origin.pFreeFlight * pick * ls.pdf : 0.0f;
    float pB = ls.isDelta ? 0.0f : origin.pFreeFlight * phase;
    float w = powerWeight(pC, pA, pB);
    if (w == 0) return Spectrum(0.0f);
    Spectrum T = transmittanceAlong(scene, leaving(x, Vec3(0.0f), ls.wi, ls.dist, !ls.isDelta, lightTarget(scene, li)),
                                    media, stats);
    if (isBlack(T)) return T;
    return tr.T * m.sigmaSAt(x) * ls.Le * T * (phase * w / pC);
}

}  // namespace

Spectrum PathTracer::sample(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                            PathStats& stats) const {
    const bool nee = options_.nextEventEstimation;
    const ConnectMode mode = options_.connect;
    const int maxDepth = options_.maxDepth < 0 ? 1 << 30 : options_.maxDepth;
    const Ray cameraRay = scene.camera().generateRay(fx, fy, width, height);
    WalkSegment ray = leaving(cameraRay.o, Vec3(0.0f), cameraRay.d);
    MediumStack media = scene.cameraMedia();
    Spectrum L(0.0f), beta(1.0f);
    int depth = 0;                 // scattering events so far: the index of the last vertex
    bool specularBounce = true;    // the last direction came from a delta distribution (or the camera)
    float prevPdf = 0;             // solid-angle density of the last sampled direction
    Vec3 prevP = ray.o;
    MediumOrigin prevOrigin;       // valid when the last vertex was in a medium
    bool prevInMedium = false;

    for (int guard = 0; guard < 100000; ++guard) {
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
                if (piece.boundary) continue;
                break;
            }
            MediumSegment seg{ray.o + ray.d * piece.t0, ray.d, piece.t1 - piece.t0, m};
            // In a coloured medium the channel that drives the distance is drawn in proportion
            // to the throughput (medium.h): no channel's weight can then grow along the path.
            const Spectrum channels = m->grey() ? Spectrum(1.0f / 3.0f) : throughputChannels(beta);
            if (nee && mode != ConnectMode::Density && depth + 1 <= maxDepth)
                L += beta * equiAngularDirect(scene, seg, walk.media(), mode, channels, sampler, eaDims, repeat, stats);

            // Free flight over the piece: weight T·σs/p_scatter or T/P_pass, p the mixture
            // over the channels.
            const float uChannel = m->grey() ? 0.0f : sampler.get1D(dims + dim::kChannel, repeat);
            MediumSample ms = m->sampleDistance(Ray{ray.o, ray.d}, piece.t0, piece.t1,
                                                sampler.get1D(dims + dim::kDistance, repeat), uChannel, channels, false);
            beta *= ms.weight;
            if (ms.scattered) {
                scattered = true;
                prevOrigin = MediumOrigin{seg, ms.t - piece.t0, float(ms.pdf)};
                break;
            }
            if (isBlack(ms.weight)) break;  // flew to infinity through a medium: T = 0
            if (!piece.boundary) break;
        }
        media = walk.media();
        if (scattered) {
            if (++depth > maxDepth) break;
            const Medium* m = prevOrigin.seg.medium;
            Vertex v;
            v.p = prevOrigin.seg.o + prevOrigin.seg.d * prevOrigin.t;
            v.wo = -ray.d;
            v.origin = &prevOrigin;
            if (nee) L += beta * sampleDirect(scene, v, media, mode, sampler, dim::connection(1, depth + 1), stats);
            Vec3 wi = sampleHG(ray.d, m->g, sampler.get2D(dims + dim::kDirection));  // phase/pdf = 1
            prevPdf = hgPhase(dot(ray.d, wi), m->g);
            prevP = v.p;
            prevInMedium = true;
            specularBounce = false;
            ray = leaving(v.p, Vec3(0.0f), wi);
            if (!isFinite(beta) || isBlack(beta)) break;
        } else {
            const SurfaceHit& hit = piece.hit;  // what ended the walk
            if (!hit.valid() || piece.boundary || isBlack(beta)) break;

            // Emission reached by the camera ray or by BSDF/phase sampling (strategy B).
            Spectrum Le = scene.emission(hit, -ray.d);
            if (!isBlack(Le)) {
                float w = 1.0f;
                if (nee && !specularBounce) {
                    int li = hit.sphereLight >= 0 ? hit.sphereLight : scene.triangleLight(hit.mesh, hit.triangle);
                    const Light& light = scene.lights()[li];
                    float pick = scene.lightDistribution().pmf(li);
                    float pL = lightPdf(scene, light, prevP, hit.p, hit.ng);
                    if (prevInMedium) {
                        float pB = prevOrigin.pFreeFlight * prevPdf;
                        float pA = usesDensity(mode, light) ? prevOrigin.pFreeFlight * pick * pL : 0.0f;
                        float pC = usesEquiAngular(mode, light)
                                       ? pick * pL * equiAngularDensity(scene, light, hit.p, prevOrigin, mode)
                                       : 0.0f;
                        w = powerWeight(pB, pA, pC);
                    } else {
                        w = powerHeuristic(prevPdf, pick * pL);
                    }
                }
                L += beta * Le * w;
            }
            if (hit.sphereLight >= 0) break;  // sphere lights are opaque emitters
            if (++depth > maxDepth) break;

            const Mesh& mesh = scene.mesh(hit.mesh);
            Bsdf bsdf = scene.surfaceBsdf(hit.mesh, hit.u, hit.v, hit.ng, hit.ns);
            Vertex v;
            v.p = hit.p;
            v.wo = -ray.d;
            v.bsdf = &bsdf;
            v.ng = hit.ng;
            if (nee && !bsdf.isSpecular())
                L += beta * sampleDirect(scene, v, media, mode, sampler, dim::connection(1, depth + 1), stats);

            BsdfSample bs;
            if (!bsdf.sample(v.wo, sampler.get1D(dims + dim::kLobe), sampler.get2D(dims + dim::kDirection), &bs)) break;
            beta *= bs.weight;
            if (bs.transmitted && mesh.interiorMedium >= 0) media.toggle(mesh.interiorMedium);
            specularBounce = bs.specular;
            prevPdf = bs.pdf;
            prevP = hit.p;
            prevInMedium = false;
            ray = leaving(hit.p, hit.ng, bs.wi);
            if (!isFinite(beta) || isBlack(beta)) break;
        }

        // Russian roulette after three events (sample_dimensions.h: kRoulette).
        if (depth >= 3) {
            float survive = rouletteSurvival(beta, 1.0f, depth, scene.mediumChannels() > 1);
            if (survive < 1 && sampler.get1D(dims + dim::kRoulette) >= survive) break;
            beta /= survive;
        }
    }
    return L;
}

}  // namespace brume
