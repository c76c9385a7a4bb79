// An RGB texture in linear radiometric values (the loader decodes sRGB), sampled bilinearly
// with repeat wrapping, glTF's default. (u, v) = (0, 0) is the image's top-left corner.
#pragma once
#include <vector>
#include "brume/math/vec3.h"

namespace brume {

struct Texture {
    int width = 0, height = 0;
    std::vector<Spectrum> texels;  // row-major, row 0 at the top
    Spectrum lookup(float u, float v) const;
    Spectrum average() const;
};

}  // namespace brume
