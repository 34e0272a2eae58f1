// The chain as the core sees it: the fixed transforms between consecutive joint motions.
//
//   T_base_tool(q) = L_0 · M_1(q_1) · L_1 · M_2(q_2) · ... · M_n(q_n) · L_n
//
// with M_i = Rz(q_i) (revolute) or Tz(q_i) (prismatic) and L = Chain.T_between of the
// Python layer (armkit/chain.py), which builds this once per chain.
#pragma once

#include <cstdint>
#include <vector>

#include "armkit/tolerances.hpp"
#include "armkit/vec.hpp"

namespace armkit {

struct Chain {
    int n = 0;
    std::vector<Pose> between;       // n + 1 fixed transforms
    std::vector<std::uint8_t> prismatic;  // n
    std::vector<double> lower, upper;     // n position limits [rad or m]

    // The core's one joint-limit test: value v of joint j inside its limits, to kLimitTolerance
    // (the Python layer's is Chain.outside_limits, with the same constant).
    bool within_limit(int j, double v) const {
        return lower[j] - kLimitTolerance <= v && v <= upper[j] + kLimitTolerance;
    }

    bool within_limits(const double* q) const {
        for (int j = 0; j < n; ++j)
            if (!within_limit(j, q[j])) return false;
        return true;
    }
};

}  // namespace armkit
