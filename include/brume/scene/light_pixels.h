// The pixels that hold the image of a point or spot light inside a scattering medium, and
// where in the pixel the image lies: there the renderer draws the film position in proportion
// to 1/|x − c| (sampling/inverse_distance.h says why; render/renderer.cpp draws it). A light
// seen only through glass counts as hidden (the occlusion query stops at the glass).
#pragma once
#include <cstdint>
#include <vector>

namespace brume {

class Scene;

struct LightPixel {
    uint32_t pixel = 0;    // y · width + x
    float cx = 0, cy = 0;  // the light's image in the pixel's coordinates (its square is [0, 1]²)
};

class LightPixels {
public:
    // Every point or spot light with a scattering medium around it that projects onto the film
    // [0, width) × [0, height) (in front of the camera), unless a surface hides it from the
    // camera: the pixel of its image and the eight around it; where two lights share a pixel,
    // the first.
    LightPixels(const Scene& scene, int width, int height);
    const LightPixel* find(uint32_t pixel) const;  // null when no light's image lies there
    // The density of film position (fx, fy) (in pixels) relative to uniform, as the renderer
    // draws it: 1/(Z·|x − c|) in these pixels, 1 elsewhere. For weights that read the camera's
    // density of a point (one_event_split.h).
    float density(float fx, float fy) const;
    bool empty() const { return pixels_.empty(); }
    bool madeFor(const Scene* scene, int width, int height) const {
        return scene == scene_ && width == width_ && height == height_;
    }

private:
    const Scene* scene_;
    int width_, height_;
    std::vector<LightPixel> pixels_;  // by pixel
};

}  // namespace brume
