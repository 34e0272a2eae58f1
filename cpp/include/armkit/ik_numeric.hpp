// Numeric IK of any chain: Levenberg-Marquardt with random restarts (armkit/ik/numeric.py).
//
// Minimises E = 1/2 e^T W e, e = [p_target - p; log(R_target R^T)] (pose_error), W a 0/1
// mask of task rows, with Sugihara's damped step (J^T W J + (g E + damping) I) dq = J^T W e
// (damped_step). With limits, each step is projected into them (project) and joints held
// at a bound by the gradient drop out of the next step. An attempt that has not halved its
// cost in kStallSteps steps, or used max_iterations steps, is abandoned for a uniform random
// seed inside the limits, until max_restarts or the time budget runs out.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>

#include "armkit/chain.hpp"
#include "armkit/linalg.hpp"

namespace armkit {

//: Range [m] used for random seeds of joints without limits.
constexpr double kUnboundedSeedRange = 1.0;
//: An attempt whose cost has not fallen below kStallFactor times its reference in
//: kStallSteps steps is abandoned for a new seed.
constexpr int kStallSteps = 3;
constexpr double kStallFactor = 0.5;

struct NumericSettings {
    int rows[6] = {0, 1, 2, 3, 4, 5};  // task rows of e kept by the mask (ascending)
    int m = 6;
    double position_tolerance = 1e-9;     // [m]
    double orientation_tolerance = 1e-9;  // [rad]
    double damping_gain = 0.1;            // g
    double damping = 1e-9;                // the damping floor
    int max_iterations = 30;              // steps per attempt
    int max_restarts = 100;               // random seeds after the first attempt
    double time_budget = 0.5;             // [s] wall clock, checked between attempts
    bool within_limits = true;            // every step projected into the joint limits
};

struct NumericResult {
    bool success = false;
    int iterations = 0;               // steps over all attempts
    int restarts = 0;                 // attempts from a random seed
    double position_error = 0.0;      // [m], masked rows
    double orientation_error = 0.0;   // [rad], masked rows
};

// A chain with its settings and the box random seeds are drawn from (the limits; an
// infinite bound replaced by +-kUnboundedSeedRange).
struct NumericSolver {
    NumericSolver(Chain chain, const NumericSettings& settings);

    Chain chain;
    NumericSettings settings;
    double seed_low[kMaxJoints], seed_high[kMaxJoints];
};

// Moves q (n) into the limits in place and marks the joints left at a bound: sides[i] = -1
// at the lower, +1 at the upper, 0 inside. A revolute angle outside its range moves by
// whole turns if that fits, else to the bound nearer in angle; a prismatic value to the
// nearer bound.
void project(const Chain& chain, double* q, double* sides);

// Solves fk(q) = target from q0 (n; the middle of the seed box if null) into q (n), with the
// restart seeds drawn from Random(seed). On failure q is the lowest-cost configuration seen.
NumericResult solve(const NumericSolver& solver, const Pose& target, const double* q0, std::uint64_t seed,
                    double* q);

// solve() for N targets (N x 4 x 4) from q0 (N x n, or null) into q (N x n) and the other
// outputs (N each), over `threads` threads (0: all cores), pose i seeded by item_seed(seed, i):
// the results do not depend on the thread count, except for solves cut short by the time
// budget (which each pose has for itself).
void solve_batch(const NumericSolver& solver, const double* T, const double* q0, std::size_t N,
                 std::uint64_t seed, int threads, double* q, bool* success, std::int64_t* iterations,
                 std::int64_t* restarts, double* position_error, double* orientation_error);

}  // namespace armkit
