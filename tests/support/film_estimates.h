// Per-pixel estimates with standard errors from K independent renders (batch means), for
// integrators that splat (bidirectional methods): a pixel's value then depends on samples
// taken for other pixels, so per-sample statistics are not available, batches are.
#pragma once
#include <algorithm>
#include <vector>

#include "brume/film/film.h"
#include "brume/render/renderer.h"
#include "support/pixel_estimates.h"

namespace brume::test {

// With block > 1, estimates are of block × block pixel averages (row-major over blocks).
// sampler: Sobol (the renderer's default) or Independent, whose batch means are near normal
// even at a few samples per pixel (Sobol's stratified light choice makes them take two
// values or so there).
inline std::vector<PixelEstimate> estimateFilm(const Scene& scene, Integrator& integrator, int width,
                                               int height, int sppPerBatch, int batches, uint64_t seed,
                                               int block = 1, SamplerKind sampler = SamplerKind::Sobol) {
    const int bw = width / block, bh = height / block;
    std::vector<PixelEstimate> px(size_t(bw) * bh);
    std::vector<Spectrum> acc(px.size());
    for (int b = 0; b < batches; ++b) {
        Film film(width, height);
        RenderOptions o;
        o.width = width;
        o.height = height;
        o.spp = sppPerBatch;
        o.seed = seed * 1000003ULL + uint64_t(b);
        o.threads = 2;
        o.sampler = sampler;
        render(scene, integrator, o, film);
        std::fill(acc.begin(), acc.end(), Spectrum(0.0f));
        for (int y = 0; y < bh * block; ++y)
            for (int x = 0; x < bw * block; ++x) acc[size_t(y / block) * bw + x / block] += film.pixel(x, y);
        for (size_t i = 0; i < px.size(); ++i) {
            Spectrum v = acc[i] / float(block * block);
            PixelEstimate& e = px[i];
            for (int c = 0; c < 3; ++c) {
                e.sum[c] += v[c];
                e.sum2[c] += double(v[c]) * v[c];
            }
            ++e.n;
        }
    }
    return px;
}

// The same for an integrator made for these renders alone.
inline std::vector<PixelEstimate> estimateFilm(const Scene& scene, Integrator&& integrator, int width, int height,
                                               int sppPerBatch, int batches, uint64_t seed, int block = 1,
                                               SamplerKind sampler = SamplerKind::Sobol) {
    return estimateFilm(scene, integrator, width, height, sppPerBatch, batches, seed, block, sampler);
}

}  // namespace brume::test
