// The closed-form case solvers, one target at a time (port of armkit/ik/cases.py).
//
// The chain is taken as screw axes at q = 0: T(q) = exp(xi_1 q_1) ... exp(xi_n q_n) M, so a
// target gives G = T M^-1, the motion of the joints alone. One solver per geometric case
// splits G (rotation R, translation t) into Paden-Kahan subproblems (subproblems.hpp) and
// writes every candidate into the rows of q (k x n, internal joint order), with valid and
// family flags (k). New cases (general 6R, 16 solutions; 7R through a locked joint) join
// as another CaseKind and solver function.
#pragma once

#include <cstdint>
#include <vector>

#include "armkit/ik_general.hpp"
#include "armkit/vec.hpp"

namespace armkit {

// Point: joints 1-3 of any chain carry a tool point to a target position (position IK, 4
// candidates); General: any 6R arm (ik_general.hpp, 16 candidates); the others solve full poses.
enum class CaseKind : int { Spherical = 0, ThreeParallel = 1, ParallelBase = 2, Planar = 3, Point = 4, General = 5 };

// How joints 1-3 of a spherical-wrist arm place the wrist centre
// (armkit.ik.cases.POSITION_CASES, same order).
enum class PositionCase : int {
    Parallel23 = 0, Parallel12 = 1, Intersect23 = 2, Intersect12Revolute = 3, Intersect12Prismatic = 4,
    General123 = 5, None = -1
};

// Everything a case solver needs from the chain, computed once per chain by the Python
// layer (armkit/ik/closed_form.py, ClosedFormSolver), field for field cases.CaseGeometry.
struct CaseGeometry {
    CaseKind kind = CaseKind::Spherical;
    PositionCase position_case = PositionCase::None;
    int n = 0;
    std::vector<Vec3> h, p;               // internal axes and points (n)
    std::vector<std::uint8_t> prismatic;  // (n)
    Vec3 c, o, u, hp, a1, a2, a3;         // points / directions, meaning by case
    double Q[2][2] = {{0, 0}, {0, 0}};    // the constant part of the two-angle system
    double Q_inv[2][2] = {{0, 0}, {0, 0}};
    double f[2] = {0, 0};
    bool rank1 = false;
    double lam[2] = {0, 0}, mu[2] = {0, 0};
    bool snap_t2 = true;
    std::vector<double> q5_aligned;  // q5 values that turn axis 6 parallel to h (three-parallel)
    double b_aligned = 0.0;
    std::vector<int> revolute_joints;  // planar: the revolute joints (2 or 3)
    int prismatic_joint = -1;          // planar: the prismatic joint, or -1
    GeneralSixR general;               // general: the elimination's constants
    int k = 8;                         // candidates per pose (8; 2 planar, 4 point, 16 general)
    double size = 1.0;                 // length scale [m]: 1 + the largest coordinate of p
};

// Every candidate for the joint motion G = (R, t): into q (g.k x g.n, row-major, internal
// joint order), valid and family (g.k).
void solve_pose(const CaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

}  // namespace armkit
