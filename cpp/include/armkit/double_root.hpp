// Roots of fk(q) = T beside a near-double root: the weak-direction search.
//
// Where two roots of a pose nearly meet (a UR5 with one line moved by 1e-8, at q5 = 1e-4: two
// solutions ~1e-6 apart), the Jacobian at and between them has a singular value of about the
// residual's curvature times their distance (1e-8 of the largest there), and Newton steps on
// the full pose stall between them: the damping holds back the step along the weak direction,
// and the normal equations J J^T square its singular value into rounding. A stalled candidate
// sat 2e-6 rad off its root at a residual of 9e-14.
//
// The search takes J's SVD at the candidate q: the strong directions get their Gauss-Newton
// step (linear), and along the weakest right singular vector v the residual projected onto the
// weakest left singular vector u is fitted by a quadratic (Lyapunov-Schmidt reduction),
//
//     g(t) = u . e(q + t v) ~ g0 + g1 t + g2 t^2,    g1 = -u . J v,  g2 by a second difference,
//
// whose real zeros (two; one, the vertex, where the pair has left the real line) are the two
// roots. Each is finished by the same step, taking the zero nearest to the point each time
// (on a simple root it is a Newton step, and beside its twin it does not stall), and kept
// where it reproduces T to rounding (kDoubleRootExact).
#pragma once

#include "armkit/chain.hpp"
#include "armkit/vec.hpp"

namespace armkit {

//: Roots at most that the search finds from one candidate (the two of a near-double root).
constexpr int kDoubleRoots = 2;

// The roots of fk(q) = T beside the candidate q (chain.n = 6), into roots (kDoubleRoots x 6),
// nearest to q first, each reproducing T to kDoubleRootExact times size and distinct (by
// kDuplicateTolerance); returns their number: 0 where the Jacobian at q is not nearly singular
// (its singular values' ratio above kNearDoubleRoot), the chain has not 6 joints, or no zero of
// the model ends on an exact root.
int near_double_roots(const Chain& chain, const Pose& T, const double* q, double size, double* roots);

}  // namespace armkit
