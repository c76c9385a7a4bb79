// What both commands do before rendering: load the scene file, pick the image size.
#include <cmath>
#include <cstdio>

#include "brume/cli/commands.h"
#include "brume/scene/gltf_loader.h"

namespace brume::cli {

SceneDescription loadSceneDescription(const std::string& path, bool printWarnings) {
    SceneDescription desc = loadGltf(path);
    if (printWarnings)
        for (const std::string& w : desc.warnings) std::fprintf(stderr, "brume: warning: %s\n", w.c_str());
    return desc;
}

Resolution imageResolution(const Camera& camera, Resolution requested) {
    if (requested.width > 0) return requested;
    Resolution r{640, 480};
    float aspect = camera.aspectRatio;
    if (aspect > 0 && std::isfinite(aspect)) {
        double h = std::round(640.0 / double(aspect));
        r.height = h < 1 ? 1 : (h > 1e9 ? 1000000000 : int(h));
    }
    try {
        checkResolution("camera aspect ratio", r);
    } catch (const UsageError&) {
        char aspectText[32];
        std::snprintf(aspectText, sizeof aspectText, "%g", double(aspect));
        throw std::runtime_error(std::string("camera aspect ratio ") + aspectText + " gives a 640x" +
                                 std::to_string(r.height) + " image, beyond the limits; pass --res WxH");
    }
    return r;
}

}  // namespace brume::cli
