#include "brume/integrators/one_event_split.h"

#include <algorithm>
#include <cmath>

#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/direct_light_tracing.h"
#include "brume/integrators/equiangular_segment.h"
#include "brume/integrators/light_numbers.h"
#include "brume/integrators/path_stats.h"
#include "brume/integrators/sample_dimensions.h"
#include "brume/integrators/splat_list.h"
#include "brume/integrators/visibility.h"
#include "brume/sampling/equiangular.h"
#include "brume/sampling/hg.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"
#include "brume/scene/light_pixels.h"
#include "brume/scene/light_sampling.h"

namespace brume {

bool oneEventSplitApplies(const Scene& scene) {
    if (scene.lightDistribution().empty() || scene.hasBoundedMedia() || scene.hasInvisibleBoundaries() ||
        scene.hasTransparentEmitters() || scene.hasEmissiveMedia() || scene.hasTriangleLights())
        return false;
    for (const Light& l : scene.lights())
        if ((!l.isDelta() && l.kind != LightKind::Sphere) || l.atInfinity()) return false;
    for (const Medium& m : scene.desc().media)
        if (m.heterogeneous() || !m.grey() || m.emissive()) return false;
    return true;
}

namespace {

// Σ π² of the light family's techniques at distance s along its ray (y, d): free flight, and
// (unless --connect density) the equi-angular stand-in over [0, ∞) towards the pinhole c.
double lightSquares(ConnectMode mode, float sigmaT, Vec3 y, Vec3 d, float s, Vec3 c) {
    const double ff = double(sigmaT) * std::exp(-double(sigmaT) * s);
    if (mode == ConnectMode::Density) return ff * ff;
    const double ea = equiAngularStandInPdf(y, d, c, s);
    return ff * ff + ea * ea;
}

// Splats whose weight W_L is likely below this are made with probability W_L / kSplatLevel
// (then counted that many times more): below it, tracing their rays costs more than their
// share of the image is worth.
constexpr double kSplatLevel = 1.0 / 8.0;

}  // namespace

float OneEventSplit::cameraWeight(const Scene& scene, Vec3 x, const Medium& m, int li, Vec3 y, double cameraDensity) const {
    if (q <= 0 || kappa <= 0) return 1.0f;
    const Camera& cam = scene.camera();
    const Vec3 c = cam.position;
    const Vec3 toX = x - c;
    const float sc = length(toX);
    if (!(sc > 0)) return 1.0f;
    // pdfDir = We·cosθ (camera_importance.h), from the one projection of x onto the film, which
    // also gives the film density around a light's image (drawn by inverse distance there,
    // light_pixels.h); 0 off the film.
    CameraConnection cx;
    double pdfDir = 0;
    if (connectToCamera(cam, x, width, height, &cx))
        pdfDir = double(cx.We) * -double(dot(cx.wi, cam.forward)) * (lightPixels ? double(lightPixels->density(cx.fx, cx.fy)) : 1.0);
    // The camera family (the path tracer) picks its light along the camera ray, light tracing
    // by power (light_selection.h): p_C carries the ratio of the two picks, here over the
    // unbounded ray (a stand-in both families compute alike).
    const double pick = scene.lightSelection().spatial()
                            ? double(scene.lightSelection().pmfAlong(c, toX / sc, kInfinity, li)) /
                                  double(scene.lightDistribution().pmf(li))
                            : 1.0;
    return weightFrom(scene, x, m, li, y, pdfDir / (double(sc) * sc) * cameraDensity * pick);
}

double OneEventSplit::rayPick(const Scene& scene, Vec3 dir, int li) const {
    if (!scene.lightSelection().spatial()) return 1.0;
    if (li != pickLight_) {
        pickLight_ = li;
        rayPickValue_ = double(scene.lightSelection().pmfAlong(scene.camera().position, dir, kInfinity, li)) /
                        double(scene.lightDistribution().pmf(li));
    }
    return rayPickValue_;
}

// x on the camera ray through (rayFx_, rayFy_): pdfDir = 1/(A·cos³θ) of its direction
// (camera_importance.h) and m at that film position, the pick along the ray (the same
// numbers as cameraWeight takes from x, up to rounding), once per sample.
float OneEventSplit::cameraFamilyWeight(const Scene& scene, Vec3 x, const Medium& m, int li, Vec3 y, double cameraDensity) const {
    if (q <= 0 || kappa <= 0) return 1.0f;
    const Camera& cam = scene.camera();
    const Vec3 toX = x - cam.position;
    const double s2 = double(dot(toX, toX));
    if (!(s2 > 0)) return 1.0f;
    const double s = std::sqrt(s2);
    const Vec3 dir = toX / float(s);
    const double cos = double(dot(dir, cam.forward));
    if (rayFilm_ < 0)
        rayFilm_ = cos > 0 ? double(cameraPdfDir(cam, dir, width, height)) * cos * cos * cos *
                                 (lightPixels ? double(lightPixels->density(rayFx_, rayFy_)) : 1.0)
                           : 0.0;
    return weightFrom(scene, x, m, li, y, rayFilm_ / (cos * cos * cos * s2) * cameraDensity * rayPick(scene, dir, li));
}

float OneEventSplit::weightFrom(const Scene& scene, Vec3 x, const Medium& m, int li, Vec3 y, double pc) const {
    const Vec3 fromLight = x - y;
    const float sl = length(fromLight);
    if (!(sl > 0)) return 1.0f;
    float pos, dir;
    const Vec3 dl = fromLight / sl;
    const Light& light = scene.lights()[size_t(li)];
    emissionPdf(scene, light, y, Vec3(0.0f), dl, &pos, &dir);
    double pl = q * kappa * double(dir) / (double(sl) * sl);
    if (light.kind == LightKind::Sphere) {  // y's own densities (header, "Sphere lights")
        const Vec3 n = normalize(y - light.position);
        const Vec3 c = scene.camera().position;
        const Vec3 wc = normalize(x - c);
        const double pA = lightPdf(scene, light, x, y, n), pB = hgPhase(dot(wc, -dl), m.g);
        pc *= (pA + pB) * std::abs(double(dot(n, dl))) / (double(sl) * sl);
        pl *= double(pos);
    }
    const double B = pl * pl * lightSquares(mode, m.sigmaT().x, y, dl, sl, scene.camera().position);
    const double A = pc * pc;
    if (!(B > 0)) return 1.0f;
    if (!(A > 0)) return 0.0f;
    return float(A / (A + B));
}

double OneEventSplit::cameraDensity(const Scene& scene, Vec3 x, const Medium& m, const Light& light,
                                    PathStats& stats) const {
    const Vec3 c = scene.camera().position;
    const float s = length(x - c);
    if (!(s > 0)) return 0.0;
    const Vec3 d = (x - c) / s;
    if (mode == ConnectMode::Density) return cameraDensityOn(light, MediumSegment{c, d, kInfinity, &m}, s);
    // The path tracer's segment: the camera ray to its first surface.
    ++stats.rays;
    const SurfaceHit hit = scene.intersect(leaving(c, Vec3(0.0f), d).query);
    return cameraDensityOn(light, MediumSegment{c, d, hit.valid() ? hit.t : kInfinity, &m}, s);
}

double OneEventSplit::cameraDensityOn(const Light& light, const MediumSegment& seg, float t) const {
    const float sigmaT = seg.medium->sigmaT().x;
    if (mode == ConnectMode::Density) return double(sigmaT) * std::exp(-double(sigmaT) * t);
    EquiAngular ea;
    if (!equiAngularTowards(light, light.position, seg, connectAnisotropy(mode, seg.medium->g), &ea)) return 0.0;
    return double(equiAngularPdf(ea, t));
}

// The light family (one_event_split.h): x = y + t·d on the light's ray, before its first
// surface, by free flight and (unless --connect density) equi-angularly towards the pinhole
// within the view frustum, each connected to the camera:
//   value = Le/(P·p_e) · e^(−σt t)·σs / π_v(t) · phase · T(x, c) · We·cosθ/|x − c|²
// (camera_importance.h), weighted π_v² / (π_ff² + π_ea²) within light tracing (the exact
// densities of this ray), then W_L = 1 − W_C, and counted 1/q. Where W_L is likely small (its
// bound from the camera family's density taken from below, with no ray: equi-angular over the
// unbounded ray, whose normalisation is at least a segment's; with --connect density the free
// flight itself), the splat is made with probability r = W_L bound / kSplatLevel before any ray
// is traced, and counted 1/r.
void oneEventLightTracing(const Scene& scene, const OneEventSplit& split, const Sampler& sampler, PathStats& stats,
                          SplatList& splats, DirectLightTracing* learning) {
    const uint32_t start = dim::kLightStart;
    float pick;
    const int li = pickLight(scene, sampler, start, 0, &pick);
    const Light& light = scene.lights()[size_t(li)];
    EmissionSample es;
    if (!sampleEmission(scene, light, sampler.get2D(start + dim::kPosition), sampler.get2D(start + dim::kEmitDir), &es) ||
        isBlack(es.Le) || !(es.pdfDir > 0))
        return;
    const Medium* m = scene.medium(scene.lightMedia(li).current());
    if (!m) return;
    const float sigmaT = m->sigmaT().x;
    if (!(sigmaT > 0)) return;
    const Camera& cam = scene.camera();
    // The ray to its first surface; equi-angular: its part inside the view frustum.
    ++stats.rays;
    ++stats.counts.bdpt.lightWalkRays;
    const SurfaceHit hit = scene.intersect(leaving(es.p, Vec3(0.0f), es.d).query);
    const float tEnd = hit.valid() ? hit.t : kInfinity;
    float a = 0, b = tEnd;
    const bool eaOn = split.mode != ConnectMode::Density && clipToFrustum(cam, split.width, split.height, es.p, es.d, &a, &b);
    EquiAngular ea;
    if (eaOn) ea = makeEquiAngular(es.p, es.d, cam.position, a, b);
    auto density = [&](bool equiAngular, float t) -> double {
        if (equiAngular) return eaOn && t >= a && t <= b ? double(equiAngularPdf(ea, t)) : 0.0;
        return t < tEnd ? double(sigmaT) * std::exp(-double(sigmaT) * t) : 0.0;
    };
    const float gCamera = connectAnisotropy(split.mode, m->g);
    // (Le·|cos θ_y| / (pdfPos·p_e); no cosine at a point or spot light.)
    const float cosY = light.kind == LightKind::Sphere ? std::abs(dot(es.n, es.d)) : 1.0f;
    const Spectrum emitted = es.Le * cosY / (pick * es.pdfPos * es.pdfDir) * m->sigmaS;
    for (int variant = 0; variant < 2; ++variant) {
        const bool equiAngular = variant == 1;
        if (equiAngular && !eaOn) continue;
        const float t = equiAngular ? sampleEquiAngular(ea, sampler.get1D(dim::connection(2, 1) + dim::kEquiAngular))
                                    : -std::log1p(-sampler.get1D(dim::walkVertex(dim::Side::Light, 0) + dim::kDistance)) / sigmaT;
        const double p = density(equiAngular, t), pOther = density(!equiAngular, t);
        if (!(p > 0) || !std::isfinite(p)) continue;
        const Vec3 x = es.p + es.d * t;
        CameraConnection cc;
        if (!connectToCamera(cam, x, split.width, split.height, &cc)) continue;
        double r = 1;  // the splat's probability
        if (!learning) {
            // The camera family's density of x from below: with --connect density exactly its
            // free flight (the equi-angular stand-in, above it near the light's closest
            // approach, made the bound too small there and the splat's 1/r a heavy tail); else
            // equi-angular over the unbounded ray, towards where C aims (a sphere's centre).
            const Vec3 c = cam.position;
            const float sc = cc.dist;
            const double below = split.mode == ConnectMode::Density
                                     ? double(sigmaT) * std::exp(-double(sigmaT) * sc)
                                     : double(equiAngularStandInPdf(c, -cc.wi, light.kind == LightKind::Sphere ? light.position : es.p,
                                                                    sc, gCamera));
            const double bound = 1.0 - split.cameraWeight(scene, x, *m, li, es.p, below);
            r = std::min(1.0, bound / kSplatLevel);
            const float u = equiAngular ? sampler.get1D(dim::connection(2, 1) + dim::kConnect)
                                        : sampler.get1D(dim::walkVertex(dim::Side::Light, 0) + dim::kRoulette);
            if (!(u < r)) continue;
        }
        const uint64_t rays0 = stats.rays;
        const Spectrum T = transmittanceAlong(scene, leaving(x, Vec3(0.0f), cc.wi, cc.dist), scene.cameraMedia(), stats);
        const Spectrum value =
            isBlack(T) ? Spectrum(0.0f)
                       : emitted * T * float(std::exp(-double(sigmaT) * t) / p * hgPhase(dot(es.d, cc.wi), m->g) * cc.We *
                                             dot(-cc.wi, cam.forward) / (double(cc.dist) * cc.dist));
        const double within = p * p / (p * p + pOther * pOther);
        if (learning) learning->addLight(int(cc.fx), int(cc.fy), value * float(within / split.q));
        double w = 0;
        if (!isBlack(value)) {
            const double pCamera = split.cameraDensity(scene, x, *m, light, stats);
            w = within * (1.0 - split.cameraWeight(scene, x, *m, li, es.p, pCamera)) / (split.q * r);
        }
        stats.counts.bdpt.rays(StrategyKind::CameraConnection, equiAngular) += stats.rays - rays0;
        const Spectrum splat = value * float(w);
        if (split.cameraSplit) {  // the check: measured, not splatted
            learning->addSplitLight(int(cc.fx), int(cc.fy), splat);
            continue;
        }
        if (isBlack(splat)) continue;
        ++stats.counts.bdpt.contribution(StrategyKind::CameraConnection, equiAngular);
        stats.techniques.addAlone(techniqueSlot(StrategyKind::CameraConnection, equiAngular), splat);
        splats.splat(cc.fx, cc.fy, splat, split.width, split.height);
    }
}

}  // namespace brume
