// The small dense linear algebra of the solvers: the damped least-squares step.
#pragma once

#include "armkit/tolerances.hpp"

namespace armkit {

//: Largest number of joints the core's fixed-size work arrays hold.
constexpr int kMaxJoints = 16;

// Solves A x = b for a symmetric positive definite A (k x k, row-major, lower triangle
// read and overwritten by the Cholesky factor); b (k) becomes x. False if A is not
// positive definite. Written out: for k <= 7 a LAPACK call costs more than the arithmetic.
bool cholesky_solve(double* A, double* b, int k);


// The damped least-squares (Levenberg-Marquardt) step dq (n) for the task rows `rows`
// (m of 0..5) of J (6 x n, row-major) and e (6). Joints held at a bound (sides[i] = -1 at
// the lower, +1 at the upper, 0 free) by the gradient J^T e get a zero column. Solves
// (J J^T + damping I) y = e, dq = J^T y when m <= n, else (J^T J + damping I) dq = J^T e;
// if that is not positive definite the damping becomes kSingularDamping trace(J^T J).
void damped_step(const double* J, int n, const double* e, const int* rows, int m, const double* sides,
                 double damping, double* dq);

// Resolved-rate control's damping lambda^2 for the Jacobian's smallest singular value:
// (1 - (sigma_min / threshold)^2) max_damping^2 below threshold, else 0 (Nakamura and
// Hanafusa 1986; Maciejewski and Klein 1988).
double rate_damping(double sigma_min, double threshold, double max_damping);

// The factor in (0, 1] that scales joint velocities qd (n) down together until every
// |qd_i| * inverse_max_velocity_i <= 1.
double limit_scale(const double* qd, const double* inverse_max_velocity, int n);

struct RateStepInfo {
    double sigma_min;  // smallest singular value of J
    double damping;    // lambda^2 used
    double scale;      // limit_scale applied (1 without limits)
};

// Resolved-rate control's joint velocities qd (n) for a twist (6) through J (6 x n,
// row-major): sigma_min from the eigenvalues of the small Gram matrix (J J^T for n >= 6,
// else J^T J), damped_step with every row and rate_damping(sigma_min) (kSingularDamping
// trace(J^T J) where that is zero and J is singular to rounding, kGramRounding), then scaled
// by limit_scale if inverse_max_velocity (n) is given (not null). Solved for J scaled by the
// power of two that brings its largest entry into [0.5, 1): exact, so the answer is the same
// for J of any size, and a J of 1e-300 (whose J J^T underflows) gets its true step, not 0.
RateStepInfo rate_step(const double* J, int n, const double* twist, double threshold, double max_damping,
                       const double* inverse_max_velocity, double* qd);

}  // namespace armkit
