#include "brume/scene/light_pixels.h"

#include <algorithm>
#include <cmath>

#include "brume/sampling/inverse_distance.h"
#include "brume/scene/camera_importance.h"
#include "brume/scene/scene.h"

namespace brume {

LightPixels::LightPixels(const Scene& scene, int width, int height) : scene_(&scene), width_(width), height_(height) {
    if (width <= 0 || height <= 0) return;
    const auto& lights = scene.lights();
    for (size_t i = 0; i < lights.size(); ++i) {
        const Light& light = lights[i];
        if (light.kind != LightKind::Point && light.kind != LightKind::Spot) continue;
        const Medium* m = scene.medium(scene.lightMedia(int(i)).current());
        if (!m || isBlack(m->sigmaS)) continue;
        CameraConnection cc;
        if (!connectToCamera(scene.camera(), light.position, width, height, &cc)) continue;
        // A light hidden behind a surface has no singular pixel: the rays near its line of sight
        // stop before they pass it, and the weights would only add noise there. (With invisible
        // medium boundaries, which such a query would count as blockers, it is kept.)
        if (!scene.hasInvisibleBoundaries() &&
            scene.occluded(Ray{scene.camera().position, -cc.wi, cc.dist * (1.0f - 1e-4f)}))
            continue;
        // The pixel that holds the image, and its eight neighbours: next to the image a pixel's
        // integrand is still ∝ 1/|x − c|, c just outside it (a light imaged near a pixel's
        // corner is nearly singular in all four).
        const int px = int(std::floor(cc.fx)), py = int(std::floor(cc.fy));
        for (int y = py - 1; y <= py + 1; ++y)
            for (int x = px - 1; x <= px + 1; ++x) {
                if (x < 0 || y < 0 || x >= width || y >= height) continue;
                const LightPixel lp{uint32_t(y) * uint32_t(width) + uint32_t(x), cc.fx - float(x), cc.fy - float(y)};
                if (find(lp.pixel)) continue;
                pixels_.push_back(lp);
                std::sort(pixels_.begin(), pixels_.end(), [](const LightPixel& a, const LightPixel& b) { return a.pixel < b.pixel; });
            }
    }
}

const LightPixel* LightPixels::find(uint32_t pixel) const {
    auto it = std::lower_bound(pixels_.begin(), pixels_.end(), pixel,
                               [](const LightPixel& a, uint32_t p) { return a.pixel < p; });
    return it != pixels_.end() && it->pixel == pixel ? &*it : nullptr;
}

float LightPixels::density(float fx, float fy) const {
    if (pixels_.empty() || !(fx >= 0) || !(fy >= 0) || fx >= float(width_) || fy >= float(height_)) return 1.0f;
    const float px = std::floor(fx), py = std::floor(fy);
    const LightPixel* p = find(uint32_t(py) * uint32_t(width_) + uint32_t(px));
    return p ? inverseDistancePdf(p->cx, p->cy, fx - px, fy - py) : 1.0f;
}

}  // namespace brume
