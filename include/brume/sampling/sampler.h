// Every random number a sample uses comes from a Sampler, dimension by dimension, so a
// low-discrepancy sampler can later replace this independent one. A stream is keyed by
// (seed, pixel, pass): the image does not depend on which thread renders which pixel.
#pragma once
#include <cstdint>

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
        uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = uint32_t(old >> 59u);
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

class Sampler {
public:
    Sampler(uint64_t seed, uint64_t pixel, uint64_t pass)
        : rng_(mixBits(seed ^ mixBits(pixel)), mixBits(pass ^ mixBits(seed + 0x5851F42D4C957F2DULL))) {}
    // Uniform in [0, 1): 24 random bits, so the result is never rounded up to 1.
    float next1D() { return float(rng_.next() >> 8) * 0x1p-24f; }
    Sample2 next2D() {
        float u = next1D();
        return {u, next1D()};
    }

private:
    Pcg32 rng_;
};

}  // namespace brume
