// 3-vectors of float: positions, directions and RGB radiometric quantities.
#pragma once
#include <algorithm>
#include <cmath>

namespace brume {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 1.0f / kPi;
constexpr float kInv4Pi = 1.0f / (4.0f * kPi);

struct Vec3 {
    float x = 0, y = 0, z = 0;
    constexpr Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3(float s) : x(s), y(s), z(s) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

// RGB radiometric quantity (radiance, throughput, coefficients): same arithmetic as Vec3.
using Spectrum = Vec3;

constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
constexpr Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3 operator/(Vec3 a, Vec3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
constexpr Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3 operator*(float s, Vec3 a) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3 operator/(Vec3 a, float s) { return a * (1.0f / s); }
inline Vec3& operator+=(Vec3& a, Vec3 b) { return a = a + b; }
inline Vec3& operator-=(Vec3& a, Vec3 b) { return a = a - b; }
inline Vec3& operator*=(Vec3& a, Vec3 b) { return a = a * b; }
inline Vec3& operator*=(Vec3& a, float s) { return a = a * s; }
inline Vec3& operator/=(Vec3& a, float s) { return a = a / s; }

constexpr float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// A Vec3 read one float at a time, for hot functions whose callers have just written it float
// by float: the compiler may otherwise load x and y as one 8-byte pair, and a load that
// straddles two stores is not forwarded from the store buffer (it waits for the stores to
// reach the cache; measured as most of a small function's time). Volatile reads are 4 bytes.
inline float loadFloat(const float& f) { return *static_cast<const volatile float*>(&f); }
inline Vec3 loadVec3(const Vec3& v) { return {loadFloat(v.x), loadFloat(v.y), loadFloat(v.z)}; }

inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline float lengthSquared(Vec3 a) { return dot(a, a); }
inline Vec3 normalize(Vec3 a) { return a / length(a); }
inline Vec3 vmin(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 vmax(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline Vec3 vexp(Vec3 a) { return {std::exp(a.x), std::exp(a.y), std::exp(a.z)}; }
inline float maxComponent(Vec3 a) { return std::max(a.x, std::max(a.y, a.z)); }
inline float minComponent(Vec3 a) { return std::min(a.x, std::min(a.y, a.z)); }
inline float average(Vec3 a) { return (a.x + a.y + a.z) * (1.0f / 3.0f); }
inline float luminance(Spectrum s) { return 0.2126f * s.x + 0.7152f * s.y + 0.0722f * s.z; }
inline bool isBlack(Spectrum s) { return s.x == 0 && s.y == 0 && s.z == 0; }
inline bool isFinite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// Reflect d (pointing away from the surface) about n.
inline Vec3 reflect(Vec3 d, Vec3 n) { return 2.0f * dot(d, n) * n - d; }

}  // namespace brume
