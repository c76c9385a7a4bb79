// Image accumulation. The renderer works in passes of one sample per pixel; the film keeps,
// per pixel, the sum of those samples in double RGB and reports their mean over the
// completed passes.
//
// Splats (contributions that land on arbitrary pixels, e.g. light tracing in a later
// bidirectional integrator) go to a separate buffer. To keep images independent of the
// thread count, splats are never added to the film concurrently: each work unit (one tile
// of one pass) records its splats in its own SplatList, and after the pass the renderer
// merges the lists in tile order. The set of splats a tile makes depends only on
// (seed, pixels of the tile, pass), so the summation order — and the image — is fixed.
// pixel() = (sum of samples + sum of splats) / passes.
#pragma once
#include <cstdint>
#include <vector>

#include "brume/integrators/splat_list.h"
#include "brume/math/vec3.h"

namespace brume {

class Film {
public:
    Film(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    // Number of completed passes (the divisor of pixel()).
    int passes() const { return passes_; }

    // Adds one sample to pixel (x, y). Distinct pixels may be added from different threads
    // at the same time; one pixel must not.
    void add(int x, int y, Spectrum value) {
        double* p = &sum_[3 * (size_t(y) * size_t(width_) + size_t(x))];
        p[0] += value.x;
        p[1] += value.y;
        p[2] += value.z;
    }
    // Adds one splat at pixel (x, y) (single-threaded; see the file comment).
    void splat(int x, int y, Spectrum value);
    // Adds a tile's splats, in their recorded order (single-threaded).
    void mergeSplats(const SplatList& splats);
    bool hasSplats() const { return !splat_.empty(); }

    // Marks the end of a pass: every pixel has received its sample (or had it dropped).
    void completePass() { ++passes_; }

    // Mean over the completed passes (black before the first one).
    Spectrum pixel(int x, int y) const;
    // The whole image as float RGB, row-major, top row first (what writeImage takes).
    std::vector<float> rgb() const;
    // Back to black, zero passes.
    void clear();

    // The raw state, for checkpoints: 3 sums per pixel of samples and of splats (the latter
    // empty until the first splat). restore() puts such a state back exactly (it throws
    // std::invalid_argument for negative passes or sizes that are not 3 per pixel; splat
    // sums may be empty).
    const std::vector<double>& sampleSums() const { return sum_; }
    const std::vector<double>& splatSums() const { return splat_; }
    void restore(int passes, std::vector<double> sampleSums, std::vector<double> splatSums);

private:
    int width_, height_;
    int passes_ = 0;
    std::vector<double> sum_;    // 3 per pixel
    std::vector<double> splat_;  // 3 per pixel; allocated on the first splat
};

}  // namespace brume
