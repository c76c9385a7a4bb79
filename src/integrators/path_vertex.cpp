#include "brume/integrators/path_vertex.h"

#include "brume/sampling/hg.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/light_emission.h"

namespace brume {

float vertexDirectionPdf(const Scene& scene, const PathVertex& v, Vec3 wFrom, Vec3 wTo, int width, int height) {
    switch (v.kind) {
    case VertexKind::Camera: return cameraPdfDir(scene.camera(), wTo, width, height);
    case VertexKind::Light: {
        float pos, dir;
        emissionPdf(scene, scene.lights()[v.light], v.p, v.ng, wTo, &pos, &dir);
        return dir;
    }
    case VertexKind::Medium: return hgPhase(dot(-wFrom, wTo), v.medium->g);
    case VertexKind::Surface: return v.delta || v.mesh < 0 ? 0.0f : vertexBsdf(scene, v).pdf(wFrom, wTo);
    }
    return 0.0f;
}

}  // namespace brume
