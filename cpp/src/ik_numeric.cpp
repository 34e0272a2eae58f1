#include "armkit/ik_numeric.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "armkit/batch.hpp"
#include "armkit/fk.hpp"
#include "armkit/random.hpp"

namespace armkit {

namespace {

using Clock = std::chrono::steady_clock;

//: Budgets [s] from which on the clock is not read (also keeps the deadline from overflowing).
constexpr double kUnlimitedBudget = 1e9;

// The lowest-cost configuration over all attempts of one solve.
struct Best {
    double cost = std::numeric_limits<double>::infinity();
    double position = std::numeric_limits<double>::infinity();
    double orientation = std::numeric_limits<double>::infinity();
    double q[kMaxJoints];
};

struct Attempt {
    bool solved;
    int steps;
    double position, orientation;  // errors [m, rad] of the last configuration evaluated
};

// x mod 2 pi in [0, 2 pi), as Python's float % (the numba kernel this ports).
double turn_remainder(double x) {
    double r = std::fmod(x, kTwoPi);
    if (r != 0.0) {
        if (r < 0.0) r += kTwoPi;
    } else {
        r = 0.0;
    }
    return r;
}

// The 2-norm of the kept error rows of one kind (position: rows 0-2), scaled so that a target
// 1e160 m away or farther, whose squares overflow, still gets its distance rather than inf.
double scaled_error_norm(const double* e, const NumericSettings& s, bool position_rows) {
    double largest = 0.0;
    for (int k = 0; k < s.m; ++k)
        if ((s.rows[k] < 3) == position_rows) largest = std::max(largest, std::abs(e[s.rows[k]]));
    if (largest == 0.0 || !std::isfinite(largest)) return largest;
    double sum = 0.0;
    for (int k = 0; k < s.m; ++k) {
        if ((s.rows[k] < 3) != position_rows) continue;
        const double x = e[s.rows[k]] / largest;
        sum += x * x;
    }
    return largest * std::sqrt(sum);
}

// One Levenberg-Marquardt attempt from q (updated in place to the last configuration
// evaluated); best keeps the lowest-cost configuration.
Attempt attempt(const NumericSolver& solver, const Pose& target, double* q, Best& best) {
    const Chain& chain = solver.chain;
    const NumericSettings& s = solver.settings;
    const int n = chain.n;
    const double position_tolerance2 = s.position_tolerance * s.position_tolerance;
    const double orientation_tolerance2 = s.orientation_tolerance * s.orientation_tolerance;
    Vec3 axes[kMaxJoints], points[kMaxJoints];
    double J[6 * kMaxJoints], e[6], sides[kMaxJoints] = {}, dq[kMaxJoints];
    if (s.within_limits) project(chain, q, sides);
    double reference = std::numeric_limits<double>::infinity();
    double position = reference, orientation = reference;
    int since = 0, steps = 0;
    while (steps < s.max_iterations) {
        ++steps;
        const Pose T = joint_axes(chain, q, axes, points);
        pose_error(target, T, e);
        position = orientation = 0.0;
        for (int k = 0; k < s.m; ++k) (s.rows[k] < 3 ? position : orientation) += e[s.rows[k]] * e[s.rows[k]];
        const double cost = 0.5 * (position + orientation);
        if (!std::isfinite(cost)) {  // squares overflowed: keep the distances, end the attempt below
            const double position_norm = scaled_error_norm(e, s, true);
            if (std::isinf(best.cost) && !(position_norm >= best.position)) {
                best.position = position_norm;
                best.orientation = scaled_error_norm(e, s, false);
                std::copy(q, q + n, best.q);
            }
        } else if (cost < best.cost) {
            best.cost = cost;
            best.position = std::sqrt(position);
            best.orientation = std::sqrt(orientation);
            std::copy(q, q + n, best.q);
        }
        if (position <= position_tolerance2 && orientation <= orientation_tolerance2)
            return {true, steps, std::sqrt(position), std::sqrt(orientation)};
        if (cost < kStallFactor * reference) {
            reference = cost;
            since = 0;
        } else if (++since >= kStallSteps || !std::isfinite(cost)) {
            break;
        }
        if (steps == s.max_iterations) break;  // the step would never be evaluated
        jacobian_from_axes(T, axes, points, chain.prismatic.data(), n, J);
        damped_step(J, n, e, s.rows, s.m, sides, s.damping_gain * cost + s.damping, dq);
        for (int i = 0; i < n; ++i) q[i] += dq[i];
        if (s.within_limits) project(chain, q, sides);
    }
    return {false, steps, std::sqrt(position), std::sqrt(orientation)};
}

}  // namespace

NumericSolver::NumericSolver(Chain chain_, const NumericSettings& settings_)
    : chain(std::move(chain_)), settings(settings_) {
    for (int i = 0; i < chain.n; ++i) {
        seed_low[i] = std::isfinite(chain.lower[i]) ? chain.lower[i] : -kUnboundedSeedRange;
        seed_high[i] = std::isfinite(chain.upper[i]) ? chain.upper[i] : kUnboundedSeedRange;
    }
}

void project(const Chain& chain, double* q, double* sides) {
    for (int i = 0; i < chain.n; ++i) {
        double value = q[i];
        const double low = chain.lower[i], high = chain.upper[i];
        sides[i] = 0.0;
        if (low < value && value < high) continue;
        if (!chain.prismatic[i] && !(low <= value && value <= high)) {
            const double turned = low + turn_remainder(value - low);  // in [low, low + 2 pi)
            // inside, or else at the bound nearer in angle
            value = turned <= high || turned - high < low + kTwoPi - turned ? turned : low;
        }
        if (value <= low) {
            value = low;
            sides[i] = -1.0;
        } else if (value >= high) {
            value = high;
            sides[i] = 1.0;
        }
        q[i] = value;
    }
}

NumericResult solve(const NumericSolver& solver, const Pose& target, const double* q0, std::uint64_t seed,
                    double* q) {
    const int n = solver.chain.n;
    const NumericSettings& s = solver.settings;
    for (int i = 0; i < n; ++i) q[i] = q0 ? q0[i] : (solver.seed_low[i] + solver.seed_high[i]) / 2.0;
    Best best;
    std::copy(q, q + n, best.q);
    const bool timed = s.time_budget < kUnlimitedBudget;
    const Clock::time_point deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(
                           std::chrono::duration<double>(timed ? s.time_budget : 0.0));
    Random random(seed);
    NumericResult result;
    while (true) {
        const Attempt a = attempt(solver, target, q, best);
        result.iterations += a.steps;
        if (a.solved) {
            result.success = true;
            result.position_error = a.position;
            result.orientation_error = a.orientation;
            return result;
        }
        if (result.restarts >= s.max_restarts || (timed && Clock::now() > deadline)) break;
        for (int i = 0; i < n; ++i) q[i] = random.uniform(solver.seed_low[i], solver.seed_high[i]);
        ++result.restarts;
    }
    std::copy(best.q, best.q + n, q);
    result.position_error = best.position;
    result.orientation_error = best.orientation;
    return result;
}

void solve_batch(const NumericSolver& solver, const double* T, const double* q0, std::size_t N,
                 std::uint64_t seed, int threads, double* q, bool* success, std::int64_t* iterations,
                 std::int64_t* restarts, double* position_error, double* orientation_error) {
    const std::size_t n = std::size_t(solver.chain.n);
    // a solve costs more than starting a thread (one pose per thread at least), its result
    // depending on its pose alone
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const NumericResult r = solve(solver, pose_from_matrix(T + 16 * i), q0 ? q0 + n * i : nullptr,
                                          item_seed(seed, i), q + n * i);
            success[i] = r.success;
            iterations[i] = r.iterations;
            restarts[i] = r.restarts;
            position_error[i] = r.position_error;
            orientation_error[i] = r.orientation_error;
        }
    }, 1);
}

}  // namespace armkit
