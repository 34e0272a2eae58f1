// Every IK solution of a general 6R arm: Raghavan and Roth's elimination (1993), with the
// coefficient matrices found numerically.
//
// The chain is taken as screw axes at q = 0, G = exp(xi_1 q_1) ... exp(xi_6 q_6) (the joint
// motion, as for the other cases). Joint 6 fixes its own line, so joints 1-5 carry the
// line of axis 6 (point p6, direction h6) onto its image under G:
//
//     e3 e4 e5 (p6, h6)  =  e2^-1 e1^-1 G (p6, h6)                       (left = right)
//
// The 14 quantities of Raghavan and Roth (p, l, p.p, p.l, p x l, (p.p) l - 2 (p.l) p) of
// either side are trigonometric polynomials of degree one in each joint angle (Raghavan and
// Roth prove it for DH coordinates; a rigid change of coordinates keeps it), so sampling
// each side at three angles per joint gives their coefficients exactly (a three-point DFT):
// the left side once per arm (27 samples: it holds no pose), the right side per pose (9).
// Eliminating the 8 monomials in q1, q2 leaves 6 equations in q3, q4, q5; with half-angle
// tangents x_i they are quadratic in each x_i, and the 6 equations and their multiples by
// x4 are a 12 x 12 matrix polynomial M(x3) = M0 + M1 x3 + M2 x3^2 acting on the monomials
// x4^i x5^j (i <= 3, j <= 2). det M(x3) = 0 is a 24 x 24 companion eigenproblem (Eigen's
// QZ on the pencil where M2 and M0 are both nearly singular: no home-made eigen solver); the
// null vector of M(x3) gives x4 and x5, the right side's least-squares solution gives q1, q2,
// and q6 follows from the rotation left over. The roots x3 = +-i (four each) are spurious:
// their invariant subspace depends on the arm alone, so a basis made once per arm splits
// them off and Eigen's real Schur solver works on the 16 x 16 rest; at most 16 real roots.
//
// One prismatic joint (5R1P: a Stanford arm off its class) is taken where the loop
// eliminates it linearly, as its joint 1 or 2 (loop_takes): a slide d moves the line by d h,
// so the right side's quantities are of degree two in d (fitted from three slides, x = d /
// size = 0, 1, -1) where an angle's are of degree one in (cos, sin); the 8 monomials of q1,
// q2 are eliminated the same way and the left side is the 6R one, spurious roots and all.
//
// The joint angles are measured from offsets (kGeneralOffsets), so that no root of a
// generic pose lies at a half-angle tangent of infinity. Candidates are rough (1e-12 ..
// 1e-6 where the arm is near a Pieper class); the pipeline polishes them by Newton steps on
// the full pose and checks them by FK (closed_form.cpp).
#pragma once

#include <memory>

#include "armkit/case_chain.hpp"
#include "armkit/ik_detect.hpp"
#include "armkit/vec.hpp"

namespace armkit {

//: Real solutions of a general 6R arm at most (and candidates the solver writes).
constexpr int kGeneralRoots = 16;
//: The 14 quantities of each side.
constexpr int kQuantities = 14;

// What the per-pose solver needs of one arm, computed once by prepare_general (named for
// the 6R arm; a 5R1P arm's slide is one of the loop's linear joints, see loop_takes).
struct GeneralSixR {
    Vec3 h[6], p[6];                      // axes and points at q = 0 (internal joint order)
    bool prismatic[6] = {};               // at most one, the loop's joint 1 or 2 (loop_takes)
    double size = 1.0;                    // a slide's unit in the right side's samples [m]
    int shift = 0;                        // the loop starts at joint shift + 1 (see general_six_r)
    double left[kQuantities][3][3][3];    // shift 0: left side over (1, cos, sin) of t3, t4, t5
    double spurious[2][24 * 24];          // shift 0: bases splitting off the roots x3 = +-i
};

// Whether the elimination takes the chain's joints in the loop starting at joint shift + 1:
// every joint revolute but at most one prismatic joint, as the loop's joint 1 or 2. Those two
// are eliminated linearly (the 8 monomials of q1, q2): a slide d enters the 14 quantities as
// (1, d, d^2) where an angle enters as (1, cos, sin), so the elimination is the same (Raghavan
// and Roth's method takes prismatic joints so too); on the left side a slide would change the
// degree structure the spurious roots are split off by, and the loop's joint 6 must turn (its
// angle comes from the rotation).
bool loop_takes(const CaseChain& chain, int shift);

// The arm's constants from its lines (6, loop_takes(chain, shift)) and the loop's shift (0 .. 5).
void prepare_general(const CaseChain& chain, int shift, GeneralSixR& g);

// The loop may start at any joint: with shift s, e_{s+1} ... e_6 e_1' ... e_s' = G, where e_j'
// = G^-1 e_j G turns about G^-1 of joint j's line, so joints s+3 .. s+5 (cyclically) stay
// and s+1, s+2, s+6 are eliminated; for s > 0 the left side holds the pose and is sampled per
// pose. Which joints are eliminated decides the conditioning: an arm with parallel or
// meeting axes (many zero DH entries, a Kinova Jaco) degenerates in some loops, not in all.
//
// Every real candidate for the joint motion G = (R, t) into q (kGeneralRoots x 6, row-major),
// valid (kGeneralRoots; false for unused rows) and family (all false: the pipeline flags
// families). Returns the number of valid candidates.
int general_six_r(const GeneralSixR& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// A class the arm is near (within kNearClass), solved on the arm moved onto it exactly: its
// candidates seed the general solver's (ik_general.cpp).
struct ClassSeed;

// The general case of the registry (ik_cases.hpp), the last: any 6R or 5R1P arm, the elimination's
// constants made once and shared by copies (12 KB: not carried by any other case); for an arm
// near a class, that class's seed.
struct GeneralGeometry : CaseChain {
    std::shared_ptr<const GeneralSixR> arm;
    std::shared_ptr<const ClassSeed> seed;
};

// general_six_r on g.arm: 16 candidates. With a seed, the class's candidates (mapped to this
// loop's joints) come first, then the elimination's that are not within kLoopNear of one:
// Newton then takes each onto the real arm and FK decides (closed_form.cpp), so a root the
// elimination loses near a class is still listed.
void solve_case(const GeneralGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// Any 6R or 5R1P arm, on the loop on which the elimination is best conditioned for it: the
// chain or its reverse, and the loop's first joint (shift; of a 5R1P arm's, the four that
// take its slide). The loops are run, once per arm, on the poses of kLoopSamples seeded
// random configurations; the first whose raw candidates come within kGoodLoop of every
// generating configuration is taken (a generic arm's first), else the one whose raw
// candidates come closest to the generating configurations (worst sample, then mean), then
// the one with the most distinct raw candidates near a solution of their pose (kLoopNear:
// a loop that loses roots has fewer, its other candidates far off), ties to the first
// tried. An arm with parallel or meeting axes degenerates in some loops and not in others,
// and an arm near a Pieper class loses digits in one order and far fewer in another (a
// PROBOT with one wrist axis moved by 1e-9: one loop of the twelve lists every solution).
// Two or more prismatic joints: why not (numeric IK).
Detection<GeneralGeometry> detect_general(const ArmLines& arm);

}  // namespace armkit
