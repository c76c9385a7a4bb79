#include "brume/math/mat4.h"

namespace brume {

Mat4 Mat4::fromTRS(const double t[3], const double q[4], const double s[3]) {
    // q = (x, y, z, w), glTF order. Rotation matrix of a unit quaternion, then scale columns.
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                      {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                      {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    Mat4 M;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) M(row, col) = r[row][col] * s[col];
    for (int row = 0; row < 3; ++row) M(row, 3) = t[row];
    return M;
}

Mat4 Mat4::operator*(const Mat4& b) const {
    Mat4 c;
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) sum += (*this)(row, k) * b(k, col);
            c(row, col) = sum;
        }
    return c;
}

Vec3 Mat4::point(Vec3 p) const {
    double r[3];
    for (int row = 0; row < 3; ++row)
        r[row] = (*this)(row, 0) * p.x + (*this)(row, 1) * p.y + (*this)(row, 2) * p.z + (*this)(row, 3);
    return Vec3(float(r[0]), float(r[1]), float(r[2]));
}

Vec3 Mat4::vector(Vec3 v) const {
    double r[3];
    for (int row = 0; row < 3; ++row)
        r[row] = (*this)(row, 0) * v.x + (*this)(row, 1) * v.y + (*this)(row, 2) * v.z;
    return Vec3(float(r[0]), float(r[1]), float(r[2]));
}

double Mat4::det3() const {
    const Mat4& a = *this;
    return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) -
           a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
           a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
}

Vec3 Mat4::normal(Vec3 n) const {
    // Cofactor matrix = det · inverse-transpose; times sign(det) it points like the
    // inverse-transpose, also for mirroring transforms.
    const Mat4& a = *this;
    double c[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            c[i][j] = a(i1, j1) * a(i2, j2) - a(i1, j2) * a(i2, j1);
        }
    double r[3];
    for (int i = 0; i < 3; ++i) r[i] = c[i][0] * n.x + c[i][1] * n.y + c[i][2] * n.z;
    double sign = det3() < 0 ? -1.0 : 1.0;
    Vec3 out{float(sign * r[0]), float(sign * r[1]), float(sign * r[2])};
    float len = length(out);
    return len > 0 ? out / len : n;
}

Mat4 Mat4::affineInverse() const {
    // [R t]⁻¹ = [R⁻¹  −R⁻¹·t], R⁻¹ = cofactorᵀ / det.
    const Mat4& a = *this;
    const double det = det3();
    Mat4 inv;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            inv(j, i) = (a(i1, j1) * a(i2, j2) - a(i1, j2) * a(i2, j1)) / det;
        }
    for (int r = 0; r < 3; ++r) inv(r, 3) = -(inv(r, 0) * a(0, 3) + inv(r, 1) * a(1, 3) + inv(r, 2) * a(2, 3));
    return inv;
}

}  // namespace brume
