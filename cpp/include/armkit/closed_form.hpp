// Every closed-form candidate of one target pose (port of the loop of armkit/ik/closed_form.py).
//
// The case solver (ik_cases.hpp) works on the joint motion G = T M^-1 in its internal joint
// order; pose_candidates maps its candidates to the user's joints, polishes quartic ones by
// two Newton steps on the full pose, wraps revolute angles into [-pi, pi], checks them by
// FK where the chain is over-determined or a quartic was solved, and merges duplicates.
#pragma once

#include <cmath>
#include <cstdint>

#include "armkit/chain.hpp"
#include "armkit/ik_cases.hpp"
#include "armkit/linalg.hpp"
#include "armkit/tolerances.hpp"

namespace armkit {


// What the per-pose loop needs of one chain, made once by ClosedFormSolver (Python). It
// holds copies of the chain and the case geometry, so it outlives neither's Python object.
struct ClosedForm {
    Chain chain;             // the user's chain, for FK
    CaseGeometry geometry;   // the case solver's constants
    int index[kMaxJoints];   // user's joint of internal joint j
    double sign[kMaxJoints]; // q_user[index[j]] = sign[j] q_int[j]
    Pose M_inv;              // inverse tool pose at q = 0 of the (possibly reversed) chain
    bool inverted = false;   // the solver's chain describes T^-1
    int k = kMaxCandidates;  // candidates per pose
    bool verify = false;     // check candidates by FK
    bool polish = false;     // Newton steps on the full pose (quartic paths, general 6R)
    int polish_steps = 2;    // ... this many (general 6R: at most kGeneralNewtonSteps)
    double polish_stop = 0;  // ... stopping below this pose error (general 6R: kPolished x size)
    double verify_tolerance = 0.0;  // max |fk(q) - T| of a kept candidate (top three rows)
};

// G = T M^-1 (or T^-1 M^-1 for an inverted chain): its rotation R and translation t.
void joint_motion(const ClosedForm& cf, const Pose& T, Mat3& R, Vec3& t);

//: Newton steps at most for a general 6R candidate: the elimination loses digits on arms
//: near a Pieper class (candidates ~1e-4 off at deviations of 1e-6), and quadratic
//: convergence takes 1e-4 to rounding in four steps; a few more for a slow start.
constexpr int kGeneralNewtonSteps = 8;

// `steps` damped Newton steps on fk(q) = T (all six rows, damping 1e-14) for one
// candidate q (n), in place, stopping early where the pose error is at most `stop` [m,
// rad]. Where a quartic root meets another singularity (a double root near an aligned
// wrist) a candidate may carry errors of ~1e-7; two steps bring it to rounding level, and
// the FK check then decides.
void newton(const Chain& chain, const Pose& T, double* q, int steps, double stop = 0.0);

// max |fk(q) - T| over the top three rows.
double fk_difference(const Chain& chain, const Pose& T, const double* q);

// Whether configurations a and b (n joints, prismatic flags) differ by at most gap in every joint
// (revolute ones modulo 2 pi): the one comparison of two configurations here (inline: the
// candidates' pairwise scans call it for every pair). Last joint first: a pose's candidates
// share their first joints in groups (the arm's branches) and differ in the wrist's, so two
// apart are told apart at the first joint looked at.
inline bool within(const std::uint8_t* prismatic, int n, const double* a, const double* b, double gap) {
    for (int j = n - 1; j >= 0; --j) {
        const double d = b[j] - a[j];
        if (!(std::fabs(prismatic[j] ? d : wrap_angle(d)) <= gap)) return false;
    }
    return true;
}

inline bool within(const Chain& chain, const double* a, const double* b, double gap) {
    return within(chain.prismatic.data(), chain.n, a, b, gap);
}

// Whether two valid candidates (rows of q, k x n) are within gap of each other (within).
bool any_close_pair(const Chain& chain, const double* q, int k, const bool* valid, double gap);

// duplicate[b] (k): candidate b (row of q, k x n) equals, modulo 2 pi for revolute joints
// and to kDuplicateTolerance, an earlier valid candidate.
void mark_duplicates(const double* q, int k, int n, const bool* valid, const std::uint8_t* prismatic,
                     bool* duplicate);

// Two valid candidates (rows of q, cf.k x n) within kCloseCandidates of each other where
// the Jacobian at either is singular: members of a family the case solver did not see (two
// exact solutions 1e-5 apart where a double root meets a second singularity), both flagged
// family, to be walked towards near later. Two candidates within kSplitRoots whose point
// between, put onto the solution set of T to rounding, is singular, and more singular
// than either or the first is no solution to rounding (two roots a rounding error's square
// root apart, ~1e-7, on either side of a family or of the crossing of two, and up to 1e-2
// apart along it): that point replaces the first, both flagged family. Two close roots of
// a regular pose, and twin roots beside a fold, are left alone.
void flag_close_singular_candidates(const ClosedForm& cf, const Pose& T, double* q, const bool* valid, bool* family);

// Each finite invalid candidate that reproduces T (to rounding, after a few Newton steps)
// and is no twin of an accepted one made valid, and family where the Jacobian there is singular.
void take_exact_candidates(const ClosedForm& cf, const Pose& T, double* q, bool* valid, bool* family);

// Every candidate of one target T into q (cf.k x n, user's joints), valid and family
// (cf.k); duplicates are invalid, and family implies valid. Where a candidate fails the
// case's existence tests, FK decides (take_exact_candidates).
void pose_candidates(const ClosedForm& cf, const Pose& T, double* q, bool* valid, bool* family);

}  // namespace armkit
