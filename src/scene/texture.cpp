#include "brume/scene/texture.h"

namespace brume {

Spectrum Texture::lookup(float u, float v) const {
    if (texels.empty()) return Spectrum(1.0f);
    // Texel centres sit at half-integer coordinates.
    float x = u * float(width) - 0.5f, y = v * float(height) - 0.5f;
    float fx = std::floor(x), fy = std::floor(y);
    float ax = x - fx, ay = y - fy;
    auto wrap = [](long i, int n) { long r = i % n; return int(r < 0 ? r + n : r); };
    int x0 = wrap(long(fx), width), x1 = wrap(long(fx) + 1, width);
    int y0 = wrap(long(fy), height), y1 = wrap(long(fy) + 1, height);
    auto at = [&](int xi, int yi) { return texels[size_t(yi) * width + xi]; };
    return (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) + (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
}

Spectrum Texture::average() const {
    if (texels.empty()) return Spectrum(1.0f);
    Spectrum sum(0.0f);
    for (const Spectrum& t : texels) sum += t;
    return sum / float(texels.size());
}

}  // namespace brume
