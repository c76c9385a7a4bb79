// Random numbers for one pixel sample, asked for by place: every sampling decision names the
// dimension it reads (integrators/sample_dimensions.h keeps the table), so the number a
// decision gets does not depend on how many numbers other decisions drew before it. That is
// what a low-discrepancy sampler needs. Two kinds behind one class:
//   Sobol (the renderer's default): padded, shuffled, Owen-scrambled 2D Sobol (sobol.h). The
//     sequence index is the pass; each dimension (a 1D decision) or pair of dimensions (a 2D
//     one) has its own index shuffle and scrambles, seeded by (seed, pixel, dimension), so
//     every decision's numbers over the passes of a pixel form a stratified (0, 2)-sequence
//     (a net at every power of two), independent of every other decision's and of the
//     neighbouring pixels'. Repeated draws of one decision (repeat > 0) are hashed.
//   Independent: a hash of (seed, pixel, pass, dimension, repeat): white noise, for
//     comparison and for tests that need independent samples.
// The image does not depend on which thread renders which pixel, and a light subpath does
// not depend on the camera subpath's length. (PCG32 streams serve the sequential draws of
// tests and tools.)
#pragma once
#include <cstdint>

#include "brume/sampling/sobol.h"

namespace brume {

// PCG32 (O'Neill 2014): 64-bit LCG state, xorshift-rotate output.
class Pcg32 {
public:
    Pcg32(uint64_t state, uint64_t stream) : inc_((stream << 1u) | 1u) {
        next();
        state_ += state;
        next();
    }
    uint32_t next() {
        uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        return output(old);
    }
    // The output permutation (XSH-RR) of a 64-bit state.
    static uint32_t output(uint64_t state) {
        uint32_t xorshifted = uint32_t(((state >> 18u) ^ state) >> 27u);
        uint32_t rot = uint32_t(state >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }

private:
    uint64_t state_ = 0;
    uint64_t inc_;
};

// SplitMix64 finaliser: decorrelates nearby keys before they seed a stream.
inline uint64_t mixBits(uint64_t v) {
    v += 0x9E3779B97F4A7C15ULL;
    v = (v ^ (v >> 30)) * 0xBF58476D1CE4E5B9ULL;
    v = (v ^ (v >> 27)) * 0x94D049BB133111EBULL;
    return v ^ (v >> 31);
}

struct Sample2 {
    float u, v;
};

// Uniform in [0, 1) from 32 random bits: 24 of them, so the result is never rounded up to 1.
inline float toUnitFloat(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }

// A sequential stream of uniform numbers (tests, tools, and anything that is not a pixel
// sample's decision).
class Rng {
public:
    Rng(uint64_t state, uint64_t stream) : pcg_(state, stream) {}
    float next1D() { return toUnitFloat(pcg_.next()); }
    Sample2 next2D() {
        float u = next1D();
        return {u, next1D()};
    }

private:
    Pcg32 pcg_;
};

enum class SamplerKind { Sobol, Independent };

class Sampler {
public:
    Sampler(uint64_t seed, uint64_t pixel, uint64_t pass, SamplerKind kind = SamplerKind::Independent)
        : Sampler(Keys{mixBits(seed ^ mixBits(pixel)), mixBits(pass ^ mixBits(seed + 0x5851F42D4C957F2DULL))}, pass,
                  kind, seed) {}

    // The sampler of one sequence for the whole image, at index pass·count + index: for
    // decisions whose outcome lands anywhere on the image rather than in this pixel (the
    // bidirectional tracer's light subpaths, which splat where they reach the camera). With
    // Sobol the `count` samples of a pass (index: the pixel, count: the pixels) are then
    // consecutive points of one (0, 2)-sequence in every decision, stratified over the pass
    // and over the passes, where one sequence per pixel leaves them independent across pixels.
    // Deterministic in (seed, pass, index). Indices wrap at 2^32 (640 × 480 pixels: after
    // 13981 passes), which costs stratification, never correctness.
    Sampler imageWide(uint64_t index, uint64_t count) const {
        return Sampler(seed_, kImageWidePixel, pass_ * count + index, kind_);
    }

    // The number at dimension `dim`. `repeat` > 0: the repeat-th further draw of a decision
    // that may draw a variable number of times (invisible-boundary pieces, tracking steps),
    // from a hashed stream seeded by its dimension; repeat 0 is the dimension itself.
    float get1D(uint32_t dim, uint32_t repeat = 0) const {
        if (kind_ == SamplerKind::Sobol && repeat == 0) {
            // owenScramble(sobolDimension0(i)) = reverse(LK(i)): two reversals fewer.
            const uint64_t h = sobolKey(dim);
            return toUnit(reverseBits(laineKarrasPermutation(sobolIndex(h), uint32_t(h >> 32))) >> 8);
        }
        return toUnit(hash(dim, repeat) >> 40);
    }
    // Dimensions dim and dim + 1 as one decision (one hash, or one Sobol pair).
    Sample2 get2D(uint32_t dim, uint32_t repeat = 0) const {
        if (kind_ == SamplerKind::Sobol && repeat == 0) {
            const uint64_t h = sobolKey(dim), h2 = mixBits(h);
            const uint32_t i = sobolIndex(h);
            return {toUnit(reverseBits(laineKarrasPermutation(i, uint32_t(h >> 32))) >> 8),
                    toUnit(owenScramble(sobolDimension1(i), uint32_t(h2)) >> 8)};
        }
        uint64_t h = hash(dim, repeat);
        return {toUnit(h >> 40), toUnit((h >> 8) & 0xFFFFFFu)};
    }

    SamplerKind kind() const { return kind_; }

    // A sequential stream of this pixel sample's own, apart from the dimensions above: for
    // tests and tools, never for an integrator's decisions.
    float next1D() { return sequential_.next1D(); }
    Sample2 next2D() { return sequential_.next2D(); }

private:
    struct Keys {
        uint64_t key, stream;  // of (seed, pixel) and of (seed, pass)
    };
    Sampler(Keys k, uint64_t pass, SamplerKind kind, uint64_t seed)
        : base_(mixBits(k.key ^ k.stream)), pixelKey_(k.key), passReversed_(reverseBits(uint32_t(pass))), kind_(kind),
          sequential_(k.key, k.stream), seed_(seed), pass_(pass) {}
    static constexpr uint64_t kImageWidePixel = ~0ULL;  // no pixel has this index

    // The (seed, pixel, pass) key is hashed once (constructor), here with the place a second
    // time (SplitMix64's finaliser): every key reaches the bits through the hash. (PCG32
    // streams that differ only in their increment start from states a fixed offset apart,
    // and their first outputs are correlated pass to pass.)
    uint64_t hash(uint32_t dim, uint32_t repeat) const {
        uint64_t d = uint64_t(dim) | (uint64_t(repeat) << 32);
        return mixBits(base_ ^ (d * 0xD1B54A32D192ED03ULL));
    }
    // Sobol: the seeds of a decision (the same for every pass of the pixel): the low half
    // shuffles the index, the high half scrambles the first coordinate.
    uint64_t sobolKey(uint32_t dim) const { return mixBits(pixelKey_ ^ (uint64_t(dim) * 0x9E6C63D0676A9A99ULL)); }
    // The pass shuffled: owenScramble(pass) with the pass's reversal done once.
    uint32_t sobolIndex(uint64_t key) const { return reverseBits(laineKarrasPermutation(passReversed_, uint32_t(key))); }
    static float toUnit(uint64_t bits24) { return float(bits24) * 0x1p-24f; }

    uint64_t base_;
    uint64_t pixelKey_;
    uint32_t passReversed_;
    SamplerKind kind_;
    Rng sequential_;
    uint64_t seed_, pass_;
};

}  // namespace brume
