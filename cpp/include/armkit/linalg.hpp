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

}  // namespace armkit
