// A spherical wrist (axes 4-6 meet at c): joints 1-3 place c (the point case), then the wrist:
// 8 candidates (ik_case_spherical.cpp). A spherical base is this case on the reversed chain.
#pragma once

#include "armkit/ik_case_point.hpp"

namespace armkit {

// Joints 1-3 as PointGeometry; u a unit normal of h6.
struct SphericalGeometry : PointGeometry {
    Vec3 u;
};

void solve_case(const SphericalGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// 6 joints, revolute axes 4-6 meeting at one point and joints 1-3 of a position case (a
// spherical wrist); else the same on the reversed chain (a spherical base).
Detection<SphericalGeometry> detect_spherical(const ArmLines& arm);

}  // namespace armkit
