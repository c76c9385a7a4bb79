#include "brume/math/fixed_sum.h"

#include <cmath>
#include <cstdint>

namespace brume {

// v = M·2^(e−24) with M the 24-bit mantissa (frexp: v = m·2^e, m in [0.5, 1)); in units of
// 2^-64 that is M·2^(e+40): a left shift, or a right shift that truncates towards zero.
FixedSum toFixed(float v) {
    if (v == 0 || !std::isfinite(v)) return 0;
    int e;
    const float m = std::frexp(std::abs(v), &e);
    const FixedSum M = FixedSum(int64_t(std::ldexp(m, 24)));  // exact: m has 24 significant bits
    const int shift = e + 40;
    FixedSum q;
    if (shift >= 0)
        q = shift <= 102 ? M << shift : FixedSum(1) << 126;  // |v| ≥ 2^62: clamped
    else
        q = -shift < 64 ? M >> -shift : FixedSum(0);
    return v < 0 ? -q : q;
}

}  // namespace brume
