// Checks of user-given rigid transforms and the whole-turn wrap of revolute angles.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "armkit/chain.hpp"

namespace armkit {

struct Rigidity {
    bool finite = true;          // every entry finite
    double last_row = 0.0;       // largest deviation of a last row from [0, 0, 0, 1]
    double orthonormal = 0.0;    // largest of |R^T R - I| and |det R - 1|
    std::size_t rough = 0;       // rotations off by more than 1e-14
};

// One pass over N transforms (N x 4 x 4, row-major), no temporaries.
Rigidity rigidity(const double* T, std::size_t N);

// A revolute angle shifted by whole turns into [lower, upper] (widened by tolerance):
// among several fitting shifts (limits wider than 2 pi) the one closest to `reference`;
// an angle that fits no shift is moved as close to `reference` as whole turns allow.
inline double wrap_angle_into_limits(double q, double lower, double upper, double reference,
                                     double tolerance = kLimitTolerance) {
    const double low = lower - tolerance, high = upper + tolerance;
    if (low <= q && q <= high && high - low < kTwoPi) return q;  // fits, and no other shift can
    const double turns_low = std::ceil((low - q) / kTwoPi);
    const double turns_high = std::floor((high - q) / kTwoPi);
    double turns = nearest_integer((reference - q) / kTwoPi);
    // clamped into [turns_low, turns_high] (NaN: turns_low, as fmax gives; std::min and max inline,
    // where fmin and fmax are libm calls)
    if (turns_low <= turns_high) turns = std::isnan(turns) ? turns_low : std::min(std::max(turns, turns_low), turns_high);
    return q + kTwoPi * turns;
}

}  // namespace armkit
