// atan in float for arguments ≥ 0 by a polynomial (Abramowitz & Stegun 4.4.49, |error| ≤ 2e-8
// on [0, 1]), with atan(x) = π/2 − atan(1/x) above 1. For quantities that only need to be a
// fixed, smooth function of their inputs (the stand-in densities of the bidirectional
// weights), at a fraction of libm's double atan.
#pragma once

namespace brume {

// atan(x) for 0 ≤ x ≤ 1.
inline float atanUnit(float x) {
    const float z = x * x;
    float p = 0.0028662257f;
    p = p * z - 0.0161657367f;
    p = p * z + 0.0429096138f;
    p = p * z - 0.0752896400f;
    p = p * z + 0.1065626393f;
    p = p * z - 0.1420889944f;
    p = p * z + 0.1999355085f;
    p = p * z - 0.3333314528f;
    return x + x * z * p;
}

// π/2 + atan(x) for any x: the angle an unbounded ray [0, ∞) subtends from a point at signed
// offset x (in units of its distance D) along it. For x < 0 it is atan(1/|x|), kept accurate
// where it is small.
inline float halfPiPlusAtan(float x) {
    constexpr float kHalfPi = 1.57079632679f;
    if (x >= 0) return x <= 1 ? kHalfPi + atanUnit(x) : 2 * kHalfPi - atanUnit(1 / x);
    return x >= -1 ? kHalfPi - atanUnit(-x) : atanUnit(-1 / x);
}

// atan2(y, x) for y ≥ 0, in [0, π] (0 when both are 0).
inline float atan2NonNegative(float y, float x) {
    constexpr float kPi = 3.14159265359f, kHalfPi = 1.57079632679f;
    const float ax = x < 0 ? -x : x;
    if (ax >= y) {
        if (ax == 0) return 0.0f;
        const float a = atanUnit(y / ax);
        return x > 0 ? a : kPi - a;
    }
    const float a = atanUnit(ax / y);
    return x >= 0 ? kHalfPi - a : kHalfPi + a;
}

}  // namespace brume
