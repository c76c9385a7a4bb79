// Image accumulation. The renderer works in passes of one sample per pixel; the film keeps,
// per pixel, the sum of those samples and reports their mean over the completed passes.
//
// The sums are exact (math/fixed_sum.h: 128-bit fixed point, whose addition is associative).
// So the image does not depend on the order in which passes, tiles, threads or MPI ranks add
// their samples: passes can be rendered anywhere and their sums combined in any order, to the
// same bits; and passes summed elsewhere the same way can be taken out again (rgbWithout).
//
// Splats (contributions that land on arbitrary pixels, e.g. light tracing in the
// bidirectional integrator) go to the same sums. They are still never added concurrently:
// each work unit (one tile of one pass) records its splats in its own SplatList, and after
// the pass the renderer merges the lists.
// pixel() = sum / passes.
//
// Adaptive sampling (film/pixel_noise.h) stops pixels one by one: a film that tracks noise
// (trackNoise()) also keeps, per pixel, how many passes it took part in and the exact sums of
// the squares of its values per pass (its sample plus that pass's splats on it), and its
// pixel() is sum / that count. A film that does not track noise keeps neither.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "brume/integrators/splat_list.h"
#include "brume/math/fixed_sum.h"
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
        Sum* p = &sum_[3 * (size_t(y) * size_t(width_) + size_t(x))];
        p[0] += toFixed(value.x);
        p[1] += toFixed(value.y);
        p[2] += toFixed(value.z);
    }
    // Adds one splat at pixel (x, y) (single-threaded; see the file comment).
    void splat(int x, int y, Spectrum value);
    // Adds a tile's splats (single-threaded).
    void mergeSplats(const SplatList& splats);
    // Whether any splat has been added (a checkpoint records it).
    bool hasSplats() const { return hasSplats_; }

    // Marks the end of a pass: every pixel has received its sample (or had it dropped).
    void completePass() { ++passes_; }

    // Noise tracking (see the file comment). trackNoise() on a film without passes starts it;
    // on one with passes it is a std::logic_error (their squares are gone).
    void trackNoise();
    bool tracksNoise() const { return !samples_.empty(); }
    // With noise tracked: pixel i (= y·width + x) took part in the pass in flight, whose
    // value there (sample and splats) was `value`: counts it and adds its squares. Call it
    // once per taking part pixel per pass (single-threaded), with add()/splat() as usual.
    void addPassValue(size_t i, Spectrum value);
    // The passes pixel i took part in (passes() without noise tracking).
    int samples(size_t i) const { return samples_.empty() ? passes_ : samples_[i]; }
    // The exact sums of the squares of its values per pass, 3 per pixel (empty without noise
    // tracking).
    const std::vector<FixedSum>& squares() const { return squares_; }
    const std::vector<int32_t>& sampleCounts() const { return samples_; }

    // Mean over the completed passes (black before the first one).
    Spectrum pixel(int x, int y) const;
    // The whole image as float RGB, row-major, top row first (what writeImage takes).
    std::vector<float> rgb() const;
    // The mean over the completed passes but `passes` of them, whose exact sums are `sums`
    // (3 per pixel, as sums()); rgb() if that leaves none or the sums do not fit.
    std::vector<float> rgbWithout(int passes, const std::vector<FixedSum>& sums) const;
    // The same where `leaveOut(n)` holds for the n passes a pixel keeps without them (a film
    // that tracks noise: pixels that stopped early keep fewer), the plain mean elsewhere.
    std::vector<float> rgbWithout(int passes, const std::vector<FixedSum>& sums,
                                  const std::function<bool(int)>& leaveOut) const;
    // Back to black, zero passes.
    void clear();

    // The exact sums (see the file comment), 3 per pixel, row-major, top row first.
    typedef FixedSum Sum;  // toFixed, fromFixed: math/fixed_sum.h

    // The raw state, for checkpoints and for combining renders of disjoint passes (MPI
    // ranks): the sums, the pass count and whether there were splats. restore() puts such a
    // state back exactly (it throws std::invalid_argument for a negative pass count or sums
    // that are not 3 per pixel). With noise tracking also the counts and squares (both
    // empty: none; else one count in [0, passes] per pixel and 3 squares per pixel).
    const std::vector<Sum>& sums() const { return sum_; }
    void restore(int passes, std::vector<Sum> sums, bool hasSplats, std::vector<int32_t> samples = {},
                 std::vector<Sum> squares = {});

private:
    int width_, height_;
    int passes_ = 0;
    std::vector<Sum> sum_;  // 3 per pixel
    bool hasSplats_ = false;
    std::vector<int32_t> samples_;  // noise tracking: passes per pixel
    std::vector<Sum> squares_;      // and their squares, 3 per pixel
};

}  // namespace brume
