// Time-optimal path parameterisation by reachability analysis (TOPP-RA: H. Pham and Q.-C. Pham,
// "A new approach to time-optimal path parameterization based on reachability analysis",
// IEEE T-RO 2018), written for armkit: armkit/trajectory/topp.py is the Python side.
//
// Along a path q(s) sampled on a grid s_0 < s_1 < ... < s_N, the unknowns are x_i = s'(t)^2
// at each grid point and u_i = s''(t) on each interval, tied by x_{i+1} = x_i + 2 (s_{i+1} - s_i) u_i.
// Every constraint is linear in (u, x) at a grid point:
//     lo_ij <= a_ij u + b_ij x + c_ij <= hi_ij      (row j of m; joint acceleration: a = q', b = q'')
//     0 <= x_i <= x_max_i                            (joint velocity: x_max = min_j (vmax_j / |q'_j|)^2)
// Backward pass: the controllable sets K_i (the x_i from which some admissible controls reach
// K_N = {x_end}), each the projection onto x of a 2-variable polygon; u is eliminated exactly by
// pairing every lower bound on u with every upper bound (Fourier-Motzkin), so each K_i is found in
// closed form in O(m^2), no LP iterations. Forward pass: from x_0 = x_start, the largest admissible
// u_i keeping x_{i+1} inside K_{i+1}.
#pragma once

#include <cstddef>

#include "armkit/tolerances.hpp"

namespace armkit {

// The problem on a grid of `points` = N + 1 grid points with `rows` = m constraint rows each.
// Arrays are C-ordered: s (N+1), a, b, c, lo, hi (N+1, m), x_max (N+1; +inf: no bound).
struct ToppProblem {
    std::size_t points;
    std::size_t rows;
    const double* s;
    const double* a;
    const double* b;
    const double* c;
    const double* lo;
    const double* hi;
    const double* x_max;
    double x_start;  // s'^2 at s_0 (0: starting at rest)
    double x_end;    // s'^2 at s_N (0: ending at rest)
};

enum class ToppStatus : int {
    success = 0,
    infeasible = 1,        // some K_i is empty: no admissible motion passes grid point `point`
    start_unreachable = 2  // x_start is outside K_0
};

struct ToppResult {
    ToppStatus status;
    std::size_t point;  // the grid point where it failed (0 on success)
};

// Most constraint rows per grid point (bounds kept on the stack, no allocation per point).
constexpr std::size_t kToppMaxRows = 64;


// Solves `problem` (rows <= kToppMaxRows): x (N+1) = s'^2 at the grid points, u (N) = s'' on the intervals, and the
// controllable sets [k_lo, k_hi] (N+1 each). On failure x and u are left unspecified.
ToppResult topp_ra(const ToppProblem& problem, double* x, double* u, double* k_lo, double* k_hi);

}  // namespace armkit
