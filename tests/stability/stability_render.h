// Renders a scene in independent batches through the renderer (so that bidirectional splats
// are included) and keeps what the stability checks need: per-block batch means with standard
// errors, every batch's pixel values, and the count of samples the renderer dropped for being
// NaN or infinite (dropped samples never reach the film, so a finite image alone proves nothing).
#pragma once
#include <chrono>
#include <cmath>
#include <vector>

#include "brume/film/film.h"
#include "brume/render/renderer.h"
#include "support/pixel_estimates.h"

namespace brume::test {

struct StabilityRun {
    int width = 0, height = 0, block = 1, batches = 0, sppPerBatch = 0;
    std::vector<PixelEstimate> blocks;  // block × block pixel averages, row-major over blocks
    std::vector<double> batchPixels;    // [batch · width · height + pixel]: mean of the channels
    uint64_t nonFinite = 0;             // samples and splats the renderer dropped
    bool filmFinite = true;             // every pixel of every batch finite
    double seconds = 0;
    int blocksX() const { return width / block; }
    double pixel(int batch, int i) const { return batchPixels[size_t(batch) * width * height + i]; }
};

// One thread per render: the suite runs its cases in parallel (ctest -j).
inline StabilityRun renderBatches(const Scene& scene, Integrator& integrator, int width, int height,
                                  int sppPerBatch, int batches, uint64_t seed, int block) {
    StabilityRun run;
    run.width = width, run.height = height, run.block = block, run.batches = batches, run.sppPerBatch = sppPerBatch;
    const int bw = width / block, bh = height / block;
    run.blocks.resize(size_t(bw) * bh);
    run.batchPixels.resize(size_t(batches) * width * height);
    std::vector<Spectrum> acc(run.blocks.size());
    auto start = std::chrono::steady_clock::now();
    for (int b = 0; b < batches; ++b) {
        Film film(width, height);
        RenderOptions o;
        o.width = width;
        o.height = height;
        o.spp = sppPerBatch;
        o.seed = seed * 1000003ULL + uint64_t(b);
        o.threads = 1;
        run.nonFinite += render(scene, integrator, o, film).nonFinite;
        std::fill(acc.begin(), acc.end(), Spectrum(0.0f));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                Spectrum v = film.pixel(x, y);
                if (!isFinite(v)) run.filmFinite = false;
                run.batchPixels[size_t(b) * width * height + size_t(y) * width + x] = (double(v.x) + v.y + v.z) / 3.0;
                if (x < bw * block && y < bh * block) acc[size_t(y / block) * bw + x / block] += v;
            }
        for (size_t i = 0; i < acc.size(); ++i) {
            Spectrum v = acc[i] / float(block * block);
            for (int c = 0; c < 3; ++c) {
                run.blocks[i].sum[c] += v[c];
                run.blocks[i].sum2[c] += double(v[c]) * v[c];
            }
            ++run.blocks[i].n;
        }
    }
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return run;
}

}  // namespace brume::test
