#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <nanobind/stl/vector.h>

#include "armkit/fk.hpp"
#include "armkit/ik_numeric.hpp"
#include "armkit/linalg.hpp"
#include "armkit/random.hpp"
#include "bindings.hpp"

namespace armkit::bindings {

namespace {

using InIndex = nb::ndarray<const std::int64_t, nb::c_contig, nb::device::cpu>;
using OutIndex = nb::ndarray<std::int64_t, nb::c_contig, nb::device::cpu>;

NumericSolver make_solver(const Chain& chain, const std::vector<int>& rows, double position_tolerance,
                          double orientation_tolerance, double damping_gain, double damping, int max_iterations,
                          int max_restarts, double time_budget, bool within_limits) {
    NumericSettings s;
    if (rows.empty() || rows.size() > 6) throw std::invalid_argument("NumericSolver: expected 1 to 6 task rows");
    s.m = int(rows.size());
    for (int k = 0; k < s.m; ++k) {
        if (rows[k] < 0 || rows[k] > 5 || (k > 0 && rows[k] <= rows[k - 1]))
            throw std::invalid_argument("NumericSolver: expected ascending task rows in 0..5");
        s.rows[k] = rows[k];
    }
    if (max_iterations < 1 || max_restarts < 0 || !(time_budget >= 0.0))
        throw std::invalid_argument("NumericSolver: expected max_iterations >= 1, max_restarts >= 0, "
                                    "time_budget >= 0");
    s.position_tolerance = position_tolerance;
    s.orientation_tolerance = orientation_tolerance;
    s.damping_gain = damping_gain;
    s.damping = damping;
    s.max_iterations = max_iterations;
    s.max_restarts = max_restarts;
    s.time_budget = time_budget;
    s.within_limits = within_limits;
    return NumericSolver(chain, s);
}

const double* optional_seeds(const In& q0, std::size_t size, const char* message) {
    if (!q0.is_valid()) return nullptr;
    if (q0.size() != size) throw std::invalid_argument(message);
    return q0.data();
}

// What solve_one did: a result code (as ruckig's Result), the reason in the Python layer's words.
enum NumericStatus : int { kSolved = 0, kTargetNotFinite = 1, kSeedNotFinite = 2 };

// The solve of one target into q (n): (status, success, iterations, restarts, position_error,
// orientation_error); a status other than kSolved says which input has a non-finite value and
// nothing was solved (the Python layer names the values: checking here spares a NumPy reduction
// per call).
nb::tuple solve_one(const NumericSolver& solver, In T, In q0, std::uint64_t seed, Out q) {
    const std::size_t n = std::size_t(solver.chain.n);
    if (T.size() != 16 || q.size() != n) throw std::invalid_argument("solve: expected T (4, 4) and q (n,)");
    const double* seeds = optional_seeds(q0, n, "solve: expected q0 (n,) or None");
    const auto unsolved = [](NumericStatus status) { return nb::make_tuple(int(status), false, 0, 0, 0.0, 0.0); };
    if (!all_finite(T.data(), 16)) return unsolved(kTargetNotFinite);
    if (seeds && !all_finite(seeds, n)) return unsolved(kSeedNotFinite);
    const NumericResult r = solve(solver, pose_from_matrix(T.data()), seeds, item_seed(seed, 0), q.data());
    return nb::make_tuple(int(kSolved), r.success, r.iterations, r.restarts, r.position_error, r.orientation_error);
}

void solve_many(const NumericSolver& solver, In T, In q0, std::uint64_t seed, int threads, Out q,
                OutBool success, OutIndex iterations, OutIndex restarts, Out position_error,
                Out orientation_error) {
    const std::size_t N = T.size() / 16, n = std::size_t(solver.chain.n);
    if (T.size() != 16 * N || q.size() != n * N || success.size() != N || iterations.size() != N ||
        restarts.size() != N || position_error.size() != N || orientation_error.size() != N)
        throw std::invalid_argument("solve_batch: expected T (N, 4, 4), outputs q (N, n) and (N,) each");
    const double* seeds = optional_seeds(q0, n * N, "solve_batch: expected q0 (N, n) or None");
    solve_batch(solver, T.data(), seeds, N, seed, threads, q.data(), success.data(), iterations.data(),
                restarts.data(), position_error.data(), orientation_error.data());
}

// Resolved-rate control's step through J (6, n) for a twist (6,) into qd (n,), scaled to the
// velocity limits if inverse_max_velocity (n,) is given: (sigma_min, damping, scale).
nb::tuple rate_step_of(In J, In twist, double threshold, double max_damping, In inverse_max_velocity, Out qd) {
    const std::size_t n = qd.size();
    if (n == 0 || n > std::size_t(kMaxJoints) || J.ndim() != 2 || J.shape(0) != 6 || J.shape(1) != n ||
        twist.ndim() != 1 || twist.size() != 6)
        throw std::invalid_argument("rate_step: expected J (6, n), twist (6,) and qd (n,)");
    const double* limits = optional_seeds(inverse_max_velocity, n, "rate_step: expected inverse_max_velocity (n,)");
    const RateStepInfo info = rate_step(J.data(), int(n), twist.data(), threshold, max_damping, limits, qd.data());
    return nb::make_tuple(info.sigma_min, info.damping, info.scale);
}

double limit_scale_of(In qd, In inverse_max_velocity) {
    if (qd.size() != inverse_max_velocity.size())
        throw std::invalid_argument("limit_scale: expected qd and inverse_max_velocity (n,)");
    return limit_scale(qd.data(), inverse_max_velocity.data(), int(qd.size()));
}

#ifdef ARMKIT_TEST_BINDINGS  // bound for the tests only (CMake's ARMKIT_TEST_BINDINGS)
void project_into_limits(const NumericSolver& solver, Out q, Out sides) {
    if (q.size() != std::size_t(solver.chain.n) || sides.size() != q.size())
        throw std::invalid_argument("project: expected q and sides (n,)");
    project(solver.chain, q.data(), sides.data());
}

void damped_step_of(In J, In e, InIndex rows, In sides, double damping, Out dq) {
    const std::size_t n = dq.size(), m = rows.size();
    if (n == 0 || n > std::size_t(kMaxJoints) || J.size() != 6 * n || e.size() != 6 || sides.size() != n ||
        m == 0 || m > 6)
        throw std::invalid_argument("damped_step: expected J (6, n), e (6,), rows (m,), sides and dq (n,)");
    int r[6];
    for (std::size_t k = 0; k < m; ++k) {
        if (rows.data()[k] < 0 || rows.data()[k] > 5)
            throw std::invalid_argument("damped_step: expected rows in 0..5");
        r[k] = int(rows.data()[k]);
    }
    damped_step(J.data(), int(n), e.data(), r, int(m), sides.data(), damping, dq.data());
}
#endif

}  // namespace

void bind_numeric(nb::module_& m) {
    nb::class_<NumericSolver>(m, "NumericSolver",
                              "Levenberg-Marquardt IK with random restarts of one chain (armkit.ik.numeric).")
        .def(nb::new_(&make_solver), nb::arg("chain"), nb::arg("rows"), nb::arg("position_tolerance"),
             nb::arg("orientation_tolerance"), nb::arg("damping_gain"), nb::arg("damping"),
             nb::arg("max_iterations"), nb::arg("max_restarts"), nb::arg("time_budget"),
             nb::arg("within_limits"))
        .def("solve", &solve_one, nb::arg("T"), nb::arg("q0").none(), nb::arg("seed"), nb::arg("q"),
             "Solve fk(q) = T (4, 4) from q0 (n,) or the middle of the limits (None) into q (n,): "
             "(status, success, iterations, restarts, position_error, orientation_error), restart seeds "
             "from `seed`; status NUMERIC_SOLVED, or NUMERIC_TARGET_NOT_FINITE / NUMERIC_SEED_NOT_FINITE "
             "(nothing solved).")
        .def("solve_batch", &solve_many, nb::arg("T"), nb::arg("q0").none(), nb::arg("seed"), nb::arg("threads"),
             nb::arg("q"), nb::arg("success"), nb::arg("iterations"), nb::arg("restarts"),
             nb::arg("position_error"), nb::arg("orientation_error"), nb::call_guard<nb::gil_scoped_release>(),
             "solve() of T (N, 4, 4) from q0 (N, n) or None into the outputs, over threads (0: all); "
             "pose i draws its restart seeds from stream i of `seed` (stream 0 is solve()'s), so the results "
             "do not depend on the thread count unless the time budget cuts a solve short.")
        .def_prop_ro("n", [](const NumericSolver& s) { return s.chain.n; });
    m.def("rate_step", &rate_step_of, nb::arg("J"), nb::arg("twist"), nb::arg("threshold"), nb::arg("max_damping"),
          nb::arg("inverse_max_velocity").none(), nb::arg("qd"),
          "Resolved-rate joint velocities qd (n,) for a base-frame twist (6,) through J (6, n), damped least "
          "squares with rate_damping(sigma_min), scaled by limit_scale unless inverse_max_velocity is None: "
          "(sigma_min, damping, scale).");
    m.def("limit_scale", &limit_scale_of, nb::arg("qd"), nb::arg("inverse_max_velocity"),
          "The factor in (0, 1] that brings every |qd_i| * inverse_max_velocity_i to at most 1.");
    m.def("rate_damping", &rate_damping, nb::arg("sigma_min"), nb::arg("threshold"), nb::arg("max_damping"),
          "(1 - (sigma_min / threshold)^2) max_damping^2 below threshold, else 0.");
    m.attr("NUMERIC_SOLVED") = int(kSolved);
    m.attr("NUMERIC_TARGET_NOT_FINITE") = int(kTargetNotFinite);
    m.attr("NUMERIC_SEED_NOT_FINITE") = int(kSeedNotFinite);
#ifdef ARMKIT_TEST_BINDINGS
    m.def("project", &project_into_limits, nb::arg("solver"), nb::arg("q"), nb::arg("sides"),
          "Move q (n,) into the solver's limits in place; sides (n,) -1 / +1 at the lower / upper bound, else 0.");
    m.def("damped_step", &damped_step_of, nb::arg("J"), nb::arg("e"), nb::arg("rows"), nb::arg("sides"),
          nb::arg("damping"), nb::arg("dq"),
          "The Levenberg-Marquardt step dq (n,) for the task rows of J (6, n) and e (6,); joints held at "
          "a bound (sides -1 / +1) by the gradient are left out.");
#endif
}

}  // namespace armkit::bindings
