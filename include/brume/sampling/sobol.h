// The two-dimensional Sobol sequence and hash-based Owen scrambling (Burley 2020, "Practical
// hash-based Owen scrambling"), the pieces of the low-discrepancy sampler (sampler.h).
//
// Sobol points in base 2 (Joe & Kuo's definition): x_i = ⊕_k i_k v_k over the bits i_k of
// the index, with direction numbers v_k = m_k / 2^k. The first dimension has v_k = 2^-k: the
// index's bits reversed (van der Corput). The second has the primitive polynomial x + 1 and
// m_1 = 1, so m_k = 2 m_(k−1) ⊕ m_(k−1): m = 1, 3, 5, 15, 17, 51, … Together they form a
// (0, 2)-sequence: every aligned block of 2^k consecutive points has exactly one point in
// each elementary interval of area 2^-k, [a 2^-j, (a+1) 2^-j) × [b 2^-(k−j), (b+1) 2^-(k−j)).
//
// Owen scrambling permutes the digits of a coordinate so that digit j's flip depends on the
// digits before it, at random: the net property survives, and each coordinate becomes
// uniform. With the bits reversed, "before" becomes "below", and any hash in which every bit
// depends only on the bits below it serves (Laine & Karras 2011's hash, with the constants of
// Vegdahl's improved variant). Applied to the index instead, the same
// scramble shuffles the order of the points: the first 2^k indices go to one aligned block
// of 2^k, so every power-of-two prefix is still a net. A different seed per pair of
// dimensions decorrelates the pairs ("padding").
#pragma once
#include <cstdint>

namespace brume {

inline uint32_t reverseBits(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}

// A bijection on 32 bits in which bit j of the result depends only on bits 0 … j of x
// (every step carries upwards only: x·even, +, x·odd), seeded.
inline uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Owen scrambling of a coordinate in 0.32 fixed point (bit 31 is the first binary digit).
inline uint32_t owenScramble(uint32_t x, uint32_t seed) {
    return reverseBits(laineKarrasPermutation(reverseBits(x), seed));
}

// Sobol dimension 0 (van der Corput) and dimension 1 of index i, in 0.32 fixed point.
inline uint32_t sobolDimension0(uint32_t i) { return reverseBits(i); }
uint32_t sobolDimension1(uint32_t i);

}  // namespace brume
