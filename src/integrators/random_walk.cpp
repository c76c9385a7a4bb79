#include "brume/integrators/random_walk.h"

#include <algorithm>
#include <limits>

#include "brume/guiding/guided_phase.h"
#include "brume/guiding/guided_survival.h"
#include "brume/integrators/free_flight_walk.h"
#include "brume/sampling/free_flight.h"
#include "brume/sampling/hg.h"

namespace brume {

// Free-flight densities along an edge prev → next that may cross invisible boundaries into
// other media (pieces k = 1..n, free_flight_walk.h):
//   forward  = Π_{k<n} P_pass,k · (next is a medium point ? p_scatter,n : P_pass,n)
//   reverse  = Π_{k>1} P_pass,k · (prev is a medium point ? p_scatter,1 : P_pass,1)
// the reverse being the density with which a walk from next back to prev would stop at prev.
namespace {

int walk(const Scene& scene, const WalkStart& start, TransportMode mode, int maxScatter, const Sampler& sampler,
         PathVertex* path, int maxVertices, PathStats& stats);

// Directional densities of every edge, from the vertex positions: rays leave surfaces from
// offset origins, so the sampled direction differs slightly from the edge's own direction,
// and MIS needs densities that are functions of the path alone (every strategy must see the
// same numbers for the same path). Free-flight densities come from the walk (per edge).
// ghostAfter: path[count] records a ray the walk traced from path[count − 1] without making a
// vertex (PathVertex::ghost); an equi-angular variant may place one there, on that ray from
// path[count − 1].p itself, so path[count − 2].pdfRev uses the ray's direction.
// guide: the camera walk's (random_walk.h), read by the densities that are that walk's (pdfFwd
// on the camera side, pdfRev on the light side).
void edgeDensities(const Scene& scene, PathVertex* path, int count, int width, int height, bool ghostAfter,
                   bool cameraSide, const GuidingField* guide) {
    const GuidingField* fwdGuide = cameraSide ? guide : nullptr;
    const GuidingField* revGuide = cameraSide ? nullptr : guide;
    for (int i = 1; i < count; ++i) {  // wo along the edge itself, not the offset ray
        Vec3 back = path[i - 1].p - path[i].p;
        float len = length(back);
        if (len > 0) path[i].wo = back / len;
        path[i].edgeDist = len;
    }
    for (int i = 1; i < count; ++i) {
        PathVertex& prev = path[i - 1];
        PathVertex& v = path[i];
        Vec3 toV = v.p - prev.p;
        float dist = length(toV);
        if (!(dist > 0)) {
            v.pdfFwd = prev.pdfRev = Channels(0.0);
            continue;
        }
        Vec3 w = toV / dist;
        Vec3 prevFrom = i >= 2 ? normalize(path[i - 2].p - prev.p) : prev.wo;
        if (!prev.delta)
            v.pdfFwd = solidAngleToArea(v, w, vertexDirectionPdf(scene, prev, prevFrom, w, width, height, fwdGuide), dist) *
                       v.edgeFwdFreeFlight;
        if ((i + 1 < count || ghostAfter) && !v.delta) {
            Vec3 vFrom = i + 1 < count ? normalize(path[i + 1].p - v.p) : path[i + 1].edgeDir;
            prev.pdfRev = solidAngleToArea(prev, w, vertexDirectionPdf(scene, v, vFrom, -w, width, height, revGuide), dist) *
                          v.edgeRevFreeFlight;
        }
    }
}

}  // namespace

void crossingPathDensities(const Scene& scene, PathVertex* path, int count, int width, int height,
                           const GuidingField* guide) {
    edgeDensities(scene, path, count, width, height, false, true, guide);
}

int randomWalk(const Scene& scene, const WalkStart& start, TransportMode mode, int maxScatter, const Sampler& sampler,
               PathVertex* path, int maxVertices, PathStats& stats) {
    int count = walk(scene, start, mode, maxScatter, sampler, path, maxVertices, stats);
    edgeDensities(scene, path, count, start.width, start.height, count < maxVertices && path[count].ghost,
                  start.side == dim::Side::Camera, start.guide);
    return count;
}

namespace {

int walk(const Scene& scene, const WalkStart& start, TransportMode mode, int maxScatter, const Sampler& sampler,
         PathVertex* path, int maxVertices, PathStats& stats) {
    WalkSegment ray = start.ray;
    MediumStack media = start.media;
    Spectrum beta = start.beta;
    float pdfDir = start.pdfDir;
    const bool coloured = scene.mediumChannels() > 1;
    const float rrScale = maxComponent(start.beta) > 0 ? maxComponent(start.beta) : 1.0f;
    const Spectrum channels = heroChannel(start.hero);
    const GuidingField* guide = start.side == dim::Side::Camera ? start.guide : nullptr;  // (random_walk.h)
    int count = 1, scatters = 0;
    if (maxVertices > 1) path[1].ghost = false;
    while (count < maxVertices && scatters < maxScatter) {
        PathVertex& prev = path[count - 1];
        PathVertex& v = path[count];
        v = PathVertex{};
        const uint32_t dims = dim::walkVertex(start.side, count - 1);
        // The ray's own record, kept even if it makes no vertex (see PathVertex::ghost).
        v.edgeOrigin = ray.o;
        v.edgeDir = ray.d;
        v.edgeBeta = beta;
        v.edgeMedia = media;
        v.edgeMedium = scene.medium(media.current());
        v.ghost = true;
        // A camera walk gathers emissive media's emission on every ray (weighted over the
        // channels from prev's on: free_flight_walk.h).
        FlightEmission emission{prev.channelRatio, start.hero, scene.mediumChannels(), start.heuristic,
                                dim::mediumEmission(count - 1)};
        emission.againstVolumeLights = count - 1 >= 1 && count - 1 <= start.volumeLightsUpTo && !prev.delta;
        emission.dirPdf = pdfDir;
        const bool gathers = start.side == dim::Side::Camera && scene.hasEmissiveMedia();
        // Transparent emitters the flight crosses (emitter_crossing.h), where the walk wants them.
        thread_local std::vector<FlightCrossing> crossedHere;
        std::vector<FlightCrossing>* crossed = nullptr;
        if (start.crossings) {
            crossed = &crossedHere;
            crossed->clear();
        }
        Flight f = sampleFlight(scene, ray, media, prev.isMedium(), channels, throughputChannels(beta), sampler, dims, stats,
                                count >= start.passFrom || (count == start.passFirstAt && !prev.delta),
                                gathers ? &emission : nullptr, crossed);
        v.edgeEnd = f.firstEnd;
        v.edgeEmission = beta * emission.gathered;
        for (size_t i = 0; crossed && i < crossed->size(); ++i) {  // as the vertex the ray would make there
            const FlightCrossing& x = (*crossed)[i];
            start.crossings->push_back(CrossingVertex{count, v});
            PathVertex& y = start.crossings->back().vertex;
            y.ghost = false;
            y.edgeEmission = Spectrum(0.0f);
            y.kind = VertexKind::Surface;
            y.p = x.hit.p;
            y.ng = x.hit.ng;
            y.ns = x.hit.ns;
            y.u = x.hit.u;
            y.v = x.hit.v;
            y.mesh = x.hit.mesh;
            y.triangle = x.hit.triangle;
            y.light = scene.triangleLight(x.hit.mesh, x.hit.triangle);
            y.edgeCrossed = x.crossedBefore;
            y.wo = -ray.d;
            y.media = media;
            y.beta = beta * x.weight;
            y.edgeDist = x.t;
            y.edgeFwdFreeFlight = x.fwd;
            y.edgeRevFreeFlight = x.rev;
            y.pdfFwd = solidAngleToArea(y, y.wo, pdfDir, x.t) * x.fwd;
            y.channelRatio = prev.channelRatio;
            if (x.fwd[start.hero] > 0)
                for (int c = 0; c < 3; ++c) y.channelRatio[c] *= x.fwd[c] / x.fwd[start.hero];
        }
        if (f.end == Flight::End::Escape) return count;
        beta *= f.weight;
        media = f.media;
        const float dist = f.t;
        const Channels fwdFF = f.fwd, revFF = f.rev;
        if (f.end == Flight::End::Collision) {
            v.kind = VertexKind::Medium;
            v.p = ray.o + ray.d * f.t;
            v.medium = f.medium;
        } else {
            const SurfaceHit& hit = f.hit;
            v.kind = VertexKind::Surface;
            v.p = hit.p;
            v.ng = hit.ng;
            v.ns = hit.ns;
            v.u = hit.u;
            v.v = hit.v;
            v.mesh = hit.mesh;
            v.triangle = hit.triangle;
            v.light = hit.sphereLight >= 0 ? hit.sphereLight : scene.triangleLight(hit.mesh, hit.triangle);
        }
        v.edgeCrossed = f.crossed;
        if (!isFinite(beta) || isBlack(beta)) return count;

        v.wo = -ray.d;
        v.media = media;
        v.beta = beta;
        v.edgeDist = dist;
        v.edgeFwdFreeFlight = fwdFF;
        v.ghost = false;
        v.edgeRevFreeFlight = revFF;
        v.pdfFwd = solidAngleToArea(v, v.wo, pdfDir, dist) * fwdFF;
        v.channelRatio = prev.channelRatio;
        if (fwdFF[start.hero] > 0)
            for (int c = 0; c < 3; ++c) v.channelRatio[c] *= fwdFF[c] / fwdFF[start.hero];
        ++count;
        ++scatters;
        // Until a next ray is traced, the slot after the path holds no ray record.
        if (count < maxVertices) path[count].ghost = false;
        if (v.isSurface() && v.mesh < 0) break;  // a sphere light: an opaque emitter
        if (count >= maxVertices || scatters >= maxScatter) break;

        // Sample the continuation; its reverse density completes prev.pdfRev.
        Vec3 wi;
        float pdfFwdDir, pdfRevDir;
        // Guided (camera walk with a guide): from the mixture α · guide + (1 − α) · phase/BSDF,
        // weight f / p_mixture (guided_phase.h; u.u picks the technique, rescaled). The reverse
        // density is the light walk's, never guided.
        if (v.isMedium()) {
            const GuidedPhase gp = GuidedPhase::at(guide, v.p, ray.d, v.medium->g);
            wi = gp.sample(sampler.get2D(dims + dim::kDirection));
            pdfRevDir = hgPhase(dot(ray.d, wi), v.medium->g);
            pdfFwdDir = gp.share > 0 ? gp.pdf(wi) : pdfRevDir;  // unguided: phase/pdf = 1
            if (gp.share > 0) beta *= pdfFwdDir > 0 ? pdfRevDir / pdfFwdDir : 0.0f;
        } else {
            Bsdf bsdf = vertexBsdf(scene, v);
            const GuidingCell* cell = guide && !bsdf.isSpecular() ? guide->lookup(v.p) : nullptr;
            const float share = cell ? cell->surfaceShare : 0.0f;
            BsdfSample bs;
            const Sample2 u = sampler.get2D(dims + dim::kDirection);
            if (share > 0) {  // (opaque: only dielectrics, which are specular, transmit)
                if (u.u < share) {
                    bs.wi = cell->surface.sample(Sample2{std::min(u.u / share, 0x1.fffffep-1f), u.v});
                } else if (!bsdf.sample(v.wo, sampler.get1D(dims + dim::kLobe),
                                        Sample2{std::min((u.u - share) / (1.0f - share), 0x1.fffffep-1f), u.v}, &bs, mode)) {
                    return count;
                }
                bs.pdf = share * cell->surface.pdf(bs.wi) + (1.0f - share) * bsdf.pdf(v.wo, bs.wi);
                bs.weight = bs.pdf > 0 ? bsdf.eval(v.wo, bs.wi) / bs.pdf : Spectrum(0.0f);
                bs.specular = bs.transmitted = false;
            } else if (!bsdf.sample(v.wo, sampler.get1D(dims + dim::kLobe), u, &bs, mode)) {
                return count;
            }
            wi = bs.wi;
            Spectrum w = bs.weight;
            if (mode == TransportMode::Importance) w *= shadingNormalCorrection(v.wo, wi, v.ng, v.ns);
            beta *= w;
            if (bs.specular) {
                v.delta = true;
                pdfFwdDir = pdfRevDir = 0;  // delta densities never enter the MIS weights
            } else {
                pdfFwdDir = bs.pdf;
                pdfRevDir = bsdf.pdf(wi, v.wo);
            }
            if (bs.transmitted && scene.mesh(v.mesh).interiorMedium >= 0) media.toggle(scene.mesh(v.mesh).interiorMedium);
        }
        prev.pdfRev = solidAngleToArea(prev, ray.d, pdfRevDir, dist) * revFF;
        if (!isFinite(beta) || isBlack(beta)) return count;

        // Russian roulette from the fourth vertex, relative to the start: a light subpath's
        // throughput carries the light's power (≫ 1) (integrator.h: rouletteSurvival). In
        // coloured media β is f / p_hero, which for another channel c can be far from what
        // the path is worth there; the roulette reads f / avg_c p_c = β / avg_c (p_c / p_hero)
        // instead (bounded by 3 f_c / p_c). On β itself, a path whose hero channel is dim
        // would be cut and its survivors' other channels multiplied up at every bounce.
        // Guided survival of the camera walk with a guiding field (guided_survival.h; v.beta is
        // the throughput before v's scattering). Survival probabilities enter no MIS weight
        // (nor does the throughput roulette's).
        const GuidingCell* cell =
            guide && !coloured && scatters < kGuidedSurvivalDepth ? guide->lookup(v.p) : nullptr;
        const float adjoint = cell ? (v.isMedium() ? cell->mediumAdjoint : cell->surfaceAdjoint) : -1.0f;
        if (adjoint >= 0 && start.pixelValue > 0) {
            const float survive = guidedSurvival(v.beta, adjoint, start.pixelValue);
            if (survive < 1 && sampler.get1D(dims + dim::kRoulette) >= survive) return count;
            beta /= survive;
        } else if (count >= 4) {
            const Channels& r = v.channelRatio;
            const double avg = (r[0] + r[1] + r[2]) / 3.0;
            Spectrum worth = beta;
            if (avg > 0 && avg != 1.0)  // in double, capped to float's range (the ratios reach 1e±300)
                for (int c = 0; c < 3; ++c)
                    worth[c] = float(std::min(double(beta[c]) / avg, double(std::numeric_limits<float>::max())));
            float survive = rouletteSurvival(worth, rrScale, count, coloured);
            if (survive < 1 && sampler.get1D(dims + dim::kRoulette) >= survive) return count;
            beta /= survive;
        }
        ray = leaving(v.p, v.isSurface() ? v.ng : Vec3(0.0f), wi);
        pdfDir = pdfFwdDir;
    }
    return count;
}

}  // namespace

}  // namespace brume
