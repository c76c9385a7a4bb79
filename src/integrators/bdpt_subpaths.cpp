#include "brume/integrators/bdpt_subpaths.h"

#include "brume/integrators/light_numbers.h"
#include "brume/integrators/random_walk.h"
#include "brume/integrators/sample_dimensions.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"
#include "brume/scene/light_geometry.h"

namespace brume {

PathVertex makeLightVertex(const Scene& scene, int li, float pick, Vec3 p, Vec3 n, float pdfPos) {
    const Light& light = scene.lights()[li];
    PathVertex y0;
    y0.kind = VertexKind::Light;
    y0.light = li;
    y0.p = p;
    y0.ng = y0.ns = n;
    y0.deltaLight = light.isDelta();
    // A double-sided planar emitter may emit from its back, where other media may be.
    bool back = false;
    if (light.isPlanar()) {
        y0.mesh = light.mesh;
        y0.triangle = light.triangle;
        lightSurfaceUv(scene, light, p, &y0.u, &y0.v);
        back = dot(n, light.shape.edgeCross()) < 0;
    }
    y0.media = scene.lightMedia(li, back);
    y0.pdfFwd = Channels(light.atInfinity() ? pick : pick * pdfPos);
    y0.beta = Spectrum(1.0f / float(y0.pdfFwd[0]));
    return y0;
}

namespace {

// z0, the pinhole, and the camera ray through film position (fx, fy).
Ray startCameraSubpath(const Scene& scene, float fx, float fy, int width, int height, PathVertex* path) {
    const Camera& cam = scene.camera();
    const Ray ray = cam.generateRay(fx, fy, width, height);
    PathVertex& z0 = path[0];
    z0 = PathVertex{};
    z0.kind = VertexKind::Camera;
    z0.p = ray.o;
    z0.ng = cam.forward;
    z0.media = scene.cameraMedia();
    z0.beta = Spectrum(1.0f);  // We·cosθ / p_dir = 1 for the pinhole
    return ray;
}

}  // namespace

int cameraVertexOnly(const Scene& scene, float fx, float fy, int width, int height, PathVertex* path) {
    startCameraSubpath(scene, fx, fy, width, height, path);
    return 1;
}

int traceCameraSubpath(const Scene& scene, float fx, float fy, int width, int height, int maxScatter, int passFrom,
                       int passFirstAt, int hero, const Sampler& sampler, PathVertex* path, PathStats& stats,
                       const GuidingField* guide, float pixelValue, MisHeuristic heuristic, int volumeLightsUpTo,
                       std::vector<CrossingVertex>* crossings) {
    const Camera& cam = scene.camera();
    const Ray ray = startCameraSubpath(scene, fx, fy, width, height, path);
    WalkStart start{leaving(ray.o, Vec3(0.0f), ray.d), scene.cameraMedia(), Spectrum(1.0f),
                    cameraPdfDir(cam, ray.d, width, height), width, height, dim::Side::Camera, hero, passFrom, passFirstAt,
                    guide, pixelValue, heuristic, volumeLightsUpTo, crossings};
    return randomWalk(scene, start, TransportMode::Radiance, maxScatter, sampler, path, kMaxSubpathVertices, stats);
}

int traceLightSubpath(const Scene& scene, int maxScatter, int hero, const Sampler& sampler, PathVertex* path,
                      PathStats& stats, const GuidingField* cameraGuide) {
    if (scene.lightDistribution().empty()) return 0;
    float pick;
    int li = pickLight(scene, sampler, dim::kLightStart, 0, &pick);
    const Light& light = scene.lights()[li];
    const bool directional = light.atInfinity();
    if (directional) {
        // In an infinite ambient medium a directional light reaches nothing (as in pt).
        const Medium* amb = scene.medium(scene.desc().ambientMedium);
        if (amb && maxComponent(amb->sigmaT()) > 0) return 0;
    }
    EmissionSample es;
    if (!sampleEmission(scene, light, sampler.get2D(dim::kLightStart + dim::kPosition),
                        sampler.get2D(dim::kLightStart + dim::kEmitDir), &es) ||
        isBlack(es.Le) || !(es.pdfPos > 0) || !(es.pdfDir > 0))
        return 0;
    PathVertex& y0 = path[0];
    y0 = makeLightVertex(scene, li, pick, es.p, es.n, es.pdfPos);
    y0.wo = es.d;
    float cosLight = dot(es.n, es.n) > 0 ? std::abs(dot(es.n, es.d)) : 1.0f;
    Spectrum beta = es.Le * (cosLight / (pick * es.pdfPos * es.pdfDir));
    WalkStart start{leaving(es.p, es.n, es.d), y0.media, beta, directional ? 1.0f : es.pdfDir, 0, 0, dim::Side::Light, hero};
    start.guide = cameraGuide;  // (for the reverse densities alone)
    int n = randomWalk(scene, start, TransportMode::Importance, maxScatter, sampler, path, kMaxSubpathVertices, stats);
    if (directional && n > 1) {
        // Parallel rays: the disk's area density projects onto y1 with |cos| and no 1/d².
        PathVertex& y1 = path[1];
        y1.pdfFwd = double(es.pdfPos * (y1.isSurface() ? std::abs(dot(y1.ng, y1.wo)) : 1.0f)) * y1.edgeFwdFreeFlight;
    }
    return n;
}

}  // namespace brume
