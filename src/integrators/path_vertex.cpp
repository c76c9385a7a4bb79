#include "brume/integrators/path_vertex.h"

#include "brume/guiding/guided_phase.h"
#include "brume/sampling/hg.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"

namespace brume {

float vertexDirectionPdf(const Scene& scene, const PathVertex& v, Vec3 wFrom, Vec3 wTo, int width, int height,
                         const GuidingField* guide) {
    switch (v.kind) {
    case VertexKind::Camera: return cameraPdfDir(scene.camera(), wTo, width, height);
    case VertexKind::Light: {
        float pos, dir;
        emissionPdf(scene, scene.lights()[v.light], v.p, v.ng, wTo, &pos, &dir);
        return dir;
    }
    case VertexKind::Medium:
        return guide ? GuidedPhase::at(guide, v.p, -wFrom, v.medium->g).pdf(wTo) : hgPhase(dot(-wFrom, wTo), v.medium->g);
    case VertexKind::Surface: {
        if (v.delta || v.mesh < 0) return 0.0f;
        const Bsdf bsdf = vertexBsdf(scene, v);
        const float pdf = bsdf.pdf(wFrom, wTo);
        const GuidingCell* cell = guide && !bsdf.isSpecular() ? guide->lookup(v.p) : nullptr;
        return cell && cell->surfaceShare > 0 ? cell->surfaceShare * cell->surface.pdf(wTo) + (1.0f - cell->surfaceShare) * pdf
                                              : pdf;
    }
    }
    return 0.0f;
}

}  // namespace brume
