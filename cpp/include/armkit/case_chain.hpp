// The joint lines every closed-form case starts from (see ik_cases.hpp).
#pragma once

#include <cstdint>

#include "armkit/vec.hpp"

namespace armkit {

//: Joints of a case's chain at most (6: the closed-form cases and the general 6R arm).
constexpr int kMaxCaseJoints = 6;

// Internal axes h and points p at q = 0 (n each), which joints are prismatic, and the length
// scale [m]: 1 + the largest coordinate of p.
struct CaseChain {
    int n = 0;
    Vec3 h[kMaxCaseJoints], p[kMaxCaseJoints];
    std::uint8_t prismatic[kMaxCaseJoints] = {};
    double size = 1.0;
};

}  // namespace armkit
