#include "armkit/closed_form.hpp"

#include <algorithm>
#include <cmath>

#include "armkit/double_root.hpp"
#include "armkit/fk.hpp"
#include "armkit/ik_family.hpp"

namespace armkit {

void joint_motion(const ClosedForm& cf, const Pose& T, Mat3& R, Vec3& t) {
    const Pose A = cf.inverted ? inverse(T) : T;
    const Pose G = compose(A, cf.M_inv);
    R = G.rotation();
    t = G.position();
}

void newton(const Chain& chain, const Pose& T, double* q, int steps, double stop) {
    const int n = chain.n;
    static constexpr int rows[6] = {0, 1, 2, 3, 4, 5};  // every task row
    const double free[kMaxJoints] = {};                  // no joint held at a bound
    Vec3 axes[kMaxJoints], points[kMaxJoints];
    double J[6 * kMaxJoints], e[6], dq[kMaxJoints];
    for (int step = 0; step < steps; ++step) {
        const Pose F = joint_axes(chain, q, axes, points);
        jacobian_from_axes(F, axes, points, chain.prismatic.data(), n, J);
        pose_error(T, F, e);
        if (stop > 0.0 && std::all_of(e, e + 6, [stop](double v) { return std::fabs(v) <= stop; })) return;
        damped_step(J, n, e, rows, 6, free, kNewtonDamping, dq);
        for (int j = 0; j < n; ++j) q[j] += dq[j];
    }
}

double fk_difference(const Chain& chain, const Pose& T, const double* q) {
    const Pose F = tool_pose(chain, q);
    double worst = 0.0;
    for (int a = 0; a < 12; ++a) worst = std::max(worst, std::fabs(F.m[a] - T.m[a]));
    return worst;
}

bool any_close_pair(const Chain& chain, const double* q, int k, const bool* valid, double gap) {
    const int n = chain.n;
    for (int a = 0; a < k; ++a) {
        if (!valid[a]) continue;
        for (int b = a + 1; b < k; ++b)
            if (valid[b] && within(chain, q + a * n, q + b * n, gap)) return true;
    }
    return false;
}

void mark_duplicates(const double* q, int k, int n, const bool* valid, const std::uint8_t* prismatic,
                     bool* duplicate) {
    for (int a = 0; a < k; ++a) duplicate[a] = false;
    for (int a = 0; a < k; ++a) {
        if (!valid[a]) continue;
        for (int b = a + 1; b < k; ++b)
            if (within(prismatic, n, q + a * n, q + b * n, kDuplicateTolerance)) duplicate[b] = true;
    }
}

// The number of singular values of the Jacobian at q (n) within kNullSpace of the largest.
int nullity(const Chain& chain, const double* q) {
    double V[kMaxJoints * kMaxJoints];
    int null[kMaxJoints];
    return null_space(chain, q, V, null);
}

// The configuration halfway between a and b (n; revolute joints the short way round) into mid.
void midpoint(const Chain& chain, const double* a, const double* b, double* mid) {
    for (int j = 0; j < chain.n; ++j) {
        const double d = b[j] - a[j];
        mid[j] = a[j] + 0.5 * (chain.prismatic[j] ? d : wrap_angle(d));
    }
}

// The nullity of the point between configurations a and b (n, within kSplitRoots), put
// onto the solution set of T exactly (into mid; size: the arm's, see kOnFamily), or -1
// where it does not get there or leaves kSplitRoots of either.
int nullity_between(const Chain& chain, const Pose& T, const double* a, const double* b, double size, double* mid) {
    midpoint(chain, a, b, mid);
    if (!project_onto_solutions(chain, T, mid)) return -1;
    newton(chain, T, mid, 3);  // to rounding on a family; beside a fold it stops at ~1e-13
    if (!(fk_difference(chain, T, mid) <= kOnFamily * size && within(chain, a, mid, kSplitRoots) &&
          within(chain, b, mid, kSplitRoots)))
        return -1;
    return nullity(chain, mid);
}

void flag_close_singular_candidates(const ClosedForm& cf, const Pose& T, double* q, const bool* valid, bool* family) {
    const Chain& chain = cf.chain;
    const int n = chain.n;
    for (int a = 0; a < cf.k; ++a) {
        if (!valid[a]) continue;
        double* qa = q + a * n;
        int at_a = -1;  // the nullity at qa, once needed
        for (int b = a + 1; b < cf.k; ++b) {
            const double* qb = q + b * n;
            if (!valid[b] || !within(chain, qa, qb, kSplitRoots)) continue;
            if (at_a < 0) at_a = nullity(chain, qa);
            const int at_b = nullity(chain, qb);
            if (within(chain, qa, qb, kCloseCandidates) && (at_a > 0 || at_b > 0)) family[a] = family[b] = true;
            // split roots: the singular point between them stands for them where it is more
            // singular than either (a family, or where two cross), or the first is rough
            // (no solution to rounding: it then loses nothing)
            double mid[kMaxJoints];
            const int between = nullity_between(chain, T, qa, qb, case_chain(cf.geometry).size, mid);
            const bool rough = fk_difference(chain, T, qa) > kOnFamily * case_chain(cf.geometry).size;
            if (between > std::max(at_a, at_b) || (between > 0 && rough)) {
                for (int j = 0; j < n; ++j) qa[j] = chain.prismatic[j] ? mid[j] : wrap_angle(mid[j]);
                family[a] = family[b] = true;
                at_a = between;
            }
        }
    }
}

// A candidate the case's existence tests rejected, which they can do at a multiple root of
// its equations (a doubly singular pose of a degenerate arm) while it still reproduces T:
// there FK decides. A finite invalid candidate within kExactFraction of cf.verify_tolerance
// after kExactNewtonSteps Newton steps, and not a twin of an accepted one, is valid, and a
// family member if the Jacobian there is singular.
//: Newton steps for it (kNearlyExact, kExactFraction): enough to reach rounding from 1e4
//: times the tolerance, so that a rejected twin of a valid candidate lands on it and is
//: marked a duplicate.
constexpr int kExactNewtonSteps = 6;

// Whether q (n) lies within kCloseCandidates of a candidate the case accepted (a twin of it:
// near a fold the rejected root of a pair converges onto the accepted one only slowly).
bool twin_of_accepted(const ClosedForm& cf, const double* q, const double* candidates, const bool* accepted) {
    for (int t = 0; t < cf.k; ++t)
        if (accepted[t] && within(cf.chain, candidates + t * cf.chain.n, q, kCloseCandidates)) return true;
    return false;
}

void take_exact_candidates(const ClosedForm& cf, const Pose& T, double* q, bool* valid, bool* family) {
    const int n = cf.chain.n;
    bool accepted[kMaxCandidates];
    std::copy(valid, valid + cf.k, accepted);
    for (int s = 0; s < cf.k; ++s) {
        double* qs = q + s * n;
        if (valid[s] || !std::all_of(qs, qs + n, [](double v) { return std::isfinite(v); })) continue;
        // only a candidate already near the pose is worth the Newton steps (every finite
        // rejected candidate pays one FK here: all of an unreachable pose's, and a UR5's
        // reachable pose has about one)
        if (!(fk_difference(cf.chain, T, qs) <= kNearlyExact * cf.verify_tolerance)) continue;
        double polished[kMaxJoints];
        std::copy(qs, qs + n, polished);
        newton(cf.chain, T, polished, kExactNewtonSteps);
        if (!(fk_difference(cf.chain, T, polished) <= kExactFraction * cf.verify_tolerance) ||
            twin_of_accepted(cf, polished, q, accepted))
            continue;
        for (int j = 0; j < n; ++j) qs[j] = cf.chain.prismatic[j] ? polished[j] : wrap_angle(polished[j]);
        valid[s] = true;
        family[s] = family[s] || nullity(cf.chain, qs) > 0;
    }
}

// Of two valid, close candidates (not family members) that are one solution, the one
// farther from the pose is no longer valid.
void merge_one_solution(const ClosedForm& cf, const Pose& T, const double* q, bool* valid, const bool* family) {
    const int n = cf.chain.n;
    for (int a = 0; a < cf.k; ++a) {
        for (int b = a + 1; b < cf.k && valid[a]; ++b) {
            if (!valid[b] || family[a] || family[b] || !within(cf.chain, q + a * n, q + b * n, kCloseCandidates))
                continue;
            const double at_a = fk_difference(cf.chain, T, q + a * n), at_b = fk_difference(cf.chain, T, q + b * n);
            if (!(std::min(at_a, at_b) <= kOnFamily * case_chain(cf.geometry).size)) continue;
            double mid[kMaxJoints];
            midpoint(cf.chain, q + a * n, q + b * n, mid);
            if (fk_difference(cf.chain, T, mid) > kBarrier * std::max(at_a, at_b)) continue;
            valid[at_a > at_b ? a : b] = false;
        }
    }
}

// Each polished candidate that Newton left above its stop, near the pose (stalled, cf.k: FK
// misses it by more than kPolished, by at most kNearlyExact times the FK check's tolerance;
// valid or not after that check), replaced by the nearest root the weak-direction search finds
// beside it (near_double_roots), and the other root of the pair put into the last row that is
// neither valid nor stalled, where there is one. A candidate FK already puts within
// kDoubleRootExact is replaced only where that root is nearer the pose (residual, cf.k): beside a
// near-double root FK cannot tell a point 2e-5 along the weak direction from the root (both
// within 1e-14), and the search finishes it onto the root.
void split_near_double_roots(const ClosedForm& cf, const Pose& T, double* q, bool* valid, const bool* stalled,
                             const double* residual) {
    const int n = cf.chain.n;
    const double exact = kDoubleRootExact * case_chain(cf.geometry).size;
    for (int s = 0; s < cf.k; ++s) {
        if (!stalled[s]) continue;
        double roots[kDoubleRoots * 6];
        const int found = near_double_roots(cf.chain, T, q + s * n, case_chain(cf.geometry).size, roots);
        if (found > 0 && residual[s] <= exact && !(fk_difference(cf.chain, T, roots) < residual[s])) continue;
        for (int r = 0; r < found; ++r) {
            int row = s;
            if (r > 0) {
                row = cf.k - 1;
                while (row >= 0 && (row == s || valid[row] || stalled[row])) --row;
                if (row < 0) break;
            }
            const double* root = roots + 6 * r;
            for (int j = 0; j < n; ++j) q[row * n + j] = cf.chain.prismatic[j] ? root[j] : wrap_angle(root[j]);
            valid[row] = true;
        }
    }
}

void pose_candidates(const ClosedForm& cf, const Pose& T, double* q, bool* valid, bool* family) {
    const int k = cf.k, n = cf.chain.n;
    bool stalled[kMaxCandidates] = {};
    double residuals[kMaxCandidates] = {};
    double q_int[kMaxCandidates * kMaxJoints];
    Mat3 R;
    Vec3 t;
    joint_motion(cf, T, R, t);
    solve_pose(cf.geometry, R, t, q_int, valid, family);
    const double exact = kDoubleRootExact * case_chain(cf.geometry).size;
    const double polished = kPolished * case_chain(cf.geometry).size;
    auto wrap_revolute = [&](double* qs) {
        for (int j = 0; j < n; ++j)
            if (!cf.chain.prismatic[j]) qs[j] = wrap_angle(qs[j]);
    };
    for (int s = 0; s < k; ++s) {
        double* qs = q + s * n;
        bool finite = true;
        for (int j = 0; j < n; ++j) {
            qs[cf.index[j]] = cf.sign[j] * q_int[s * n + j];
        }
        for (int j = 0; j < n; ++j) finite = finite && std::isfinite(qs[j]);
        valid[s] = valid[s] && finite;
        const bool polish = cf.polish && valid[s];
        double unpolished[kMaxJoints] = {};
        if (polish) {
            std::copy(qs, qs + n, unpolished);
            newton(cf.chain, T, qs, cf.polish_steps, cf.polish_stop);
        }
        wrap_revolute(qs);
        if (cf.verify && valid[s]) {
            double residual = fk_difference(cf.chain, T, qs);
            // beside a near-double root Newton can step along the weak direction away from the
            // root the case placed (an aligned wrist of a three-parallel arm: 1e-8 off the pose
            // before, 2.6e-6 after, q6 a radian away): the better of the two goes on
            if (polish && !(residual <= exact)) {
                wrap_revolute(unpolished);
                const double before = fk_difference(cf.chain, T, unpolished);
                if (before < residual) std::copy(unpolished, unpolished + n, qs), residual = before;
            }
            valid[s] = residual <= cf.verify_tolerance;
            stalled[s] = polish && residual > polished && residual <= kNearlyExact * cf.verify_tolerance;
            residuals[s] = residual;
        }
    }
    if (cf.polish) split_near_double_roots(cf, T, q, valid, stalled, residuals);
    take_exact_candidates(cf, T, q, valid, family);
    // duplicates, close singular candidates and one solution twice are pairs within kSplitRoots:
    // a regular pose has none, and one scan tells
    if (any_close_pair(cf.chain, q, k, valid, kSplitRoots)) {
        bool duplicate[kMaxCandidates];
        mark_duplicates(q, k, n, valid, cf.chain.prismatic.data(), duplicate);
        for (int s = 0; s < k; ++s) valid[s] = valid[s] && !duplicate[s];
        flag_close_singular_candidates(cf, T, q, valid, family);
        merge_one_solution(cf, T, q, valid, family);
    }
    for (int s = 0; s < k; ++s) family[s] = family[s] && valid[s];
}

}  // namespace armkit
