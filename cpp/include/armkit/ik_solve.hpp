// The closed-form IK pipeline of many poses: every candidate of pose_candidates wrapped
// into the joint limits, verified by FK (a rough one refined), flagged and ranked by
// distance to a reference configuration. Header-only: used by bind_solve.cpp.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "armkit/closed_form.hpp"
#include "armkit/double_root.hpp"
#include "armkit/fk.hpp"
#include "armkit/ik_family.hpp"
#include "armkit/tolerances.hpp"
#include "armkit/transform.hpp"

namespace armkit {


// Indices of the per-candidate flags (the last axis of Found::flags).
enum FoundFlag : int { kValid = 0, kKeep = 1, kInside = 2, kFamily = 3, kFlags = 4 };

// The candidates of N poses, k per pose (rows of C-ordered arrays):
//   q (N, k, n) joint values; errors (N, k, 2) FK residual [m, rad] (NaN: not verified);
//   flags (N, k, 4): valid (a solution of the closed form), keep (also reproduces the
//   pose to kSolutionTolerance), inside (the limits), family (as the closed form flags
//   it); count (N): the usable candidates (kept, and inside if asked), sorted first;
//   size: the arm's (1 + its largest coordinate [m]), for the bars relative to it.
struct Found {
    int k = 0, n = 0;
    double* q = nullptr;
    double* errors = nullptr;
    bool* flags = nullptr;
    std::int64_t* count = nullptr;
    double size = 1.0;

    double* q_of(std::size_t i, int s) const { return q + (i * k + s) * n; }
    double* errors_of(std::size_t i, int s) const { return errors + (i * k + s) * 2; }
    bool* flags_of(std::size_t i, int s) const { return flags + (i * k + s) * kFlags; }
};

// Whether q (n) is inside the limits (to kLimitTolerance); its distance |w * (q - near)|.
inline bool inside_and_distance(const Chain& chain, const double* q, const double* near, const double* weights,
                                double& distance) {
    bool inside = true;
    double total = 0.0;
    for (int j = 0; j < chain.n; ++j) {
        inside = inside && chain.within_limit(j, q[j]);
        const double d = weights[j] * (q[j] - near[j]);
        total += d * d;
    }
    distance = std::sqrt(total);
    return inside;
}

// order (k): indices that sort values (k), equal ones in their original order (insertion sort).
inline void stable_order(const double* values, int k, int* order) {
    for (int a = 0; a < k; ++a) order[a] = a;
    for (int a = 1; a < k; ++a) {
        const int current = order[a];
        int b = a;
        while (b > 0 && values[order[b - 1]] > values[current]) {
            order[b] = order[b - 1];
            --b;
        }
        order[b] = current;
    }
}

// Flag pose i's candidates (keep, inside), count the usable ones (keep, and inside if
// within_limits) and sort them first, nearest to near (n) first.
inline void rank_pose(const Chain& chain, const Found& f, std::size_t i, const double* near,
                      const double* weights, bool within_limits) {
    const int k = f.k, n = f.n;
    double distance[kMaxCandidates];
    std::int64_t count = 0;
    for (int s = 0; s < k; ++s) {
        bool* flags = f.flags_of(i, s);
        const double* errors = f.errors_of(i, s);
        flags[kKeep] = flags[kValid] && errors[0] <= kSolutionTolerance && errors[1] <= kSolutionTolerance;
        flags[kInside] = inside_and_distance(chain, f.q_of(i, s), near, weights, distance[s]);
        const bool usable = flags[kKeep] && (flags[kInside] || !within_limits);
        if (!usable) distance[s] = std::numeric_limits<double>::infinity();
        count += usable;
    }
    f.count[i] = count;
    int order[kMaxCandidates];
    stable_order(distance, k, order);
    double q[kMaxCandidates * kMaxJoints], errors[kMaxCandidates * 2];
    bool flags[kMaxCandidates * kFlags];
    for (int s = 0; s < k; ++s) {  // the rows in that order, through copies
        const int r = order[s];
        for (int j = 0; j < n; ++j) q[s * n + j] = f.q_of(i, r)[j];
        for (int e = 0; e < 2; ++e) errors[s * 2 + e] = f.errors_of(i, r)[e];
        for (int g = 0; g < kFlags; ++g) flags[s * kFlags + g] = f.flags_of(i, r)[g];
    }
    for (int s = 0; s < k; ++s) {
        for (int j = 0; j < n; ++j) f.q_of(i, s)[j] = q[s * n + j];
        for (int e = 0; e < 2; ++e) f.errors_of(i, s)[e] = errors[s * 2 + e];
        for (int g = 0; g < kFlags; ++g) f.flags_of(i, s)[g] = flags[s * kFlags + g];
    }
}

// The configuration q (n), a solution of pose i's target T, as a valid candidate of pose i in
// its last invalid row (wrapped into the limits towards near, with its residuals), where there
// is one: the twin of a near-double root that the case's equations lost (rank_pose then keeps
// it, drop_twins drops it where it is listed already).
inline void add_candidate(const Chain& chain, const Pose& T, const Found& f, std::size_t i, const double* q,
                          const double* near) {
    int row = f.k - 1;
    while (row >= 0 && f.flags_of(i, row)[kValid]) --row;
    if (row < 0) return;
    double* out = f.q_of(i, row);
    for (int j = 0; j < f.n; ++j)
        out[j] = chain.prismatic[j] ? q[j] : wrap_angle_into_limits(q[j], chain.lower[j], chain.upper[j], near[j]);
    double* errors = f.errors_of(i, row);
    pose_residual(T, tool_pose(chain, out), errors[0], errors[1]);
    bool* flags = f.flags_of(i, row);
    flags[kValid] = true;
    flags[kFamily] = false;
}

// Candidate s of pose i, with its residuals in f above kRefineAbove: Levenberg-Marquardt
// steps onto the solution set (project_onto_solutions), taken where they lower the residual
// without moving a joint further than kRefineMove (kRefineFamilyMove for a family's
// representative); where it is still rough, the nearest root of the weak-direction search
// (near_double_roots: the Jacobian nearly singular there, the row off its root along the weakest
// direction, as far as 3e-2 beside an aligned wrist, where the steps stall; the other root of
// the pair, where the search finds one, goes into a free row: add_candidate). Revolute joints are
// wrapped into the limits again (towards near: a joint the steps moved across a limit it stood
// on, by rounding, goes to the other end if that is nearer).
inline void refine(const Chain& chain, const Pose& T, const Found& f, std::size_t i, int s, const double* near) {
    double* errors = f.errors_of(i, s);
    double* q = f.q_of(i, s);
    double moved[kMaxJoints];
    for (int j = 0; j < f.n; ++j) moved[j] = q[j];
    project_onto_solutions(chain, T, moved);
    double position, angle, far = 0.0;
    pose_residual(T, tool_pose(chain, moved), position, angle);
    for (int j = 0; j < f.n; ++j) far = std::fmax(far, std::fabs(moved[j] - q[j]));
    const double reach = f.flags_of(i, s)[kFamily] ? kRefineFamilyMove : kRefineMove;
    const bool taken = position + angle < errors[0] + errors[1] && far < reach;
    if (!taken) std::copy(q, q + f.n, moved);
    double roots[kDoubleRoots * 6];
    const int found = !taken || position > kRefineAbove || angle > kRefineAbove
                          ? near_double_roots(chain, T, moved, f.size, roots) : 0;
    if (found > 0) {
        std::copy(roots, roots + 6, moved);
        pose_residual(T, tool_pose(chain, moved), position, angle);
    } else if (!taken) {
        return;
    }
    for (int j = 0; j < f.n; ++j)
        q[j] = chain.prismatic[j] ? moved[j] : wrap_angle_into_limits(moved[j], chain.lower[j], chain.upper[j], near[j]);
    errors[0] = position, errors[1] = angle;
    if (found > 1) add_candidate(chain, T, f, i, roots + 6, near);
}

// FK residuals of candidate s of pose i (target T) into f, refined if rough (see refine);
// whether it reproduces the pose. A rough candidate the case did not flag is flagged family
// where, refined, it lies on one (on_a_family: near a family the case's equations are
// ill-conditioned, and it may place a member anywhere along it without seeing the family).
// F: its tool pose, if already computed (tool_poses for all of a pose's candidates at once).
inline bool verify(const Chain& chain, const Pose& T, const Found& f, std::size_t i, int s, const double* near,
                   const Pose* F = nullptr) {
    double* errors = f.errors_of(i, s);
    pose_residual(T, F ? *F : tool_pose(chain, f.q_of(i, s)), errors[0], errors[1]);
    const bool rough = errors[0] > kRefineAbove || errors[1] > kRefineAbove;
    if (rough) refine(chain, T, f, i, s, near);
    const bool solution = errors[0] <= kSolutionTolerance && errors[1] <= kSolutionTolerance;
    bool* flags = f.flags_of(i, s);
    if (rough && solution && !flags[kFamily]) flags[kFamily] = on_a_family(chain, T, f.q_of(i, s));
    return solution;
}

// At a singular pose: each kept family representative of pose i moved to the member of its
// family nearest to near (ik_family.hpp), with its new residuals; ranked again if one moved.
inline void nearest_family_members(const Chain& chain, const Pose& T, const Found& f, std::size_t i,
                                   const double* near, const double* weights, bool within_limits) {
    bool moved = false;
    for (int s = 0; s < f.k; ++s) {
        if (!(f.flags_of(i, s)[kFamily] && f.flags_of(i, s)[kKeep])) continue;
        double* q = f.q_of(i, s);
        double before[kMaxJoints];
        for (int j = 0; j < f.n; ++j) before[j] = q[j];
        walk_family(chain, T, q, near, weights);
        bool changed = false;
        for (int j = 0; j < f.n; ++j) changed = changed || q[j] != before[j];
        if (changed) verify(chain, T, f, i, s, near);
        moved = moved || changed;
    }
    if (moved) rank_pose(chain, f, i, near, weights, within_limits);
}

// Kept candidates of pose i that refinement or a family walk brought onto an earlier kept
// one (equal to kDuplicateTolerance, modulo 2 pi) are dropped (no longer valid); ranked
// again if one was.
inline void drop_twins(const Chain& chain, const Found& f, std::size_t i, const double* near, const double* weights,
                       bool within_limits) {
    bool keep[kMaxCandidates], twin[kMaxCandidates];
    for (int s = 0; s < f.k; ++s) keep[s] = f.flags_of(i, s)[kKeep];
    mark_duplicates(f.q_of(i, 0), f.k, f.n, keep, chain.prismatic.data(), twin);
    bool dropped = false;
    for (int s = 0; s < f.k; ++s) {
        if (!twin[s]) continue;
        f.flags_of(i, s)[kValid] = f.flags_of(i, s)[kKeep] = false;
        dropped = true;
    }
    if (dropped) rank_pose(chain, f, i, near, weights, within_limits);
}

// The distance |w * (q - near)| of q (n, wrapped into the limits) once refined, given the
// distance as it is: a revolute joint within kRefineMove of a limit (a joint at exactly
// +-pi, placed by the closed form 1e-9 beyond the other end at an ill-conditioned pose)
// may be wrapped to near's side after refinement (refine), so it is measured from there.
inline double seam_distance(const Chain& chain, const double* q, const double* near, const double* weights,
                            double distance) {
    bool seam = false;
    for (int j = 0; j < chain.n && !seam; ++j)
        seam = !chain.prismatic[j] &&
               (std::fabs(q[j] - chain.lower[j]) <= kRefineMove || std::fabs(q[j] - chain.upper[j]) <= kRefineMove);
    return seam ? std::fmin(distance, std::sqrt(family_distance(chain, q, near, weights, false, kRefineMove))) : distance;
}

// Candidates of poses [begin, end) of T (N x 4 x 4), wrapped into the limits (reference
// near, (N x n)), with their FK residuals, ranked: into f; returns the poses without a
// usable candidate. near_stride is n, or 0 when one reference serves every pose.
//
// nearest: only the nearest candidate that reproduces the pose is wanted, so the
// candidates are put through FK nearest first until one does and no unverified one can
// be nearer (refinement may move a joint at a +-pi limit to near's side: seam_distance;
// the others' residuals stay NaN: not kept); family representatives always are (they are
// moved along their family towards near), and if none does, all are (the caller's error
// message needs them).
inline long long solve_poses(const ClosedForm& cf, const double* T, const double* near, std::size_t near_stride,
                             const double* weights, bool within_limits, bool nearest, const Found& f,
                             std::size_t begin, std::size_t end) {
    const Chain& chain = cf.chain;
    const int k = f.k, n = f.n;
    constexpr double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    long long empty = 0;
    double distance[kMaxCandidates];
    bool valid[kMaxCandidates], family[kMaxCandidates];
    for (std::size_t i = begin; i < end; ++i) {
        const Pose target = pose_from_matrix(T + 16 * i);
        const double* reference = near + near_stride * i;
        pose_candidates(cf, target, f.q_of(i, 0), valid, family);
        for (int s = 0; s < k; ++s) {
            bool* flags = f.flags_of(i, s);
            flags[kValid] = valid[s];
            flags[kFamily] = family[s];
            double* q = f.q_of(i, s);
            double* errors = f.errors_of(i, s);
            errors[0] = errors[1] = nan;
            distance[s] = inf;
            if (!valid[s]) {
                for (int j = 0; j < n; ++j) q[j] = 0.0;
                continue;
            }
            for (int j = 0; j < n; ++j)
                if (!chain.prismatic[j])
                    q[j] = wrap_angle_into_limits(q[j], chain.lower[j], chain.upper[j], reference[j]);
            if (nearest) {
                double gap;
                const bool inside = inside_and_distance(chain, q, reference, weights, gap);
                distance[s] = inside || !within_limits ? seam_distance(chain, q, reference, weights, gap) : inf;
            }
        }
        if (!nearest) {  // every candidate verified: their tool poses in blocks
            Pose F[kMaxCandidates];
            tool_poses(chain, f.q_of(i, 0), k, F);
            for (int s = 0; s < k; ++s)
                if (valid[s]) verify(chain, target, f, i, s, reference, &F[s]);
        } else {
            int order[kMaxCandidates];
            stable_order(distance, k, order);
            double best = inf;  // the distance of the nearest kept candidate, once refined
            for (int a = 0; a < k; ++a) {
                const int s = order[a];
                if (distance[s] >= best) break;  // also where it is infinite
                if (!(verify(chain, target, f, i, s, reference) &&
                      (!within_limits || chain.within_limits(f.q_of(i, s)))))
                    continue;
                double gap;
                inside_and_distance(chain, f.q_of(i, s), reference, weights, gap);
                best = std::fmin(best, gap);
            }
            const bool kept = best < inf;
            for (int s = 0; s < k; ++s) {
                // a family's representative may be far from near while a member of it is not,
                // and none usable: verify the rest, to tell out of reach from out of limits
                if ((family[s] || !kept) && valid[s] && std::isnan(f.errors_of(i, s)[0])) verify(chain, target, f, i, s, reference);
            }
        }
        rank_pose(chain, f, i, reference, weights, within_limits);
        nearest_family_members(chain, target, f, i, reference, weights, within_limits);
        drop_twins(chain, f, i, reference, weights, within_limits);
        empty += f.count[i] == 0;
    }
    return empty;
}

}  // namespace armkit
