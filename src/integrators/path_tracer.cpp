#include "brume/integrators/path_tracer.h"

#include "brume/integrators/mis.h"
#include "brume/integrators/visibility.h"
#include "brume/sampling/free_flight.h"
#include "brume/sampling/hg.h"
#include "brume/scene/bsdf.h"
#include "brume/scene/light_sampling.h"

namespace brume {

namespace {

// A scattering vertex as next-event estimation sees it: a surface with a BSDF, or a medium
// point with a phase function.
struct Vertex {
    Vec3 p;
    Vec3 wo;                      // towards the previous vertex
    const Bsdf* bsdf = nullptr;   // surface vertex
    Vec3 ng;                      // surface vertex: geometric normal
    const Medium* medium = nullptr;  // medium vertex (bsdf == nullptr)

    // f·|cos| (surface) or phase (medium) for the continuation wi, and its sampling density.
    Spectrum eval(Vec3 wi, float* pdf) const {
        if (bsdf) {
            *pdf = bsdf->pdf(wo, wi);
            return bsdf->eval(wo, wi);
        }
        float p = hgPhase(dot(-wo, wi), medium->g);
        *pdf = p;
        return Spectrum(p);
    }
};

// Next-event estimation: one light picked by power, one point on it, MIS-weighted against
// the BSDF/phase sampling that could have found the same point (power heuristic).
Spectrum sampleDirect(const Scene& scene, const Vertex& v, const MediumStack& media, Sampler& sampler,
                      PathStats& stats) {
    float uPick = sampler.next1D();
    Sample2 uLight = sampler.next2D();
    if (scene.lightDistribution().empty()) return Spectrum(0.0f);
    float pickProb;
    int li = scene.lightDistribution().sample(uPick, &pickProb);
    const Light& light = scene.lights()[li];
    LightSample ls;
    if (!sampleLight(scene, light, v.p, uLight, &ls) || isBlack(ls.Le)) return Spectrum(0.0f);
    float scatterPdf;
    Spectrum f = v.eval(ls.wi, &scatterPdf);
    if (isBlack(f)) return Spectrum(0.0f);
    Vec3 o = v.bsdf ? offsetOrigin(v.p, v.ng, ls.wi) : v.p;
    // Stop short of the light's own surface so that it does not shadow itself.
    float dist = std::isinf(ls.dist) ? ls.dist : ls.dist * (1.0f - 1e-4f) - rayEpsilon(ls.p);
    Spectrum T = transmittanceAlong(scene, o, ls.wi, dist, media, li, stats);
    if (isBlack(T)) return Spectrum(0.0f);
    float lightPdfTotal = pickProb * ls.pdf;
    float w = ls.isDelta ? 1.0f : powerHeuristic(lightPdfTotal, scatterPdf);
    return f * ls.Le * T * (w / lightPdfTotal);
}

}  // namespace

Spectrum PathTracer::sample(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                            PathStats& stats) const {
    const bool nee = options_.nextEventEstimation;
    Ray ray = scene.camera().generateRay(fx, fy, width, height);
    MediumStack media = scene.cameraMedia();
    Spectrum L(0.0f), beta(1.0f);
    int depth = 0;                 // scattering events so far
    bool specularBounce = true;    // the last direction came from a delta distribution (or the camera)
    float prevPdf = 0;             // solid-angle density of the last sampled direction
    Vec3 prevP = ray.o;

    for (int guard = 0; guard < 100000; ++guard) {
        ++stats.rays;
        SurfaceHit hit = scene.intersect(ray);
        float tSurface = hit.valid() ? hit.t : kInfinity;

        // Free-flight sampling up to the surface. Weight = T·σs/pdf_scatter or T/pdf_pass,
        // both pdfs averaged over the colour channels (see free_flight.h).
        if (const Medium* m = scene.medium(media.current())) {
            Spectrum sigmaT = m->sigmaT();
            float t = sampleFreeFlight(sigmaT, sampler.next1D());
            if (t < tSurface) {
                beta *= transmittance(sigmaT, t) * m->sigmaS / freeFlightPdfScatter(sigmaT, t);
                if (++depth > options_.maxDepth && options_.maxDepth >= 0) break;
                Vertex v;
                v.p = ray.at(t);
                v.wo = -ray.d;
                v.medium = m;
                if (nee) L += beta * sampleDirect(scene, v, media, sampler, stats);
                Vec3 wi = sampleHG(ray.d, m->g, sampler.next2D());  // phase/pdf = 1
                prevPdf = hgPhase(dot(ray.d, wi), m->g);
                prevP = v.p;
                specularBounce = false;
                ray = Ray{v.p, wi, kInfinity};
                if (!isFinite(beta) || isBlack(beta)) break;
                goto roulette;
            }
            if (std::isinf(tSurface)) break;  // flew to infinity through a medium: T = 0
            beta *= transmittance(sigmaT, tSurface) / freeFlightPdfPass(sigmaT, tSurface);
        }
        if (!hit.valid()) break;

        {
            // Emission reached by the camera ray or by BSDF/phase sampling.
            Spectrum Le = scene.emission(hit, -ray.d);
            if (!isBlack(Le)) {
                float w = 1.0f;
                if (nee && !specularBounce) {
                    int li = hit.sphereLight >= 0 ? hit.sphereLight : scene.triangleLight(hit.mesh, hit.triangle);
                    float pLight = scene.lightDistribution().pmf(li) *
                                   lightPdf(scene, scene.lights()[li], prevP, hit.p, hit.ng);
                    w = powerHeuristic(prevPdf, pLight);
                }
                L += beta * Le * w;
            }
            if (hit.sphereLight >= 0) break;  // sphere lights are opaque emitters

            const Mesh& mesh = scene.mesh(hit.mesh);
            const Material& mat = scene.material(hit.mesh);
            if (mat.kind == MaterialKind::Invisible) {  // index-matched boundary: pass straight on
                if (mesh.interiorMedium >= 0) media.toggle(mesh.interiorMedium);
                ray = Ray{hit.p + ray.d * rayEpsilon(hit.p), ray.d, kInfinity};
                continue;
            }
            if (++depth > options_.maxDepth && options_.maxDepth >= 0) break;

            Spectrum baseColor = mat.baseColor;
            if (mat.baseColorTexture >= 0) baseColor *= scene.desc().textures[mat.baseColorTexture].lookup(hit.u, hit.v);
            Bsdf bsdf(mat, baseColor, hit.ng, hit.ns);
            Vertex v;
            v.p = hit.p;
            v.wo = -ray.d;
            v.bsdf = &bsdf;
            v.ng = hit.ng;
            if (nee && !bsdf.isSpecular()) L += beta * sampleDirect(scene, v, media, sampler, stats);

            float uLobe = sampler.next1D();
            BsdfSample bs;
            if (!bsdf.sample(v.wo, uLobe, sampler.next2D(), &bs)) break;
            beta *= bs.weight;
            if (bs.transmitted && mesh.interiorMedium >= 0) media.toggle(mesh.interiorMedium);
            specularBounce = bs.specular;
            prevPdf = bs.pdf;
            prevP = hit.p;
            ray = Ray{offsetOrigin(hit.p, hit.ng, bs.wi), bs.wi, kInfinity};
            if (!isFinite(beta) || isBlack(beta)) break;
        }

    roulette:
        // Russian roulette after three events: survive with probability min(0.95, max β).
        if (depth >= 3) {
            float survive = std::min(0.95f, maxComponent(beta));
            if (sampler.next1D() >= survive) break;
            beta /= survive;
        }
    }
    return L;
}

}  // namespace brume
