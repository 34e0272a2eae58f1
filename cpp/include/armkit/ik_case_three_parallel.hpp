// Axes 2-4 parallel: a two-angle system in q1, q5, then q6, q2 + q3 + q4 and a planar 2R: 8
// candidates (ik_case_three_parallel.cpp). Axes 3-5 parallel: this case on the reversed chain.
#pragma once

#include "armkit/case_chain.hpp"
#include "armkit/ik_detect.hpp"
#include "armkit/two_angle.hpp"

namespace armkit {

// hp the direction of the parallel axes, u a unit normal of it; p5, p6 the closest points of
// axes 5 and 6; the values q5_aligned (aligned of them) that turn axis 6 parallel to hp, and
// b_aligned = |h5 x hp| |h5 x h6|.
struct ThreeParallelGeometry : CaseChain, TwoAngleSystem {
    Vec3 hp, u, p5, p6;
    double q5_aligned[4] = {0, 0, 0, 0};
    int aligned = 0;
    double b_aligned = 0.0;
};

void solve_case(const ThreeParallelGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// 6 revolute joints, axes 2-4 parallel (axes 1, 5 and 6 leaving them, 5 and 6 not parallel);
// else axes 3-5 (this case on the reversed chain).
Detection<ThreeParallelGeometry> detect_three_parallel(const ArmLines& arm);

// Axes first .. first + 2 of a 6R arm's lines parallel, the axes next to them leaving them
// and axes 5, 6 not parallel (first 1: this case; first 0: the parallel-base case).
bool three_parallel_block(const ArmLines& arm, int first);

}  // namespace armkit
