// Forward kinematics and the geometric Jacobian of one configuration, and the pose error.
#pragma once

#include <cstddef>

#include "armkit/chain.hpp"
#include "armkit/linalg.hpp"
#include "armkit/simd.hpp"
#include "armkit/sin_cos.hpp"

namespace armkit {

// The sines and cosines of one configuration's joint values (a prismatic joint's unused),
// from sin_cos: every FK path of the core takes them from there, so a pose is the same
// number whichever path (one configuration, a block, frames, axes) computed it.
struct JointTrig {
    double s[kMaxJoints], c[kMaxJoints];
    JointTrig(const double* q, int n) { sin_cos(q, s, c, n); }
};

// T <- T · Rz(q) (or T · Tz(q)): joint i's motion, with its sine and cosine from trig.
inline void move(Pose& T, const double* q, const JointTrig& trig, int i, bool prismatic) {
    if (prismatic) {
        for (int r = 0; r < 3; ++r) T(r, 3) += q[i] * T(r, 2);
    } else {
        const double c = trig.c[i], s = trig.s[i];
        for (int r = 0; r < 3; ++r) {
            const double x = T(r, 0), y = T(r, 1);
            T(r, 0) = c * x + s * y;
            T(r, 1) = c * y - s * x;
        }
    }
}

// The tool pose at q (n values).
inline Pose tool_pose(const Chain& chain, const double* q) {
    const JointTrig trig(q, chain.n);
    Pose T = chain.between[0];
    for (int i = 0; i < chain.n; ++i) {
        move(T, q, trig, i, chain.prismatic[i]);
        T = compose(T, chain.between[i + 1]);
    }
    return T;
}

//: Configurations a batch FK step handles together: the arithmetic runs across them, laid
//: out structure-of-arrays so the compiler vectorises it.
constexpr int kFkBlock = 8;

// Tool poses of kFkBlock configurations q (kFkBlock x n, row-major) into T (kFkBlock x 4 x 4),
// the same numbers as tool_pose of each (the same operations in the same order). Always
// inlined, so that tool_poses_blocks' AVX2 build computes it with AVX2.
ARMKIT_INLINE void tool_poses_block(const Chain& chain, const double* q, double* out) {
    constexpr int B = kFkBlock;
    const int n = chain.n;
    double sines[B * kMaxJoints], cosines[B * kMaxJoints];
    sin_cos(q, sines, cosines, B * n);
    double T[12][B];
    for (int k = 0; k < 12; ++k)
        for (int b = 0; b < B; ++b) T[k][b] = chain.between[0].m[k];
    for (int j = 0; j < n; ++j) {
        if (chain.prismatic[j]) {
            for (int r = 0; r < 3; ++r)
                for (int b = 0; b < B; ++b) T[4 * r + 3][b] += q[b * n + j] * T[4 * r + 2][b];
        } else {
            double c[B], s[B];
            for (int b = 0; b < B; ++b) {
                c[b] = cosines[b * n + j];
                s[b] = sines[b * n + j];
            }
            for (int r = 0; r < 3; ++r)
                for (int b = 0; b < B; ++b) {
                    const double x = T[4 * r][b], y = T[4 * r + 1][b];
                    T[4 * r][b] = c[b] * x + s[b] * y;
                    T[4 * r + 1][b] = c[b] * y - s[b] * x;
                }
        }
        const Pose& L = chain.between[j + 1];
        for (int r = 0; r < 3; ++r)
            for (int b = 0; b < B; ++b) {
                const double a0 = T[4 * r][b], a1 = T[4 * r + 1][b], a2 = T[4 * r + 2][b], a3 = T[4 * r + 3][b];
                T[4 * r][b] = a0 * L(0, 0) + a1 * L(1, 0) + a2 * L(2, 0);
                T[4 * r + 1][b] = a0 * L(0, 1) + a1 * L(1, 1) + a2 * L(2, 1);
                T[4 * r + 2][b] = a0 * L(0, 2) + a1 * L(1, 2) + a2 * L(2, 2);
                T[4 * r + 3][b] = a0 * L(0, 3) + a1 * L(1, 3) + a2 * L(2, 3) + a3;
            }
    }
    for (int b = 0; b < B; ++b) {
        double* M = out + 16 * b;
        for (int k = 0; k < 12; ++k) M[k] = T[k][b];
        M[12] = M[13] = M[14] = 0.0;
        M[15] = 1.0;
    }
}

// tool_poses_block over `blocks` consecutive blocks (q blocks x kFkBlock x n, out blocks x
// kFkBlock x 4 x 4), built for the baseline CPU and for AVX2 (armkit/simd.hpp; fk.cpp).
void tool_poses_blocks(const Chain& chain, const double* q, double* out, std::size_t blocks);

// The tool poses of count configurations q (count x n, row-major; count <= kMaxCandidates) into
// F (count), kFkBlock at a time through tool_poses_blocks (the numbers of tool_pose of each): the
// candidates of one IK pose in a block or two.
inline void tool_poses(const Chain& chain, const double* q, int count, Pose* F) {
    const int n = chain.n;
    double block[kFkBlock * kMaxJoints] = {}, out[kFkBlock * 16];
    for (int start = 0; start < count; start += kFkBlock) {
        const int m = count - start < kFkBlock ? count - start : kFkBlock;
        for (int a = 0; a < m * n; ++a) block[a] = q[start * n + a];
        tool_poses_blocks(chain, block, out, 1);
        for (int b = 0; b < m; ++b) F[start + b] = pose_from_matrix(out + 16 * b);
    }
}

// The tool pose, and per joint the z axis of its joint frame and its origin before the
// joint's motion (the start of the travel for a prismatic joint), base frame.
inline Pose joint_axes(const Chain& chain, const double* q, Vec3* axes, Vec3* points) {
    const JointTrig trig(q, chain.n);
    Pose T = chain.between[0];
    for (int i = 0; i < chain.n; ++i) {
        axes[i] = T.column(2);
        points[i] = T.column(3);
        move(T, q, trig, i, chain.prismatic[i]);
        T = compose(T, chain.between[i + 1]);
    }
    return T;
}

// Base-frame geometric Jacobian (6 x n, row-major, rows [v; w]) from joint_axes' results.
inline void jacobian_from_axes(const Pose& T, const Vec3* axes, const Vec3* points,
                               const std::uint8_t* prismatic, int n, double* J) {
    const Vec3 p = T.position();
    for (int i = 0; i < n; ++i) {
        const Vec3 z = axes[i];
        const Vec3 v = prismatic[i] ? z : cross(z, p - points[i]);
        const Vec3 w = prismatic[i] ? Vec3{} : z;
        J[0 * n + i] = v.x; J[1 * n + i] = v.y; J[2 * n + i] = v.z;
        J[3 * n + i] = w.x; J[4 * n + i] = w.y; J[5 * n + i] = w.z;
    }
}

// e = [p_target - p; rotation vector of R_target R^T] (base frame), exact up to and at pi:
// from 120 degrees on (trace <= 0) the axis comes from the symmetric part of the rotation,
// (R + R^T) / 2 - cos(angle) I = (1 - cos(angle)) axis axis^T, with 1 - cos(angle) >= 3/2,
// where v / |v| (v = 2 sin(angle) axis) would lose digits as the angle nears pi.
void pose_error(const Pose& target, const Pose& T, double* e);

// FK residual of pose F to the target: position distance [m] and rotation angle [rad],
// accurate to rounding from 0 to pi (X - I = R_target^T (R - R_target) keeps small angles).
void pose_residual(const Pose& target, const Pose& F, double& position, double& angle);

}  // namespace armkit
