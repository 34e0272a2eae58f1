// Which case applies to a chain, decided from its joint lines at q = 0 (never from a
// robot's name or DH convention): the part of the case interface that detects.
//
// Each case has a detect function (declared in its header ik_case_<name>.hpp, defined in its
// source) from the chain's lines (ArmLines) to a Detection: either a CaseMatch (the case's
// geometry, the lines it works on, possibly reversed or with axes flipped, and the sentence
// `armkit show` prints) or a CaseReason (a result code and a short text saying why the case
// does not apply). The registry (ik_cases.hpp) lists them; classify (ik_cases.hpp) runs them.
//
// Every test on the lines holds them to kClassTolerance (tolerances.hpp): a class is detected
// only to the rounding of a robot file's numbers, so an arm near a class (a calibrated one) is
// the general 6R arm it is, solved exactly, never the idealised class.
#pragma once

#include <initializer_list>
#include <string>
#include <variant>

#include "armkit/case_chain.hpp"
#include "armkit/chain.hpp"
#include "armkit/tolerances.hpp"
#include "armkit/two_angle.hpp"
#include "armkit/vec.hpp"

namespace armkit {

// A chain as its joint lines at q = 0 (CaseChain: axes h, points p, prismatic), its tool pose
// M at q = 0, and how a case's internal joint j maps to the user's: q_user[index[j]] =
// sign[j] q_int[j]; inverted: the lines describe T^-1 (the reversed chain).
struct ArmLines : CaseChain {
    Pose M;
    int index[kMaxCaseJoints] = {};
    double sign[kMaxCaseJoints] = {};
    bool inverted = false;
    double scale = 1.0;  // 1 + the largest |coordinate| of the points and of M's position [m]
    double tolerance = kClassTolerance;  // the tests' bar (kNearClass: is the arm near a class?)
};

// The lines of a chain of at most kMaxCaseJoints joints (user's order, base frame).
ArmLines arm_lines(const Chain& chain);
// The lines of joints 0 .. count - 1 of `arm` alone, with M the pose that carries the tool
// point c (for position IK: joints 1-3 carry c).
ArmLines first_lines(const ArmLines& arm, int count, Vec3 c);
// The chain of T^-1: joints in reverse order, M -> M^-1, angles negated.
ArmLines reversed(const ArmLines& arm);
// The axes of `joints` that point against h flipped (their variable negated).
ArmLines aligned(const ArmLines& arm, std::initializer_list<int> joints, Vec3 h);

// Tests on the lines to arm.tolerance (angles [rad]; distances times arm.scale [m]).
bool parallel(const ArmLines& arm, int i, int j);
double distance_to_line(const ArmLines& arm, Vec3 x, int i);
// The point where revolute axes i and j meet (false: they do not, or are parallel).
bool intersection(const ArmLines& arm, int i, int j, Vec3& point);
// The point where revolute axes i, j, k meet (the middle one not parallel to either).
bool meet(const ArmLines& arm, int i, int j, int k, Vec3& point);
// The points a, b of lines (pa, ha) and (pb, hb) closest to each other (not parallel).
void closest_points(Vec3 pa, Vec3 ha, Vec3 pb, Vec3 hb, Vec3& a, Vec3& b);
// A unit vector perpendicular to h.
Vec3 unit_normal(Vec3 h);
// The constant part of a two-angle system with Q (2 x 2) and f: Q's inverse or, of rank 1
// (kRankOne), the combinations lam (holds t1 alone) and mu.
TwoAngleSystem two_angle_constants(const double (&Q)[2][2], double f0, double f1, bool snap_t2);
// The user's 1-based numbers of internal joints, sorted: "4, 5, 6".
std::string axes_text(const ArmLines& arm, std::initializer_list<int> joints);

// Why a case does not apply: the code (kCaseFitNames) and a short sentence.
enum class CaseFit : int {
    Applies = 0,     // the case applies
    Joints = 1,      // the number of joints is not the case's
    Prismatic = 2,   // a joint the case needs revolute is prismatic (or the other way)
    Axes = 3,        // the axes do not meet / are not parallel as the case needs
    Position = 4,    // the case's axes are there, but its joints 1-3 have no closed form
    PositionOnly = 5,  // a case of position IK (joints 1-3), not of a whole pose
    Degenerate = 6,  // the arm itself has no closed form (two axes on one line, a rank deficit, 7+ joints)
    Earlier = 7,     // not tried: a case listed earlier applies
};
constexpr const char* kCaseFitNames[] = {"applies", "joints", "prismatic", "axes", "position", "position-only",
                                         "degenerate", "earlier"};

struct CaseReason {
    CaseFit fit = CaseFit::Applies;
    std::string text;
};

// A case that applies: its geometry, the lines it works on (geometry and lines describe the
// same chain), the kind of arm (armkit.ik.ArmStructure.kind) and one sentence on why.
template <class G>
struct CaseMatch {
    G geometry;
    ArmLines lines;
    std::string kind, description;
    bool polish = false;  // its candidates come from a quartic or an elimination: Newton on the full pose
};

template <class G>
using Detection = std::variant<CaseMatch<G>, CaseReason>;

// How joints 1-3 of `arm` place a point (a wrist centre or a tool point): the position case,
// the point o where axes 1, 2 (or 2, 3) meet, the lines aligned for it, and the clause for
// the description; or why joints 1-3 have no closed form.
struct PositionPlan {
    int position_case = 0;  // a PositionCase
    Vec3 o;
    ArmLines lines;
    std::string clause;
};
std::variant<PositionPlan, CaseReason> position_plan(const ArmLines& arm);

// Whether arm has 6 revolute joints, as the three-parallel cases and the general solver need;
// if not, why (what: the case, e.g. "the general solver").
bool six_revolute(const ArmLines& arm, const std::string& what, CaseReason& why);

// The three-parallel case's two sub-cases, by axes 5 and 6 (internal 4, 5) of its lines (axes
// 2-4 parallel to lines.h[1] = hp): how far they are from meeting (their distance / scale; at
// 0 its two-angle system has rank 1), and how far axis 6 is from turning parallel to hp about
// axis 5 (the difference of the angles axis 5 makes with axis 6 and with hp [rad]; at 0 the
// wrist aligns, a family). Near either, not at it, the class's quartic loses roots near an
// aligned wrist, and detect_three_parallel leaves the arm to the general solver.
void wrist_subcase_gaps(const ArmLines& lines, double& meeting, double& aligning);

// The lines of a 6-joint arm near a class (its tests passing to arm.tolerance) moved onto
// the class exactly, kind: "spherical" (axes 4-6 through their meeting point, and joints 1-3
// onto their position case), "three-parallel" (axes 2-4 along axis 2, and axes 5, 6 onto the
// sub-cases they are near, see wrist_subcase_gaps) or "parallel-base" (axes 1-3 along axis 1);
// each line moves by at most arm.tolerance (times the size).
// The result's tolerance is kClassTolerance. False where the lines are not near that class.
bool snap_to_class(const ArmLines& arm, const char* kind, ArmLines& out);

}  // namespace armkit
