// 4x4 affine transforms for glTF node hierarchies (column-major, as glTF stores them).
#pragma once
#include <array>
#include "brume/math/vec3.h"

namespace brume {

struct Mat4 {
    std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // m[col*4+row]
    double operator()(int row, int col) const { return m[col * 4 + row]; }
    double& operator()(int row, int col) { return m[col * 4 + row]; }

    static Mat4 fromTRS(const double t[3], const double r[4], const double s[3]);
    Mat4 operator*(const Mat4& b) const;
    Vec3 point(Vec3 p) const;
    Vec3 vector(Vec3 v) const;
    // Normals transform by the inverse transpose of the linear part.
    Vec3 normal(Vec3 n) const;
    double det3() const;
    // The inverse of an affine transform (bottom row 0 0 0 1, det3 ≠ 0).
    Mat4 affineInverse() const;
};

}  // namespace brume
