#include "brume/integrators/bdpt.h"

#include <vector>

#include "brume/integrators/bdpt_mis.h"
#include "brume/integrators/equiangular_segment.h"
#include "brume/integrators/path_vertex.h"
#include "brume/integrators/random_walk.h"
#include "brume/integrators/visibility.h"
#include "brume/sampling/free_flight.h"
#include "brume/sampling/hg.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"
#include "brume/scene/light_sampling.h"

namespace brume {

// Notation (docs/mis.md): camera subpath z0 (the pinhole) … z(t−1), light subpath
// y0 (on a light) … y(s−1); strategy (s, t) connects y(s−1) with z(t−1). Every vertex keeps
// pdfFwd (area density of being made by its own walk) and pdfRev (by the other walk); both
// include free-flight densities. MIS weights (bdpt_mis.cpp) follow Veach's ratio recursion
// with the reverse densities of the four vertices next to the connection recomputed for it.
namespace {

constexpr int kMaxVertices = 1024;  // per subpath; Russian roulette ends paths long before

struct ThreadPaths {
    std::vector<PathVertex> camera = std::vector<PathVertex>(kMaxVertices);
    std::vector<PathVertex> light = std::vector<PathVertex>(kMaxVertices);
    // misPrefixes of each subpath
    std::vector<double> cameraPrefix = std::vector<double>(kMaxVertices), cameraVariant = cameraPrefix;
    std::vector<double> lightPrefix = cameraPrefix, lightVariant = cameraPrefix;
};

// Restores a value when the scope ends: the MIS weight edits vertex densities in place.
template <class T>
struct Scoped {
    T* target = nullptr;
    T saved{};
    Scoped() = default;
    void set(T* t, T value) {
        target = t;
        saved = *t;
        *t = value;
    }
    ~Scoped() {
        if (target) *target = saved;
    }
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
    switch (l.kind) {
    case LightKind::Point: return l.intensity;
    case LightKind::Spot: return l.intensity * spotAttenuation(l, dot(w, l.direction));
    case LightKind::Directional: return l.intensity;
    default: return scene.emission(vertexHit(v), w);
    }
}

// f·|cos| (surface), phase (medium) for light arriving from wIn and leaving along wOut
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

Vec3 offsetFrom(const PathVertex& v, Vec3 w) {
    if (v.kind == VertexKind::Surface || (v.kind == VertexKind::Light && dot(v.ng, v.ng) > 0))
        return offsetOrigin(v.p, v.ng, w);
    return v.p;
}

// Sphere lights are opaque emitters: a path that reaches one ends there.
bool scatters(const PathVertex& v) { return v.isMedium() || (v.isSurface() && v.mesh >= 0 && !v.delta); }

// Direction from path[i] back to path[i − 1] (its own wo at a subpath's start).
Vec3 towardsPrevious(const PathVertex* path, int i) {
    return i >= 1 ? normalize(path[i - 1].p - path[i].p) : path[i].wo;
}

// Whether a connection's free-flight variant runs: the vertex must scatter, and where the
// equi-angular variant could have made the same medium vertex, --connect equiangular has it
// replace the free-flight one.
bool freeFlightVariantOn(ConnectMode mode, bool real, const PathVertex& v, bool equiAngularOn) {
    return real && scatters(v) && !(mode == ConnectMode::EquiAngular && equiAngularOn && v.isMedium() && !v.edgeCrossed);
}

bool onSurfaceOrAreaLight(const PathVertex& v) {
    return v.kind == VertexKind::Surface || (v.kind == VertexKind::Light && dot(v.ng, v.ng) > 0);
}

// Transmittance and free-flight densities between vertices a and b.
Connection connectVertices(const Scene& scene, const PathVertex& a, const PathVertex& b, PathStats& stats) {
    Vec3 d = b.p - a.p;
    float dist = length(d);
    if (!(dist > 0)) return Connection{};
    d /= dist;
    Vec3 o = offsetFrom(a, d);
    float shorten = onSurfaceOrAreaLight(b) ? rayEpsilon(b.p) : 0.0f;
    float travel = length(b.p - o) - shorten;
    ShadowTarget target;
    if (b.light >= 0 && b.mesh < 0) target.sphereLight = b.light;
    if (b.mesh >= 0) target.mesh = b.mesh, target.triangle = b.triangle;
    return connectPoints(scene, o, d, travel, mediaTowards(scene, a, d), a.isMedium(), b.isMedium(), target, stats);
}

// The equi-angular variant of camera vertex z(t−1): a point on the ray the camera walk traced
// from z(t−2) (whatever the free flight made of it: a medium point, a surface, or nothing),
// within that ray's first medium, sampled towards `aim` (clipped as it says). `edge` holds
// the ray (PathVertex::edge*), prev is z(t−2), prevFrom the direction from z(t−2) back
// towards z(t−3). u picks the distance. (Also y(s−1) towards the pinhole, with the light walk.)
bool equiAngularVertex(const Scene& scene, const PathVertex& edge, const PathVertex& prev, Vec3 prevFrom,
                       const EquiAngularAim& aim, MisSettings mis, float u, PathVertex* out) {
    MediumSegment seg{edge.edgeOrigin, edge.edgeDir, edge.edgeEnd, edge.edgeMedium};
    EquiAngular ea;
    if (aim.clip) {
        if (!equiAngularTowards(scene, *aim.clip, aim.anchor, seg, &ea)) return false;
    } else if (aim.toCamera) {
        // The camera as a point light: only the part of the ray inside the view frustum can
        // reach the film.
        float a = 0, b = seg.tEnd;
        if (!clipToFrustum(scene.camera(), mis.width, mis.height, seg.o, seg.d, &a, &b)) return false;
        ea = makeEquiAngular(seg.o, seg.d, aim.anchor, a, b);
    } else {
        ea = makeEquiAngular(seg.o, seg.d, aim.anchor, 0.0f, seg.tEnd);
    }
    float t = sampleEquiAngular(ea, u);
    float pea = equiAngularPdf(ea, t);
    if (!(pea > 0) || !std::isfinite(pea)) return false;
    const Medium& m = *edge.edgeMedium;
    Spectrum sigmaT = m.sigmaT();
    PathVertex v;
    v.kind = VertexKind::Medium;
    v.medium = &m;
    v.media = edge.edgeMedia;
    v.p = seg.o + seg.d * t;
    v.beta = edge.edgeBeta * transmittance(sigmaT, t) * m.sigmaS / pea;
    Vec3 back = prev.p - v.p;
    float dist = length(back);
    if (!(dist > 0) || !isFinite(v.beta)) return false;
    v.wo = back / dist;
    v.edgeDist = dist;
    v.edgeOrigin = edge.edgeOrigin;
    v.edgeDir = edge.edgeDir;
    v.edgeEnd = edge.edgeEnd;
    v.edgeBeta = edge.edgeBeta;
    v.edgeMedium = edge.edgeMedium;
    v.edgeMedia = edge.edgeMedia;
    v.edgeFwdFreeFlight = freeFlightPdfScatter(sigmaT, dist);
    v.edgeRevFreeFlight = prev.isMedium() ? v.edgeFwdFreeFlight : freeFlightPdfPass(sigmaT, dist);
    // pdfFwd: the equi-angular density of the point as the weights see it (the stand-in
    // unless exact): direction density × 1/d² × p_ea.
    v.pdfFwd = solidAngleToArea(v, v.wo, vertexDirectionPdf(scene, prev, prevFrom, -v.wo, mis.width, mis.height), dist) *
               equiAngularDensity(scene, prev, v, aim, mis);
    *out = v;
    return v.pdfFwd > 0;
}

int generateCameraSubpath(const Scene& scene, float fx, float fy, int width, int height, int maxScatter,
                          Sampler& sampler, PathVertex* path, PathStats& stats) {
    const Camera& cam = scene.camera();
    Ray ray = cam.generateRay(fx, fy, width, height);
    PathVertex& z0 = path[0];
    z0 = PathVertex{};
    z0.kind = VertexKind::Camera;
    z0.p = ray.o;
    z0.ng = cam.forward;
    z0.media = scene.cameraMedia();
    z0.beta = Spectrum(1.0f);  // We·cosθ / p_dir = 1 for the pinhole
    WalkStart start{ray, scene.cameraMedia(), Spectrum(1.0f), cameraPdfDir(cam, ray.d, width, height), width, height};
    return randomWalk(scene, start, TransportMode::Radiance, maxScatter, sampler, path, kMaxVertices, stats);
}

int generateLightSubpath(const Scene& scene, int maxScatter, Sampler& sampler, PathVertex* path, PathStats& stats) {
    float uPick = sampler.next1D();
    Sample2 u1 = sampler.next2D(), u2 = sampler.next2D();
    if (scene.lightDistribution().empty()) return 0;
    float pick;
    int li = scene.lightDistribution().sample(uPick, &pick);
    const Light& light = scene.lights()[li];
    if (light.kind == LightKind::Directional) {
        // In an infinite ambient medium a directional light reaches nothing (as in pt).
        const Medium* amb = scene.medium(scene.desc().ambientMedium);
        if (amb && maxComponent(amb->sigmaT()) > 0) return 0;
    }
    EmissionSample es;
    if (!sampleEmission(scene, light, u1, u2, &es) || isBlack(es.Le) || !(es.pdfPos > 0) || !(es.pdfDir > 0)) return 0;
    PathVertex& y0 = path[0];
    y0 = PathVertex{};
    y0.kind = VertexKind::Light;
    y0.light = li;
    y0.p = es.p;
    y0.ng = es.n;
    y0.ns = es.n;
    y0.deltaLight = es.deltaPos || es.deltaDir;
    y0.wo = es.d;
    if (light.kind == LightKind::Triangle) {
        y0.mesh = light.mesh;
        y0.triangle = light.triangle;
        // Texture coordinates of p, for textured emission: barycentrics by areas.
        const Mesh& mesh = scene.mesh(light.mesh);
        if (!mesh.uvs.empty()) {
            const uint32_t* idx = &mesh.indices[3 * light.triangle];
            Vec3 p0 = mesh.positions[idx[0]], p1 = mesh.positions[idx[1]], p2 = mesh.positions[idx[2]];
            Vec3 n = cross(p1 - p0, p2 - p0);
            float nn = dot(n, n);
            float b1 = nn > 0 ? dot(cross(es.p - p0, p2 - p0), n) / nn : 0.0f;
            float b2 = nn > 0 ? dot(cross(p1 - p0, es.p - p0), n) / nn : 0.0f;
            float b0 = 1 - b1 - b2;
            y0.u = mesh.uvs[2 * idx[0]] * b0 + mesh.uvs[2 * idx[1]] * b1 + mesh.uvs[2 * idx[2]] * b2;
            y0.v = mesh.uvs[2 * idx[0] + 1] * b0 + mesh.uvs[2 * idx[1] + 1] * b1 + mesh.uvs[2 * idx[2] + 1] * b2;
        }
    }
    bool directional = light.kind == LightKind::Directional;
    y0.pdfFwd = directional ? pick : pick * es.pdfPos;  // a directional light's position density moves to y1
    y0.beta = Spectrum(1.0f / y0.pdfFwd);
    // A double-sided triangle may emit from its back, where other media may be.
    bool back = false;
    if (light.kind == LightKind::Triangle) {
        const Mesh& mesh = scene.mesh(light.mesh);
        const uint32_t* idx = &mesh.indices[3 * light.triangle];
        Vec3 front = cross(mesh.positions[idx[1]] - mesh.positions[idx[0]], mesh.positions[idx[2]] - mesh.positions[idx[0]]);
        back = dot(es.n, front) < 0;
    }
    MediumStack media = scene.lightMedia(li, back);
    y0.media = media;
    float cosLight = dot(es.n, es.n) > 0 ? std::abs(dot(es.n, es.d)) : 1.0f;
    Spectrum beta = es.Le * (cosLight / (pick * es.pdfPos * es.pdfDir));
    Vec3 origin = dot(es.n, es.n) > 0 ? offsetOrigin(es.p, es.n, es.d) : es.p;
    WalkStart start{Ray{origin, es.d, kInfinity}, media, beta, directional ? 1.0f : es.pdfDir, 0, 0};
    int n = randomWalk(scene, start, TransportMode::Importance, maxScatter, sampler, path, kMaxVertices, stats);
    if (directional && n > 1) {
        // Parallel rays: the disk's area density projects onto y1 with |cos| and no 1/d².
        PathVertex& y1 = path[1];
        y1.pdfFwd = es.pdfPos * (y1.isSurface() ? std::abs(dot(y1.ng, y1.wo)) : 1.0f) * y1.edgeFwdFreeFlight;
    }
    return n;
}

}  // namespace

Spectrum BdptIntegrator::sampleWithSplats(const Scene& scene, float fx, float fy, int width, int height,
                                          Sampler& sampler, PathStats& stats, SplatList& splats) const {
    thread_local ThreadPaths paths;
    PathVertex* camera = paths.camera.data();
    PathVertex* light = paths.light.data();
    // A camera subpath may end on an emitter one vertex past the last scattering event.
    const int maxScatter = options_.maxDepth < 0 ? kMaxVertices : options_.maxDepth;
    const int nCamera = generateCameraSubpath(scene, fx, fy, width, height, maxScatter + 1, sampler, camera, stats);
    const int nLight = generateLightSubpath(scene, maxScatter, sampler, light, stats);
    const Camera& cam = scene.camera();

    Spectrum L(0.0f);
    const bool weighted = options_.onlyS < 0 || options_.weighted;
    const MisSettings mis{options_.heuristic, options_.connect, options_.exactEquiAngular, width, height};
    const SubpathMis cameraMis{paths.cameraPrefix.data(), paths.cameraVariant.data()};
    const SubpathMis lightMis{paths.lightPrefix.data(), paths.lightVariant.data()};
    if (weighted) {
        misPrefixes(scene, camera, nCamera, true, mis, paths.cameraPrefix.data(), paths.cameraVariant.data());
        misPrefixes(scene, light, nLight, false, mis, paths.lightPrefix.data(), paths.lightVariant.data());
    }
    // t = nCamera + 1 exists only for equi-angular vertices on the walk's last, escaped ray.
    const bool anyEquiAngular = options_.connect != ConnectMode::Density;
    for (int t = 1; t <= nCamera + (anyEquiAngular ? 1 : 0); ++t) {
        const bool realPt = t <= nCamera;  // camera[t−1] is a vertex, not only a ray record
        if (!realPt && !camera[t - 1].ghost) break;
        // The s = 1 light sample's numbers, drawn whether or not that strategy runs.
        float uPick1 = t > 1 ? sampler.next1D() : 0.0f;
        Sample2 uLight1 = t > 1 ? sampler.next2D() : Sample2{0, 0};
        // s = 1 draws a fresh light sample, so it runs even when the light subpath is empty.
        // s = nLight + 1 exists only for equi-angular camera connections on the light walk's
        // last, escaped ray.
        for (int s = 0; s <= std::max(nLight, 1) + (anyEquiAngular && t == 1 ? 1 : 0); ++s) {
            // The equi-angular variant's distance, drawn whether or not the strategy runs.
            float uEA = anyEquiAngular && s >= 1 && (t >= 2 || s >= 2) ? sampler.next1D() : 0.0f;
            if (s == 0 && t < 2) continue;
            if (options_.maxDepth >= 0 && s + t - 2 > options_.maxDepth) continue;
            if (options_.onlyS >= 0 && (s != options_.onlyS || t != options_.onlyT)) continue;
            if ((t == 1 || s > 1) && s > nLight && !(t == 1 && s == nLight + 1 && s >= 2 && light[s - 1].ghost)) continue;
            Spectrum contrib(0.0f);
            float weight = 1.0f;
            PathVertex& pt = camera[t - 1];

            if (s == 0) {
                // The camera subpath found an emitter on its own (a free-flight strategy only).
                if (options_.onlyVariant == 1) continue;
                if (!realPt || pt.light < 0 || !pt.isSurface()) continue;
                contrib = pt.beta * emitted(scene, pt, pt.wo);
                if (isBlack(contrib)) continue;
                const Light& l = scene.lights()[pt.light];
                float pos, dir;
                emissionPdf(scene, l, pt.p, pt.ng, pt.wo, &pos, &dir);
                float pick = scene.lightDistribution().pmf(pt.light);
                PathVertex& ptm = camera[t - 2];
                Scoped<double> a, b;
                a.set(&pt.pdfRev, pick * pos);
                b.set(&ptm.pdfRev, solidAngleToArea(ptm, pt.wo, dir, pt.edgeDist) * pt.edgeRevFreeFlight);
                if (weighted) weight = float(misWeight(scene, light, camera, 0, t, mis, false, false, lightMis, cameraMis));
                if (options_.observer) options_.observer->onWeight(light, 0, camera, t, weight, false);
            } else if (t == 1) {
                // Light tracing: connect y(s−1) to the pinhole and splat; with equi-angular
                // connections also y(s−1) placed on the light walk's ray from y(s−2) towards
                // the pinhole (the camera as a point light), within the view frustum.
                const bool realQs = s <= nLight;
                const PathVertex& edge = light[s - 1];
                const PathVertex* yPrev = s >= 2 ? &light[s - 2] : nullptr;
                bool eaOn = anyEquiAngular && yPrev && edge.edgeMedium && !yPrev->delta && (realQs || edge.ghost);
                bool ffOn = realQs && (edge.kind == VertexKind::Light || scatters(edge)) && !(s == 1 && edge.deltaLight) &&
                            !(options_.connect == ConnectMode::EquiAngular && eaOn && edge.isMedium() && !edge.edgeCrossed);
                for (int variant = 0; variant < 2; ++variant) {
                const bool ea = variant == 1;
                if (ea ? !eaOn : !ffOn) continue;
                if (options_.onlyVariant >= 0 && variant != options_.onlyVariant) continue;
                Scoped<PathVertex> swap;
                if (ea) {
                    PathVertex v;
                    Vec3 prevFrom = towardsPrevious(light, s - 2);
                    if (!equiAngularVertex(scene, edge, *yPrev, prevFrom, equiAngularAim(scene, camera[0], false), mis, uEA, &v))
                        continue;
                    swap.set(&light[s - 1], v);
                }
                PathVertex& qs = light[s - 1];
                float weight = 1.0f;
                CameraConnection cc;
                if (!connectToCamera(cam, qs.p, width, height, &cc)) continue;
                Vec3 toCam = cc.wi;
                Spectrum f;
                if (qs.kind == VertexKind::Light) {
                    if (scene.lights()[qs.light].kind == LightKind::Directional) continue;
                    f = emitted(scene, qs, toCam) * (dot(qs.ng, qs.ng) > 0 ? std::abs(dot(qs.ng, toCam)) : 1.0f);
                } else {
                    f = scatter(scene, qs, toCam, qs.wo, TransportMode::Importance);
                }
                if (isBlack(f)) continue;
                Connection conn = connectVertices(scene, qs, camera[0], stats);
                if (isBlack(conn.T)) continue;
                float cosCam = dot(-toCam, cam.forward);
                Spectrum value = qs.beta * f * conn.T * (cc.We * cosCam / (cc.dist * cc.dist));
                if (isBlack(value)) continue;
                if (weighted) {
                    // The camera's walk would have made qs with the pinhole's direction density.
                    Scoped<double> a, b;
                    float pCam = cameraPdfDir(cam, -toCam, width, height);
                    a.set(&qs.pdfRev, solidAngleToArea(qs, toCam, pCam, cc.dist) * conn.freeFlightToA);
                    if (s > 1) {
                        PathVertex& qsm = light[s - 2];
                        b.set(&qsm.pdfRev, solidAngleToArea(qsm, qs.wo, vertexDirectionPdf(scene, qs, toCam, qs.wo, width, height),
                                                            qs.edgeDist) * qs.edgeRevFreeFlight);
                    }
                    weight = float(misWeight(scene, light, camera, s, 1, mis, ea, conn.crossed, lightMis, cameraMis));
                    if (options_.observer) options_.observer->onWeight(light, s, camera, 1, weight, ea);
                }
                if (std::isfinite(weight)) splats.splat(cc.fx, cc.fy, value * weight, width, height);
                }
                continue;
            } else if (s == 1) {
                // Next-event estimation: a fresh light sample connected to z(t−1), and the
                // equi-angular variant: z(t−1) placed on its ray towards the light's anchor.
                if (scene.lightDistribution().empty()) continue;
                float pick;
                int li = scene.lightDistribution().sample(uPick1, &pick);
                const Light& l = scene.lights()[li];
                Vec3 anchor;
                const PathVertex& zPrev = camera[t - 2];
                bool eaOn = anyEquiAngular && pt.edgeMedium && !zPrev.delta && equiAngularAnchor(scene, l, uLight1, &anchor);
                bool ffOn = freeFlightVariantOn(options_.connect, realPt, pt, eaOn);
                for (int variant = 0; variant < 2; ++variant) {
                const bool ea = variant == 1;
                if (ea ? !eaOn : !ffOn) continue;
                if (options_.onlyVariant >= 0 && variant != options_.onlyVariant) continue;
                Scoped<PathVertex> swap;
                if (ea) {
                    PathVertex v;
                    Vec3 prevFrom = towardsPrevious(camera, t - 2);
                    EquiAngularAim aim{true, anchor, &l, false};
                    if (!equiAngularVertex(scene, pt, zPrev, prevFrom, aim, mis, uEA, &v)) continue;
                    swap.set(&camera[t - 1], v);
                }
                Spectrum contrib(0.0f);
                float weight = 1.0f;
                LightSample ls;
                if (!sampleLight(scene, l, pt.p, uLight1, &ls) || isBlack(ls.Le)) continue;
                Spectrum f = scatter(scene, pt, pt.wo, ls.wi, TransportMode::Radiance);
                if (isBlack(f)) continue;
                Vec3 o = pt.isSurface() ? offsetOrigin(pt.p, pt.ng, ls.wi) : pt.p;
                // Stop just short of an emitting surface so it does not shadow itself.
                bool surfaceLight = l.kind == LightKind::Triangle || l.kind == LightKind::Sphere;
                float dist = surfaceLight ? ls.dist - rayEpsilon(ls.p) : ls.dist;
                Connection conn = connectPoints(scene, o, ls.wi, dist, mediaTowards(scene, pt, ls.wi), pt.isMedium(),
                                                false, lightTarget(scene, li), stats);
                if (isBlack(conn.T)) continue;
                contrib = pt.beta * f * ls.Le * conn.T / (pick * ls.pdf);
                if (weighted) {
                    // The sampled light vertex, with the light subpath's densities as stand-ins.
                    PathVertex y0;
                    y0.kind = VertexKind::Light;
                    y0.light = li;
                    y0.p = ls.p;
                    y0.deltaLight = ls.isDelta;
                    y0.media = scene.lightMedia(li);
                    if (l.kind == LightKind::Sphere) y0.ng = normalize(ls.p - l.position);
                    if (l.kind == LightKind::Triangle) {
                        const Mesh& mesh = scene.mesh(l.mesh);
                        const uint32_t* idx = &mesh.indices[3 * l.triangle];
                        y0.ng = normalize(cross(mesh.positions[idx[1]] - mesh.positions[idx[0]],
                                                mesh.positions[idx[2]] - mesh.positions[idx[0]]));
                        if (dot(y0.ng, -ls.wi) < 0) y0.ng = -y0.ng;
                    }
                    float pos, dir;
                    emissionPdf(scene, l, ls.p, y0.ng, -ls.wi, &pos, &dir);
                    bool directional = l.kind == LightKind::Directional;
                    y0.pdfFwd = directional ? pick : pick * pos;
                    float d = std::isinf(ls.dist) ? 1.0f : ls.dist;
                    y0.pdfRev = ls.isDelta ? 0.0f
                                           : solidAngleToArea(y0, ls.wi, vertexDirectionPdf(scene, pt, pt.wo, ls.wi, width, height), d) *
                                                 conn.freeFlightToB;
                    PathVertex* lightPath = &y0;
                    Scoped<double> a, b;
                    double ptRev = directional
                                      ? pos * (pt.isSurface() ? std::abs(dot(pt.ng, ls.wi)) : 1.0f) * conn.freeFlightToA
                                      : solidAngleToArea(pt, ls.wi, dir, d) * conn.freeFlightToA;
                    a.set(&pt.pdfRev, ptRev);
                    if (t > 1) {
                        PathVertex& ptm = camera[t - 2];
                        b.set(&ptm.pdfRev, solidAngleToArea(ptm, pt.wo, vertexDirectionPdf(scene, pt, ls.wi, pt.wo, width, height),
                                                            pt.edgeDist) * pt.edgeRevFreeFlight);
                    }
                    weight = float(misWeight(scene, lightPath, camera, 1, t, mis, ea, conn.crossed, lightMis, cameraMis));
                    if (options_.observer) options_.observer->onWeight(lightPath, 1, camera, t, weight, ea);
                }
                if (!isBlack(contrib) && std::isfinite(weight)) L += contrib * weight;
                }
                continue;
            } else {
                // Two subpaths joined by a deterministic connection; with equi-angular
                // connections also z(t−1) moved along its ray towards y(s−1).
                PathVertex& qs = light[s - 1];
                if (!scatters(qs)) continue;
                const PathVertex& zPrev = camera[t - 2];
                bool eaOn = anyEquiAngular && pt.edgeMedium && !zPrev.delta;
                bool ffOn = freeFlightVariantOn(options_.connect, realPt, pt, eaOn);
                for (int variant = 0; variant < 2; ++variant) {
                const bool ea = variant == 1;
                if (ea ? !eaOn : !ffOn) continue;
                if (options_.onlyVariant >= 0 && variant != options_.onlyVariant) continue;
                Scoped<PathVertex> swap;
                if (ea) {
                    PathVertex v;
                    Vec3 prevFrom = towardsPrevious(camera, t - 2);
                    if (!equiAngularVertex(scene, pt, zPrev, prevFrom, equiAngularAim(scene, qs, false), mis, uEA, &v)) continue;
                    swap.set(&camera[t - 1], v);
                }
                Spectrum contrib(0.0f);
                float weight = 1.0f;
                Vec3 d = qs.p - pt.p;
                float dist = length(d);
                if (!(dist > 0)) continue;
                Vec3 w = d / dist;  // from the camera side to the light side
                Spectrum fz = scatter(scene, pt, pt.wo, w, TransportMode::Radiance);
                Spectrum fy = scatter(scene, qs, -w, qs.wo, TransportMode::Importance);
                if (isBlack(fz) || isBlack(fy)) continue;
                Connection conn = connectVertices(scene, pt, qs, stats);
                if (isBlack(conn.T)) continue;
                contrib = pt.beta * fz * conn.T * fy * qs.beta / (dist * dist);
                if (weighted) {
                    Scoped<double> a, b, c, e;
                    a.set(&pt.pdfRev, solidAngleToArea(pt, -w, vertexDirectionPdf(scene, qs, qs.wo, -w, width, height), dist) *
                                          conn.freeFlightToA);
                    b.set(&qs.pdfRev, solidAngleToArea(qs, w, vertexDirectionPdf(scene, pt, pt.wo, w, width, height), dist) *
                                          conn.freeFlightToB);
                    PathVertex& ptm = camera[t - 2];
                    c.set(&ptm.pdfRev, solidAngleToArea(ptm, pt.wo, vertexDirectionPdf(scene, pt, w, pt.wo, width, height),
                                                        pt.edgeDist) * pt.edgeRevFreeFlight);
                    PathVertex& qsm = light[s - 2];
                    e.set(&qsm.pdfRev, solidAngleToArea(qsm, qs.wo, vertexDirectionPdf(scene, qs, -w, qs.wo, width, height),
                                                        qs.edgeDist) * qs.edgeRevFreeFlight);
                    weight = float(misWeight(scene, light, camera, s, t, mis, ea, conn.crossed, lightMis, cameraMis));
                    if (options_.observer) options_.observer->onWeight(light, s, camera, t, weight, ea);
                }
                if (!isBlack(contrib) && std::isfinite(weight)) L += contrib * weight;
                }
                continue;
            }
            if (!isBlack(contrib) && std::isfinite(weight)) L += contrib * weight;
        }
    }
    return L;
}

}  // namespace brume
