#include "brume/sampling/sobol.h"

namespace brume {

namespace {

// Direction numbers of dimension 1 in 0.32 fixed point: v_1 = 1/2, v_k = v_(k−1) ⊕ v_(k−1)/2
// (m_k = 2 m_(k−1) ⊕ m_(k−1), see sobol.h).
struct Directions {
    uint32_t v[32];
    constexpr Directions() : v{} {
        v[0] = 0x80000000u;
        for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    }
};
constexpr Directions kDimension1;

}  // namespace

uint32_t sobolDimension1(uint32_t i) {
    uint32_t x = 0;
    for (int k = 0; i; ++k, i >>= 1)
        if (i & 1u) x ^= kDimension1.v[k];
    return x;
}

}  // namespace brume
