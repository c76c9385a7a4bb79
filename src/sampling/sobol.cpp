#include "brume/sampling/sobol.h"

namespace brume {

namespace {

// Direction numbers of dimension 1 in 0.32 fixed point: v_1 = 1/2, v_k = v_(k−1) ⊕ v_(k−1)/2
// (m_k = 2 m_(k−1) ⊕ m_(k−1), see sobol.h); and, since x_i is linear in the bits of i, the
// XOR of the v of every bit of each byte value at each of the four byte positions: four
// lookups per point instead of one step per bit (a shuffled index has all 32 bits in use).
struct Dimension1Tables {
    uint32_t table[4][256];
    constexpr Dimension1Tables() : table{} {
        uint32_t v[32] = {};
        v[0] = 0x80000000u;
        for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        for (int b = 0; b < 4; ++b)
            for (int x = 0; x < 256; ++x) {
                uint32_t sum = 0;
                for (int k = 0; k < 8; ++k)
                    if (x & (1 << k)) sum ^= v[8 * b + k];
                table[b][x] = sum;
            }
    }
};
constexpr Dimension1Tables kDimension1;

}  // namespace

uint32_t sobolDimension1(uint32_t i) {
    return kDimension1.table[0][i & 0xFFu] ^ kDimension1.table[1][(i >> 8) & 0xFFu] ^
           kDimension1.table[2][(i >> 16) & 0xFFu] ^ kDimension1.table[3][i >> 24];
}

}  // namespace brume
