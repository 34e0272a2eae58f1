// Joints 1-3 carry a point c to a target w (the wrist centre of a spherical wrist, or the
// tool point of position IK): 4 candidates (ik_case_point.cpp).
#pragma once

#include "armkit/case_chain.hpp"
#include "armkit/ik_detect.hpp"
#include "armkit/two_angle.hpp"
#include "armkit/vec.hpp"

namespace armkit {

// Which pair of axes 1-3 meets or is parallel (armkit.ik.cases.POSITION_CASES, same order).
// Parallel12Prismatic: revolute axes 1, 2 parallel and joint 3 a slide not normal to them (a
// SCARA's R R P): the slide sets the height along axis 1, a planar 2R the rest.
enum class PositionCase : int {
    Parallel23 = 0, Parallel12 = 1, Intersect23 = 2, Intersect12Revolute = 3, Intersect12Prismatic = 4,
    General123 = 5, Parallel12Prismatic = 6
};
//: Their names, in PositionCase's order.
constexpr const char* kPositionCaseNames[] = {"parallel-23", "parallel-12", "intersect-23", "intersect-12-revolute",
                                              "intersect-12-prismatic", "general-123", "parallel-12-prismatic"};
//: How many position cases there are.
constexpr int kPositionCaseCount = int(sizeof(kPositionCaseNames) / sizeof(kPositionCaseNames[0]));

// o: where axes 1 and 2 (or 2 and 3) meet; for general axes (General123) the closest points
// o2, o3 of axes 2 and 3 and the two-angle system in q1, q3.
struct PointGeometry : CaseChain, TwoAngleSystem {
    PositionCase position_case = PositionCase::Parallel23;
    Vec3 c, o, o2, o3;
};

// The three joints of each of four candidates for joints 1-3.
struct ArmCandidates {
    double q[4][3];
    bool valid[4], free[4];
};

// Joints 1-3 that put the point g.c at w: four triples.
ArmCandidates wrist_centre_joints(const PointGeometry& g, Vec3 w);

// Joints 1-3 carrying g.c to t (G = T, no M^-1; R unused): 4 candidates into q (4 x 3).
void solve_case(const PointGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// The point case of joints 1-3 of plan.lines carrying c (general axes: the two-angle system
// in q1, q3 of their height along axis 2 and distance from it).
PointGeometry point_geometry(const PositionPlan& plan, Vec3 c);

// Joints 1-3 (arm: 3 joints, see first_lines) carrying the tool point arm.M's position:
// position IK only, never a whole pose.
Detection<PointGeometry> detect_point(const ArmLines& arm);

}  // namespace armkit
