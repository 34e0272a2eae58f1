// Every tolerance of the compiled core, in one place, each with the reason for its value.
//
// A tolerance is a bar a computed number is held to: relative ones are multiplied by the
// size they compare with (the arm's length scale 1 + its largest coordinate [m], a system's
// largest term), absolute ones carry their unit. Iteration counts, sample counts and
// capacities are not tolerances and stay with the code that uses them. The Python layer
// binds the ones it shows to users (armkit.chain.LIMIT_TOLERANCE,
// armkit.ik.results.SOLUTION_TOLERANCE, armkit.ik.subproblems.*_TOLERANCE,
// armkit.ik.closed_form.CANDIDATE_TOLERANCE, armkit.ik.structure.CLASS_TOLERANCE).
#pragma once

namespace armkit {

// ------------------------------------------------------------------ joints and answers

//: Slack [rad or m] allowed beyond a joint limit (bound as armkit.chain.LIMIT_TOLERANCE):
//: a solution computed to 1e-12 at a limit must not be refused for its rounding.
constexpr double kLimitTolerance = 1e-9;
//: Position [m] and angle [rad] within which every returned solution reproduces the target
//: (bound as armkit.ik.results.SOLUTION_TOLERANCE): solutions reach ~1e-13; this leaves room.
constexpr double kSolutionTolerance = 1e-9;
//: Candidates closer than this in every joint [rad or m, modulo 2 pi] are one solution
//: (armkit.ik.closed_form.DUPLICATE_TOLERANCE): distinct roots of a regular pose differ by far more.
constexpr double kDuplicateTolerance = 1e-9;

//: Deviation from a rigid transform [1] (|R^T R - I|, |det R - 1|, the last row's from
//: [0, 0, 0, 1]) up to which a target pose is accepted (bound as
//: armkit.spatial.transforms.RIGID_TOLERANCE): a rotation printed with six decimals deviates by
//: up to about 2e-6; one off by more than 1e-14 is replaced by the nearest rotation first.
constexpr double kRigidTolerance = 1e-5;

// ------------------------------------------------- which case applies (ik_detect, ik_classify)

//: Two axes count as parallel where the sine of their angle is at most this, and as meeting
//: (or one line) where they pass within this times the arm's size (1 + its largest coordinate
//: [m]): a class is detected only to the rounding of a robot file's numbers (a Kinova URDF's
//: meeting wrist axes miss by ~1e-13 relative; DH tables to ~1e-16), never to a calibration's
//: size. An arm within it is solved as its class, whose solutions are then off by at most
//: this over the pose's conditioning (polished by refine); beyond, the general solver
//: lists the real arm's exact solutions. At 1e-9 (the bar before) arms moved by 1e-9 were
//: taken as their class and 5-12 of 100 poses lost the generating configuration (the class
//: solver's equations assume exact meeting axes: candidates ~1e-6 off, or none at all),
//: while the general solver lists every solution from 1e-11 on (tests/test_ik_general.py).
constexpr double kClassTolerance = 1e-11;
//: Singular values of the Jacobian below this fraction of the largest count as zero in the
//: generic rank (armkit.ik.structure.generic_rank): a rank-deficient arm's are ~1e-16 of it,
//: a generic arm's smallest at a random configuration is rarely below 1e-3.
constexpr double kRankTolerance = 1e-9;
//: A candidate counts only where its FK matches the target to this (entries of the top three
//: rows, times the arm's size; bound as armkit.ik.closed_form.CANDIDATE_TOLERANCE): it only
//: rejects non-solutions, since solutions reproduce reachable poses to ~1e-13 and what IK
//: returns is checked again, to kSolutionTolerance.
constexpr double kCandidateTolerance = 1e-8;
//: A loop of the general solver whose raw candidates come within this [rad] of every sample's
//: generating configuration is taken without trying the others (detect_general): Newton
//: finishes such candidates in two steps.
constexpr double kGoodLoop = 1e-8;
//: An arm within this of a class (its axes as kClassTolerance measures them; a calibrated
//: arm) is solved by the general solver and, besides, by its class on the arm moved onto it
//: exactly, whose candidates Newton then takes onto the real arm (see GeneralGeometry::seed):
//: a class solution is ~deviation / conditioning off the real one, well within Newton's reach
//: at 1e-6, and the general solver's elimination may lose a root near a class (1 pose in
//: ~1000 at 1e-11 .. 1e-7 measured, tests/test_ik_general.py).
constexpr double kNearClass = 1e-6;
//: A three-parallel arm within this of one of its class's sub-cases (axes 5 and 6 meeting, or
//: able to turn axis 6 parallel to the block; wrist_subcase_gaps), not to kClassTolerance, is
//: left to the general solver: near the sub-case the class's quartic has a near-double root in
//: q5 close to an aligned wrist and loses it (a UR5 with joint 5's point moved or joint 6's axis
//: turned: 60 of 480 poses at q5 = 1e-4 .. 1e-2 for moves of 1e-8 .. 1e-6, and at 1e-5 .. 1e-4
//: still 6 of 384), the general solver, seeded within kNearClass, lists them all. The bar is the
//: size of a calibration's corrections (issue 21: 1e-6 .. 1e-3).
constexpr double kNearSubcase = 1e-3;
//: A raw candidate of a loop counts as near a solution where its FK is within this of the
//: pose (times the arm's size), and as another one where it is farther than this [rad] from
//: the loop's others (detect_general): near a class raw roots are ~1e-4 off, and Newton takes
//: them to rounding; a loop that loses a root puts its candidate ~0.1 .. 1 off.
constexpr double kLoopNear = 1e-3;

// ------------------------------------------------------------------------ subproblems

//: Relative amount by which a subproblem instance may be impossible and still count as
//: tangent: a pose reached exactly at a boundary misses it by rounding (~1e-15) times the
//: conditioning of the geometry, and 1e-9 of the arm's size is far below any real gap.
constexpr double kOutTolerance = 1e-9;
//: Relative distance to tangency below which a double solution is returned once (SP3,
//: SP4): their error is second order in the angle, so the square root of rounding (~1e-8)
//: would split one root into two.
constexpr double kTangentTolerance = 1e-14;
//: Relative size below which a vector counts as lying on the rotation axis (any angle):
//: a point zero up to rounding (the wrist centre at the shoulder's centre) is free.
constexpr double kFreeTolerance = 1e-12;

// ----------------------------------------------------- the two-angle system (ik_cases)

//: The quartic's leading coefficient below this times its largest is zero (the equation
//: has degree 1): its roots would lie at ~1 / 1e-12, far from the unit circle.
constexpr double kQuarticLeading = 1e-12;
//: A quartic root z counts as on the unit circle (a real angle) within this of |z| = 1:
//: a double root (a tangency) splits into a pair ~1e-8 off the circle, and Newton steps on
//: the equations then decide.
constexpr double kUnitCircle = 1e-6;
//: A 2x2 Newton step on the two-angle system is taken where its determinant exceeds this
//: times its scale; below, the step would be rounding noise (a double root).
constexpr double kTwoAngleSingular = 1e-12;
//: A root of the two-angle system is one where its residual is at most this times the
//: system's size: roots polish to ~1e-15; a double root reached linearly to ~1e-8 squared.
constexpr double kTwoAngleResidual = 1e-10;
//: A multiple root is merged where its exact position (a root of a derivative) is within
//: this [rad] of the polished root: a quadruple root is reached only to eps^(1/4) ~ 1e-4.
constexpr double kMultipleRootReach = 1e-3;
//: F's coefficients below this in sum are zero (its terms include the 1 of the unit
//: circle), times 1 + (the largest entry of Q^-1) x system_size (Q^-1 amplifies the
//: pose's rounding: seen 1e-12 in sum with an entry of 1.3e3): the two equations are one.
constexpr double kIdentityTolerance = 1e-12;
//: Q (the chain's 2x2 part of a two-angle system) has rank 1 where its smaller singular
//: value is below this times its larger (armkit.ik.closed_form): axes that meet exactly
//: give ~1e-16; a real offset gives far more.
constexpr double kRankOne = 1e-9;
//: A family's planar 2R counts as reaching where |f| <= 1 + this x (1 + middle / half
//: width) (see family_loops): the rounding of |v|^2 relative to the 2R's range.
constexpr double kFamilyReach = 1e-9;

// --------------------------------------------------------------- wrists (ik_cases)

//: Angle [rad] between axis 6's target direction and axis 4 within which a spherical
//: wrist counts as aligned for the family flag (the values themselves are not moved):
//: q1-q3 carry errors of up to ~1e-8 from a double root.
constexpr double kNearlyAligned = 1e-7;
//: Angle [rad] between axis 6 and the three parallel axes within which q6 may be taken
//: as free where the 2R cannot follow the q6 SP1 gives (see three_parallel): seen 4e-12.
constexpr double kAlignedToRounding = 1e-11;
//: q5 within this [rad] of an aligned wrist (three parallel axes) is recomputed from a
//: sine: the cosine equation loses q5 below ~1e-8, and the sine form is exact up to 1e-3.
constexpr double kAlignedWristReach = 1e-3;
//: A root q5 within this [rad] of an aligned wrist is put onto it exactly (the family's
//: member): at an aligned pose the pair's roots, split from sines (split_near_aligned_pairs),
//: lie within ~1e-14 of it; a pose 1e-7 off has its two roots ~1e-7 either side (1e-6 here
//: once snapped both onto it, and the generating configuration was lost).
constexpr double kAlignedWristSnap = 1e-10;
//: Two roots of the quartic within kAlignedWristReach of an aligned wrist and within this [rad]
//: of each other in q1 are a near-double pair (split_near_aligned_pairs): the quartic places a
//: pair d apart to ~1e-16 / d, so farther apart than this they are already accurate (a pair at
//: q5 = +-1e-7 lay 2e-8 apart in q1; three roots 1.5e-4 .. 6e-4 apart near q5 = 0 are no pair).
constexpr double kAlignedPair = 1e-5;
//: ... whose E is fitted on points at least this far [rad] either side of their middle
//: (roots the quartic placed to ~1e-8 may lie that far from where they are).
constexpr double kAlignedPairWidth = 1e-7;
//: ... where P (the pose's 2x2 part) is invertible: its determinant above this times its
//: scale (below, q1 is not determined by q5 and the snap would be noise).
constexpr double kAlignedWristSolvable = 1e-9;

// ------------------------------------------------------- the per-pose pipeline (closed_form)

//: Two candidates closer than this in every joint [rad or m, modulo 2 pi] are looked at
//: together (flag_close_singular_candidates): members of a family the case solver did not
//: see lie ~1e-5 apart.
constexpr double kCloseCandidates = 1e-3;
//: Two candidates within this in every joint [rad or m, modulo 2 pi] may be the two roots
//: of a double root on either side of a family (see flag_close_singular_candidates): the
//: case solver places them ~1e-7 off it and, the family being singular, up to ~1e-3
//: apart along it.
constexpr double kSplitRoots = 1e-2;
//: The point between split roots, put onto the solution set, must reproduce the pose to
//: this [m, times the arm's size; rad] (rounding: a family's members are exact, while
//: beside a fold the projection stops in a neighbourhood of residual ~1e-13 that is
//: singular too, between twin roots that are two solutions).
constexpr double kOnFamily = 1e-14;
//: A rejected candidate within this many times the FK check's tolerance of the pose is
//: polished and checked (take_exact_candidates): a multiple root lands ~1e-8 off.
constexpr double kNearlyExact = 1e4;
//: ... after which it must reproduce T to this fraction of the FK check's tolerance
//: (rounding): near a fold the point between two twin roots comes within ~1e-9 and is no solution.
constexpr double kExactFraction = 1e-4;
//: Two close candidates (kCloseCandidates), the better exact to rounding (kOnFamily), are
//: one solution unless the point between them misses the pose by more than this many
//: times the worse one's residual (a barrier between two roots): near a fold the closed
//: form can place a second root at a residual minimum of ~1e-13 beside the exact one (the
//: point between them misses by about as much), while twin roots of a pose just inside a
//: fold, each exact to rounding, have a barrier of 1e-13 to 1e-10 between them.
constexpr double kBarrier = 10.0;
//: Newton stops early once the pose error [m, rad] is below this times the arm's size
//: (rounding of FK itself).
constexpr double kPolished = 1e-15;
//: Damping of the Newton steps on the full pose (relative to J^T J): small enough to keep
//: quadratic convergence, large enough to step across a singular Jacobian.
constexpr double kNewtonDamping = 1e-14;

//: A polished candidate that Newton left short of rounding (kDoubleRootExact) is searched for the
//: two roots of a near-double root (double_root.hpp) where its Jacobian's smallest singular value
//: is at most this fraction of the largest: Newton's normal equations carry the weak direction's
//: step with a relative error of eps / ratio^2 (1e-8 at 1e-4), and its damping (kNewtonDamping)
//: holds the step back below ~1e-7; the stalled candidates seen sat at 1.5e-8, regular ones near
//: a wrist singularity at 3e-5 .. 1e-4 (they converge, and are not searched).
constexpr double kNearDoubleRoot = 1e-4;
//: A root the search finds is kept where FK reproduces the pose to this (entries of the top three
//: rows, times the arm's size), and a polished candidate that misses by more is searched (one
//: within it but above kPolished too, kept as it is unless the search's root is nearer):
//: rounding, as a regular solution (~1e-15 .. 1e-14); the point where Newton stalled between two
//: roots missed by 9e-14.
constexpr double kDoubleRootExact = 1e-14;

// ------------------------------------------------------------- refinement (ik_solve)

//: Candidates with a larger FK residual [m or rad] are rough: refined (see refine).
//: Exact closed-form solutions reach ~1e-15 .. 1e-14.
constexpr double kRefineAbove = 1e-13;
//: A refinement may move a candidate by at most this [rad or m] (it must stay on its
//: branch): a rough candidate is ~1e-8 off, other roots are farther.
constexpr double kRefineMove = 1e-6;
//: ... and a family's representative by this: the exact points near it are members of its
//: family (or of one crossing it), so no distinct solution is lost, and at a doubly
//: singular pose the closed form places it only to ~1e-5 (a multiple root; the residual
//: grows with the square of the distance along the family's second direction).
constexpr double kRefineFamilyMove = 1e-3;

// -------------------------------------------------------------- families (ik_family)

//: Singular values below this fraction of the largest span a family's directions:
//: a singular Jacobian computed at a point 1e-13 off the family has ~1e-13 .. 1e-10 there.
constexpr double kNullSpace = 1e-8;
//: ... and below this, near a crossing of two families (where the trace stops short: a
//: kink), the other family's direction too, for a step towards near that ends stuck.
constexpr double kNearCrossing = 0.05;
//: Two axes within this of one line (angle [rad], distance / size of the arm) are walked
//: along as one, then projected (see move_along_collinear_pairs).
constexpr double kNearlyCollinear = 1e-6;
//: The projection back onto the solution set stops at this residual [m, rad]: a few ulps
//: of FK at the arm's size.
constexpr double kProjectionTolerance = 1e-13;
//: The smallest step [rad or m] tried along a curved family before a direction is given
//: up: below it a kink of the family (a crossing) stops the trace, not its curvature.
constexpr double kTraceSmallestStep = 1e-3;
//: A step [rad or m] along the Jacobian's null space that tells a family from an isolated
//: singular solution (see on_a_family): large against the projection's 1e-13, small
//: against the family's curvature.
constexpr double kFamilyProbe = 1e-3;
//: A point aimed along the family from q and put onto the solution set stays on q's family
//: when the projection moves it by at most this fraction of the aim (a line family: ~0; a
//: curved one: the curvature times the step). A projection from a point far along the line
//: can land on another branch of the pose (another elbow or shoulder) that happens to be
//: nearer to near: the wrist family of a PUMA at q5 = 0 was replaced by another branch's
//: member on 8 of 300 poses, so the listing lost the generating configuration's branch.
constexpr double kStayOnFamily = 0.5;

// ------------------------------------------------------------ general 6R (ik_general)

//: A root x3 counts as real when |Im x3| is at most this times max(1, |x3|) (for a root of
//: the inverted companion, of 1 / x3): a double root (a fold of the pose) splits into a
//: complex pair ~1e-8 apart, and an arm near a Pieper class loses digits; a complex
//: candidate that is no solution fails the pipeline's Newton steps and FK check, so the
//: bar can be generous.
constexpr double kRealRoot = 1e-4;
//: The companion matrix needs the leading (or trailing) coefficient matrix inverted; below
//: this reciprocal condition number of both the pencil goes to QZ instead.
constexpr double kCompanionCondition = 1e-10;
//: The spurious roots x3 = +-i split off the companion matrix (ik_general.cpp,
//: without_spurious_roots) where the arm's basis for them leaks at most this times the
//: matrix's largest entry: rounding leaves ~1e-15 (random arms); beyond, the whole 24 x 24
//: matrix goes to the eigensolver.
constexpr double kSpuriousSplit = 1e-12;
//: The null vector of M(x3) at a root comes from LU with partial pivoting where its smallest
//: pivot is at most this fraction of the next smallest (a clear rank deficiency: at a root found
//: to 1e-12 .. 1e-4 the smallest is that small against pivots of the matrix's size), else from
//: full-pivot LU, which reveals the rank where partial pivoting may not (ik_general.cpp).
constexpr double kNullPivotGap = 1e-2;
//: A QZ eigenvalue alpha / beta with |beta| below this times |alpha| is at infinity
//: (rounding of beta relative to alpha).
constexpr double kInfiniteEigenvalue = 1e-16;

// ------------------------------------------------------------------ linear algebra

//: Damping, relative to trace(J^T J), of a step whose damped normal equations were not
//: positive definite (a singular Jacobian and no damping): within about 1e-7 of the
//: minimum-norm least-squares step on rank-deficient random Jacobians.
constexpr double kSingularDamping = 1e-10;

//: Smallest eigenvalue of a Gram matrix J J^T (or J^T J), relative to its trace, below which the
//: resolved-rate step counts J as exactly singular and takes the kSingularDamping step: the
//: eigenvalue is computed with an error of a few eps times the trace (seen: +4e-16 and +9e-18 of
//: it at exact wrist singularities), so an undamped solve there would return rounding noise.
constexpr double kGramRounding = 1e-13;
//: Damping, relative to the Gram matrix of a Jacobian scaled to a largest entry in [0.5, 1) (so the
//: matrix's entries are at most kMaxJoints), above which the resolved-rate step takes
//: (J J^T + damping I)^-1 as I / damping: the dropped term is below 6 n / 1e20 (<= 1e-18) of it, far under
//: rounding, and the damping itself may no longer be a double (a J of 1e-300 with lambda = 0.04
//: has a scaled damping of 1.6e597).
constexpr double kDampingDominates = 1e20;

// ------------------------------------------------------------------ time-optimal paths

//: Relative slack by which rounding may leave a TOPP bound violated before a set counts as
//: empty: the bounds are computed to ~1e-15 relative; 1e-9 never hides a real conflict.
constexpr double kToppSlack = 1e-9;

}  // namespace armkit
