// Small fixed-size value types of the core: 3-vectors, 3x3 rotations and rigid poses.
// Everything is plain arithmetic on doubles, inlined; no heap allocation anywhere.
#pragma once

#include <cmath>

namespace armkit {

struct Vec3 {
    double x = 0.0, y = 0.0, z = 0.0;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 vec3(const double* v) { return {v[0], v[1], v[2]}; }

// Rodrigues: v rotated by angle t about the unit axis k.
inline Vec3 rotate(Vec3 k, double t, Vec3 v) {
    const double c = std::cos(t), s = std::sin(t);
    return c * v + s * cross(k, v) + ((1.0 - c) * dot(k, v)) * k;
}

// A 3x3 matrix, row-major: r[i] is row i.
struct Mat3 {
    Vec3 r[3];
};

inline Vec3 operator*(const Mat3& R, Vec3 v) { return {dot(R.r[0], v), dot(R.r[1], v), dot(R.r[2], v)}; }
inline Vec3 mul_transposed(const Mat3& R, Vec3 v) { return v.x * R.r[0] + v.y * R.r[1] + v.z * R.r[2]; }

// A rigid transform [R p; 0 1], stored as the top three rows of the 4x4 matrix, row-major
// (m[4 * row + column]), the layout of a C-ordered NumPy (4, 4) array without its last row.
struct Pose {
    double m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

    double& operator()(int row, int col) { return m[4 * row + col]; }
    double operator()(int row, int col) const { return m[4 * row + col]; }
    Vec3 column(int col) const { return {m[col], m[4 + col], m[8 + col]}; }
    Vec3 position() const { return column(3); }
    Mat3 rotation() const {
        return {{{m[0], m[1], m[2]}, {m[4], m[5], m[6]}, {m[8], m[9], m[10]}}};
    }
};

// A pose read from / written to a 4x4 row-major array (the last row of the array is
// ignored on read and written as [0, 0, 0, 1]).
inline Pose pose_from_matrix(const double* T) {
    Pose P;
    for (int k = 0; k < 12; ++k) P.m[k] = T[k];
    return P;
}
inline void pose_to_matrix(const Pose& P, double* T) {
    for (int k = 0; k < 12; ++k) T[k] = P.m[k];
    T[12] = T[13] = T[14] = 0.0;
    T[15] = 1.0;
}

// A B for rigid transforms.
inline Pose compose(const Pose& A, const Pose& B) {
    Pose C;
    for (int r = 0; r < 3; ++r) {
        const double a0 = A(r, 0), a1 = A(r, 1), a2 = A(r, 2), a3 = A(r, 3);
        for (int k = 0; k < 4; ++k) C(r, k) = a0 * B(0, k) + a1 * B(1, k) + a2 * B(2, k);
        C(r, 3) += a3;
    }
    return C;
}

// A^-1 = [R^T, -R^T p].
inline Pose inverse(const Pose& A) {
    Pose C;
    for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) C(r, k) = A(k, r);
        C(r, 3) = -(A(0, r) * A(0, 3) + A(1, r) * A(1, 3) + A(2, r) * A(2, 3));
    }
    return C;
}

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

// x rounded to the nearest whole number, ties to even: std::nearbyint in the default rounding
// mode, inline (the baseline x86-64 build has no rounding instruction, and nearbyint is a libm
// call there). Below 2^52 adding and taking away 2^52 rounds |x| so; from 2^52 on (and inf,
// NaN) x is its own value.
inline double nearest_integer(double x) {
    constexpr double kTwo52 = 4503599627370496.0;
    const double magnitude = std::fabs(x);
    if (!(magnitude < kTwo52)) return x;
    return std::copysign((magnitude + kTwo52) - kTwo52, x);
}

// angle shifted by whole turns into [-pi, pi]. Below 3 in magnitude (inside [-pi, pi]) no turn
// is taken off and the angle is its own value (+ 0.0 turns -0 into +0, as the subtraction does).
inline double wrap_angle(double angle) {
    if (std::fabs(angle) <= 3.0) return angle + 0.0;
    return angle - kTwoPi * nearest_integer(angle / kTwoPi);
}

}  // namespace armkit
