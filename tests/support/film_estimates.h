// Per-pixel estimates with standard errors from K independent renders (batch means), for
// integrators that splat (bidirectional methods): a pixel's value then depends on samples
// taken for other pixels, so per-sample statistics are not available, batches are.
#pragma once
#include <vector>

#include "brume/render/film.h"
#include "brume/render/renderer.h"
#include "support/pixel_estimates.h"

namespace brume::test {

inline std::vector<PixelEstimate> estimateFilm(const Scene& scene, const Integrator& integrator, int width,
                                               int height, int sppPerBatch, int batches, uint64_t seed) {
    std::vector<PixelEstimate> px(size_t(width) * height);
    for (int b = 0; b < batches; ++b) {
        Film film(width, height);
        RenderOptions o;
        o.width = width;
        o.height = height;
        o.spp = sppPerBatch;
        o.seed = seed * 1000003ULL + uint64_t(b);
        o.threads = 2;
        render(scene, integrator, o, film);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                Spectrum v = film.pixel(x, y);
                PixelEstimate& e = px[size_t(y) * width + x];
                for (int c = 0; c < 3; ++c) {
                    e.sum[c] += v[c];
                    e.sum2[c] += double(v[c]) * v[c];
                }
                ++e.n;
            }
    }
    return px;
}

}  // namespace brume::test
