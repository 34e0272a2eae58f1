// Axes 1-3 parallel: a two-angle system in q6, q4, then q5, q1 + q2 + q3 and a planar 2R: 8
// candidates (ik_case_parallel_base.cpp). Axes 4-6 parallel: this case on the reversed chain.
#pragma once

#include "armkit/case_chain.hpp"
#include "armkit/ik_case_three_parallel.hpp"
#include "armkit/ik_detect.hpp"
#include "armkit/two_angle.hpp"

namespace armkit {

// hp the direction of the parallel axes, u a unit normal of it; o4, o5, o6 points of axes
// 4-6 (o4, o5 closest to each other).
struct ParallelBaseGeometry : CaseChain, TwoAngleSystem {
    Vec3 hp, u, o4, o5, o6;
};

void solve_case(const ParallelBaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// 6 revolute joints, axes 1-3 parallel (4 leaving them, 5 and 6 not parallel); else axes 4-6
// (this case on the reversed chain).
Detection<ParallelBaseGeometry> detect_parallel_base(const ArmLines& arm);

}  // namespace armkit
