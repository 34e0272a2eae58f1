// SCARA / planar 2R or 3R: angle sum, height along the axes, planar 2R: 2 candidates
// (ik_case_planar.cpp).
#pragma once

#include "armkit/case_chain.hpp"
#include "armkit/ik_detect.hpp"
#include "armkit/vec.hpp"

namespace armkit {

// Revolute joints (2 or 3) about hp (u a unit normal of it), at most one prismatic joint
// along it; y a point moved by the first two revolute joints only.
struct PlanarGeometry : CaseChain {
    Vec3 hp, u, y;
    int revolute[3] = {0, 0, 0};
    int revolute_count = 0;
    int prismatic_joint = -1;
};

void solve_case(const PlanarGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// 2 to 4 joints: 2 or 3 parallel revolute axes, at most one prismatic joint along them.
Detection<PlanarGeometry> detect_planar(const ArmLines& arm);

}  // namespace armkit
