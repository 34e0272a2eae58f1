// Singular poses: the member of a family of solutions nearest to a reference.
// Header-only: used by ik_solve.hpp.
//
// At a singular pose the closed form returns one member of a family (e.g. q4 = 0 for an
// aligned wrist, where only q4 + q6 is defined). Where two revolute axes are one line the
// family is exactly a line in joint space, walked to its point nearest to near first. The
// family runs along the null space of the Jacobian. A one-parameter family is then searched
// whole: the line through q along its null vector (two whole turns of its fastest joint,
// either way), and the curve itself, traced both ways by predictor (tangent step) and corrector
// (Levenberg-Marquardt projection) steps until it closes or has run several turns (a joint
// axis through a spherical wrist's centre frees that joint, and the wrist follows it: a curved
// family). Last, local steps along the null space (weighted), each put back exactly on the
// solution set, while the distance to near falls. Distances are taken after the 2 pi wrap
// into the limits; a point that would leave the limits a representative was inside is not taken.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "armkit/chain.hpp"
#include "armkit/fk.hpp"
#include "armkit/linalg.hpp"
#include "armkit/tolerances.hpp"
#include "armkit/transform.hpp"

namespace armkit {

//: Steps along a singular family towards near (one where the family is a line in joint space).
constexpr int kFamilySteps = 10;
//: Points sampled along a family's line (two whole turns of its fastest joint).
constexpr int kFamilySamples = 257;
//: The projection back onto the solution set: iterations (its residual: kProjectionTolerance).
constexpr int kProjectionIterations = 10;
//: Tracing a curved family: the step along its tangent [rad or m] and the length traced
//: either way (several whole turns); the smallest step tried: kTraceSmallestStep.
constexpr double kTraceStep = 0.1;
constexpr double kTraceLength = 6.0 * kTwoPi;
//: Local steps towards near that were cut to a trace step, taken besides kFamilySteps: up to
//: 6.4 rad or m of travel along the family.
constexpr int kShortenedSteps = 64;

// Singular values s (n) and right singular vectors V (n x n, row-major, column j for s[j])
// of J (6 x n, row-major, n <= 6) by one-sided (Hestenes) Jacobi rotations of J's columns.
inline void jacobi_svd(const double* J, int n, double* s, double* V) {
    double A[6 * kMaxJoints];
    for (int a = 0; a < 6 * n; ++a) A[a] = J[a];
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) V[a * n + b] = a == b ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 60; ++sweep) {
        bool rotated = false;
        for (int p = 0; p < n - 1; ++p)
            for (int q = p + 1; q < n; ++q) {
                double alpha = 0.0, beta = 0.0, gamma = 0.0;
                for (int r = 0; r < 6; ++r) {
                    alpha += A[r * n + p] * A[r * n + p];
                    beta += A[r * n + q] * A[r * n + q];
                    gamma += A[r * n + p] * A[r * n + q];
                }
                if (gamma == 0.0 || std::fabs(gamma) <= 1e-15 * std::sqrt(alpha * beta)) continue;
                rotated = true;
                const double zeta = (beta - alpha) / (2.0 * gamma);
                const double t = (zeta >= 0.0 ? 1.0 : -1.0) / (std::fabs(zeta) + std::sqrt(1.0 + zeta * zeta));
                const double c = 1.0 / std::sqrt(1.0 + t * t), sn = c * t;
                for (int r = 0; r < 6; ++r) {
                    const double x = A[r * n + p], y = A[r * n + q];
                    A[r * n + p] = c * x - sn * y;
                    A[r * n + q] = sn * x + c * y;
                }
                for (int r = 0; r < n; ++r) {
                    const double x = V[r * n + p], y = V[r * n + q];
                    V[r * n + p] = c * x - sn * y;
                    V[r * n + q] = sn * x + c * y;
                }
            }
        if (!rotated) break;
    }
    for (int j = 0; j < n; ++j) {
        double total = 0.0;
        for (int r = 0; r < 6; ++r) total += A[r * n + j] * A[r * n + j];
        s[j] = std::sqrt(total);
    }
}

// Levenberg-Marquardt steps (no limits; damping 0.1 cost + 1e-9, as armkit.ik.numeric) from
// q (n, in place) until fk(q) reproduces T to kProjectionTolerance (true), or it stalls.
inline bool project_onto_solutions(const Chain& chain, const Pose& T, double* q) {
    static constexpr int rows[6] = {0, 1, 2, 3, 4, 5};
    const double free[kMaxJoints] = {};
    Vec3 axes[kMaxJoints], points[kMaxJoints];
    double J[6 * kMaxJoints], e[6], dq[kMaxJoints];
    double reference = std::numeric_limits<double>::infinity();
    int since = 0;
    for (int step = 1; step <= kProjectionIterations; ++step) {
        const Pose F = joint_axes(chain, q, axes, points);
        pose_error(T, F, e);
        const double position = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        const double orientation = e[3] * e[3] + e[4] * e[4] + e[5] * e[5];
        const double cost = 0.5 * (position + orientation);
        if (position <= kProjectionTolerance * kProjectionTolerance &&
            orientation <= kProjectionTolerance * kProjectionTolerance)
            return true;
        if (cost < 0.5 * reference) {
            reference = cost, since = 0;
        } else if (++since >= 3 || !std::isfinite(cost)) {
            return false;
        }
        if (step == kProjectionIterations) break;
        jacobian_from_axes(F, axes, points, chain.prismatic.data(), chain.n, J);
        damped_step(J, chain.n, e, rows, 6, free, 0.1 * cost + 1e-9, dq);
        for (int j = 0; j < chain.n; ++j) q[j] += dq[j];
    }
    return false;
}

// The revolute values of q (n) shifted by whole turns into the limits (widened by
// tolerance; reference near), into out.
inline void wrap_towards(const Chain& chain, const double* q, const double* near, double* out,
                         double tolerance = kLimitTolerance) {
    for (int j = 0; j < chain.n; ++j)
        out[j] = chain.prismatic[j] ? q[j]
                                    : wrap_angle_into_limits(q[j], chain.lower[j], chain.upper[j], near[j], tolerance);
}

// Weighted squared distance of q (n) to near after the wrap (limits widened by
// tolerance); infinite where the wrapped q leaves the limits and keep_inside.
inline double family_distance(const Chain& chain, const double* q, const double* near, const double* weights,
                              bool keep_inside, double tolerance = kLimitTolerance) {
    double moved[kMaxJoints];
    wrap_towards(chain, q, near, moved, tolerance);
    double far = 0.0;
    for (int j = 0; j < chain.n; ++j) {
        const double d = weights[j] * (moved[j] - near[j]);
        far += d * d;
    }
    return chain.within_limits(moved) || !keep_inside ? far : std::numeric_limits<double>::infinity();
}

// Weighted squared distance of q (n) to near with revolute differences taken modulo 2 pi,
// the limits aside.
inline double circular_distance(const Chain& chain, const double* q, const double* near, const double* weights) {
    double far = 0.0;
    for (int j = 0; j < chain.n; ++j) {
        const double d = weights[j] * (chain.prismatic[j] ? q[j] - near[j] : wrap_angle(q[j] - near[j]));
        far += d * d;
    }
    return far;
}

// Two revolute joints i < j whose axes are one line at q (s = +1 along, -1 against) leave
// the pose unchanged along q + t (e_i - s e_j), for every t: turning joint i about that line
// keeps joint j's axis on it, so the two turns cancel. Moves q (n) along each such line to
// its point nearest to near (over the whole turns of both joints); exact, no projection
// where the two axes are one line to kNullSpace.
// This is the family of an aligned wrist even where the line search below cannot see it
// (a second singular direction at q makes the null space two-dimensional). Axes within
// kNearlyCollinear of one line are moved along it too, and the point is then projected
// onto the solution set and taken only if that succeeds and brings it nearer: a member the
// closed form placed ~1e-7 off the crossing of two families (a multiple root) lies on the
// other family, where the two axes are not quite one line.
inline void move_along_collinear_pairs(const Chain& chain, const Pose& T, double* q, const double* near,
                                       const double* weights, bool inside) {
    const int n = chain.n;
    Vec3 axes[kMaxJoints], points[kMaxJoints];
    joint_axes(chain, q, axes, points);
    double size = 1.0;
    for (int j = 0; j < n; ++j) size = std::fmax(size, 1.0 + norm(points[j]));
    for (int i = 0; i < n; ++i) {
        for (int j = i + 1; j < n; ++j) {
            if (chain.prismatic[i] || chain.prismatic[j]) continue;
            const Vec3 d = points[j] - points[i];
            const double skew = std::fmax(norm(cross(axes[i], axes[j])), norm(cross(axes[i], d)) / size);
            if (skew > kNearlyCollinear) continue;
            const double sj = dot(axes[i], axes[j]) > 0 ? 1.0 : -1.0;
            // minimise wi^2 (t - a)^2 + wj^2 (t - b)^2 over whole turns of a and b
            const double wi = weights[i] * weights[i], wj = weights[j] * weights[j];
            const double here = family_distance(chain, q, near, weights, inside);
            double best = here, best_t = 0.0;
            for (int ki = -2; ki <= 2; ++ki)
                for (int kj = -2; kj <= 2; ++kj) {
                    const double a = near[i] + kTwoPi * ki - q[i], b = sj * (q[j] - near[j] - kTwoPi * kj);
                    const double t = (wi * a + wj * b) / (wi + wj);
                    double point[kMaxJoints];
                    for (int m = 0; m < n; ++m) point[m] = q[m];
                    point[i] += t;
                    point[j] -= sj * t;
                    const double far = family_distance(chain, point, near, weights, inside);
                    if (far < best - 1e-24) best = far, best_t = t;
                }
            if (best_t == 0.0) continue;
            double moved[kMaxJoints];
            for (int m = 0; m < n; ++m) moved[m] = q[m];
            moved[i] += best_t;
            moved[j] -= sj * best_t;
            if (skew > kNullSpace && !(project_onto_solutions(chain, T, moved) &&
                                       family_distance(chain, moved, near, weights, inside) < here - 1e-24))
                continue;
            wrap_towards(chain, moved, near, q);
            joint_axes(chain, q, axes, points);  // the move turned the axes after joint i
        }
    }
}

// The null space of the Jacobian at q (n): the right singular vectors V (n x n, row-major)
// and the columns null (count returned) whose singular values are within kNullSpace of the
// largest.
inline int null_space(const Chain& chain, const double* q, double* V, int* null, double fraction = kNullSpace) {
    const int n = chain.n;
    Vec3 axes[kMaxJoints], points[kMaxJoints];
    double J[6 * kMaxJoints], s[kMaxJoints];
    jacobian_from_axes(joint_axes(chain, q, axes, points), axes, points, chain.prismatic.data(), n, J);
    jacobi_svd(J, n, s, V);
    double largest = 0.0;
    int count = 0;
    for (int j = 0; j < n; ++j) largest = std::fmax(largest, s[j]);
    for (int j = 0; j < n; ++j)
        if (s[j] <= fraction * largest) null[count++] = j;
    return count;
}


// Whether the Jacobian at q (n) is singular (a null space within kNullSpace). Every member of
// a family is: a walk along one that lands on a configuration where it is not has left the
// family for an isolated solution of another branch (a step across a near-singular
// direction, see kNearCrossing, projected onto another elbow's solution).
inline bool singular_at(const Chain& chain, const double* q) {
    double V[kMaxJoints * kMaxJoints];
    int null[kMaxJoints];
    return null_space(chain, q, V, null) > 0;
}

// Whether the solution q (n) of T lies on a family: its Jacobian has a null space, and a
// step of kFamilyProbe along it, put back onto the solution set, stays a solution that far
// from q (the solution set continues there). An isolated singular solution, such as the
// double root at a fold, draws the step back, or the projection stalls.
inline bool on_a_family(const Chain& chain, const Pose& T, const double* q) {
    double V[kMaxJoints * kMaxJoints];
    int null[kMaxJoints];
    if (null_space(chain, q, V, null) == 0) return false;
    double x[kMaxJoints];
    for (int j = 0; j < chain.n; ++j) x[j] = q[j] + kFamilyProbe * V[j * chain.n + null[0]];
    if (!project_onto_solutions(chain, T, x)) return false;
    double moved = 0.0;
    for (int j = 0; j < chain.n; ++j) moved += (x[j] - q[j]) * (x[j] - q[j]);
    return std::sqrt(moved) >= 0.5 * kFamilyProbe;
}

// The unit null vector of the Jacobian at q (n) into v, when the null space is one line
// (false otherwise).
inline bool family_tangent(const Chain& chain, const double* q, double* v) {
    double V[kMaxJoints * kMaxJoints];
    int null[kMaxJoints];
    if (null_space(chain, q, V, null) != 1) return false;
    for (int j = 0; j < chain.n; ++j) v[j] = V[j * chain.n + null[0]];
    return true;
}

// Traces the one-parameter family through q (n, on the solution set of T) both ways and
// moves q to the traced point nearest to near (weighted, circular_distance: the limits
// aside, so that a member on a limit, where the wrapped distance jumps, is approached from
// both sides; its revolute joints within pi of near's, for the descent that follows). The first step
// goes along the null vector at q, each later one along the secant of the last step; each
// is projected back onto the solution set, and a failed projection (or one that jumps
// more than twice the step, or back) halves the step. A direction ends where the curve
// closes (back within a step of q: the other direction is then not needed), after
// kTraceLength, or where the step falls below kTraceSmallestStep.
inline void trace_family(const Chain& chain, const Pose& T, double* q, const double* near, const double* weights) {
    const int n = chain.n;
    double start_tangent[kMaxJoints];
    if (!family_tangent(chain, q, start_tangent)) return;
    double best_q[kMaxJoints];
    for (int j = 0; j < n; ++j) best_q[j] = q[j];
    double best = circular_distance(chain, q, near, weights);
    bool closed = false;
    for (const double way : {1.0, -1.0}) {
        if (closed) break;
        double at[kMaxJoints], tangent[kMaxJoints];
        for (int j = 0; j < n; ++j) at[j] = q[j], tangent[j] = way * start_tangent[j];
        double step = kTraceStep, travelled = 0.0;
        while (travelled < kTraceLength && step >= kTraceSmallestStep) {
            double next[kMaxJoints];
            for (int j = 0; j < n; ++j) next[j] = at[j] + step * tangent[j];
            if (!project_onto_solutions(chain, T, next)) {
                step *= 0.5;
                continue;
            }
            double along = 0.0, moved = 0.0;
            for (int j = 0; j < n; ++j) {
                along += (next[j] - at[j]) * tangent[j];
                moved += (next[j] - at[j]) * (next[j] - at[j]);
            }
            moved = std::sqrt(moved);
            if (moved > 2.0 * step || along <= 0.0) {  // jumped to another branch, or back
                step *= 0.5;
                continue;
            }
            double home = 0.0;
            for (int j = 0; j < n; ++j) {
                tangent[j] = (next[j] - at[j]) / moved;
                at[j] = next[j];
                const double d = chain.prismatic[j] ? at[j] - q[j] : wrap_angle(at[j] - q[j]);
                home += d * d;
            }
            travelled += moved;
            const double far = circular_distance(chain, at, near, weights);
            if (far < best) {
                best = far;
                for (int j = 0; j < n; ++j) best_q[j] = at[j];
            }
            closed = travelled > 2.0 * kTraceStep && std::sqrt(home) < kTraceStep;
            if (closed) break;
            step = std::fmin(kTraceStep, 2.0 * step);
        }
    }
    for (int j = 0; j < n; ++j) q[j] = chain.prismatic[j] ? best_q[j] : near[j] + wrap_angle(best_q[j] - near[j]);
}


// Whether target (n), the projection of aimed, a point reached from q along the family,
// stays on q's family (see kStayOnFamily): the projection moved it by at most kStayOnFamily
// of the way aimed, or of longest where that is shorter.
inline bool stays_on_family(const Chain& chain, const double* q, const double* aimed, const double* target,
                            double longest = std::numeric_limits<double>::infinity()) {
    double aim = 0.0, moved = 0.0;
    for (int j = 0; j < chain.n; ++j) {
        aim += (aimed[j] - q[j]) * (aimed[j] - q[j]);
        moved += (target[j] - aimed[j]) * (target[j] - aimed[j]);
    }
    return moved <= kStayOnFamily * kStayOnFamily * std::fmin(aim, longest * longest);
}

// Whether target (n, a solution of T) is reached from q (n) along the solution set: the
// chord from q to it in kCrossingSubsteps substeps, each from the last point put back onto
// the solutions, must end within kStayOnFamily of the chord's length from target. Across
// the kink where two families cross, the path bends through the crossing onto the other
// family; from one of two separate families (two elbows of a free shoulder joint within a
// step of each other) the projections keep it on its own, and it ends a gap away.
inline bool reached_along_solutions(const Chain& chain, const Pose& T, const double* q, const double* target) {
    constexpr int kCrossingSubsteps = 8;
    const int n = chain.n;
    double at[kMaxJoints], step[kMaxJoints];
    for (int j = 0; j < n; ++j) at[j] = q[j], step[j] = (target[j] - q[j]) / kCrossingSubsteps;
    bool on = true;  // the last projection reached the solutions (one beside the crossing may stall)
    for (int k = 0; k < kCrossingSubsteps; ++k) {
        for (int j = 0; j < n; ++j) at[j] += step[j];
        on = project_onto_solutions(chain, T, at);
    }
    return on && stays_on_family(chain, q, target, at);
}

// Moves q (n, on the solution set of T) towards near: the line through q along a one-line
// null space (sampled, if sample_line: not after the trace, which has searched the curve),
// then local null-space steps while the distance falls, then the collinear pairs' lines
// again (the local steps may end on another pair's line: two families that cross).
inline void descend_family(const Chain& chain, const Pose& T, double* q, const double* near, const double* weights,
                           bool inside, bool sample_line) {
    const int n = chain.n;
    bool wider = false;  // this step spans the directions of a nearby crossing too
    int shortened = 0;  // steps cut to a trace step (they do not count against kFamilySteps)
    for (int step = 0; step < kFamilySteps + std::min(shortened, kShortenedSteps); ++step) {
        double V[kMaxJoints * kMaxJoints];
        int null[kMaxJoints];  // the columns of V spanning the null space
        const int c = null_space(chain, q, V, null, wider ? kNearCrossing : kNullSpace);
        if (c == 0) break;
        const bool line = sample_line && step == 0 && c == 1;
        double target[kMaxJoints];
        if (line) {  // the line through q, up to two whole turns of its fastest joint either way
            double v[kMaxJoints], biggest = 0.0;
            for (int j = 0; j < n; ++j) {
                v[j] = V[j * n + null[0]];
                if (std::fabs(v[j]) > std::fabs(biggest)) biggest = v[j];
            }
            for (int j = 0; j < n; ++j) v[j] /= biggest;
            double best = 0.0, point[kMaxJoints];
            for (int a = 0; a < kFamilySamples; ++a) {  // the first nearest point, t from -2 pi to 2 pi
                const double t = a == kFamilySamples - 1 ? kTwoPi : -kTwoPi + a * (2.0 * kTwoPi / (kFamilySamples - 1));
                for (int j = 0; j < n; ++j) point[j] = q[j] + t * v[j];
                const double d = family_distance(chain, point, near, weights, inside);
                if (a == 0 || d < best) {
                    best = d;
                    for (int j = 0; j < n; ++j) target[j] = point[j];
                }
            }
        } else {  // q + N (N^T W N)^-1 N^T W (near - q), W = diag(weights^2)
            double A[kMaxJoints * kMaxJoints], b[kMaxJoints];
            for (int a = 0; a < c; ++a) {
                for (int d = 0; d <= a; ++d) {
                    double total = 0.0;
                    for (int j = 0; j < n; ++j)
                        total += V[j * n + null[a]] * weights[j] * weights[j] * V[j * n + null[d]];
                    A[a * c + d] = total;
                }
                double total = 0.0;
                for (int j = 0; j < n; ++j) total += V[j * n + null[a]] * weights[j] * weights[j] * (near[j] - q[j]);
                b[a] = total;
            }
            if (!cholesky_solve(A, b, c)) break;
            double length = 0.0;
            for (int j = 0; j < n; ++j) {
                double total = 0.0;
                for (int a = 0; a < c; ++a) total += V[j * n + null[a]] * b[a];
                target[j] = total;
                length += total * total;
            }
            // at most a trace step at a time: projected from farther along a curved family,
            // the step may land on another family of the pose (a free shoulder joint's: the
            // other elbow's, and the listing lost this elbow)
            const double shorten = std::fmin(1.0, kTraceStep / std::sqrt(length));
            shortened += shorten < 1.0;
            for (int j = 0; j < n; ++j) target[j] = q[j] + shorten * target[j];
        }
        double aimed[kMaxJoints];
        for (int j = 0; j < n; ++j) aimed[j] = target[j];
        // a point sampled along the line is a member where the family is a line; where it
        // is curved, its projection from farther off than a trace step may land on another
        // family of the pose (the other wrist of a free shoulder joint: the listing lost it)
        const bool solved = project_onto_solutions(chain, T, target) &&
                            stays_on_family(chain, q, aimed, target, kTraceStep) && singular_at(chain, target) &&
                            (!wider || reached_along_solutions(chain, T, q, target));
        if (!(solved && family_distance(chain, target, near, weights, inside) <
                            family_distance(chain, q, near, weights, inside) - 1e-24)) {
            if (line) continue;  // the sampled point did not help: go on with local steps
            if (wider) break;
            wider = true;  // stuck: try once more across a crossing the trace stopped short of
            continue;
        }
        wider = false;
        wrap_towards(chain, target, near, q);
    }
    move_along_collinear_pairs(chain, T, q, near, weights, inside);
}

// Moves q (n, a solution of T at a singular pose) to the member of its family nearest to
// near (n), weights (n): along the lines of collinear axis pairs, then the better of the
// descent from there and the descent from the nearest point of the traced curve (a local
// descent alone stops at the first local minimum of the wrapped distance; the trace alone
// stops where the family branches).
inline void walk_family(const Chain& chain, const Pose& T, double* q, const double* near, const double* weights) {
    const int n = chain.n;
    const bool inside = chain.within_limits(q);
    move_along_collinear_pairs(chain, T, q, near, weights, inside);
    double traced[kMaxJoints];
    for (int j = 0; j < n; ++j) traced[j] = q[j];
    trace_family(chain, T, traced, near, weights);
    // where the curve passes within a step of near, near itself put onto the solution set
    double projected[kMaxJoints];
    for (int j = 0; j < n; ++j) projected[j] = near[j];
    const bool on_curve = circular_distance(chain, traced, near, weights) <= kTraceStep * kTraceStep &&
                          project_onto_solutions(chain, T, projected) &&
                          circular_distance(chain, projected, traced, weights) <= 4.0 * kTraceStep * kTraceStep;
    descend_family(chain, T, q, near, weights, inside, true);
    descend_family(chain, T, traced, near, weights, inside, false);  // the trace has searched the curve
    if (family_distance(chain, traced, near, weights, inside) < family_distance(chain, q, near, weights, inside))
        for (int j = 0; j < n; ++j) q[j] = traced[j];
    if (on_curve && family_distance(chain, projected, near, weights, inside) < family_distance(chain, q, near, weights, inside))
        wrap_towards(chain, projected, near, q);
}

}  // namespace armkit


