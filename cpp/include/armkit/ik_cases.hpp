// The closed-form case solvers, one target at a time, behind one case interface.
//
// The chain is taken as screw axes at q = 0: T(q) = exp(xi_1 q_1) ... exp(xi_n q_n) M, so a
// target gives G = T M^-1, the motion of the joints alone. One solver per geometric case
// splits G (rotation R, translation t) into Paden-Kahan subproblems (subproblems.hpp) and
// writes every candidate into the rows of q (k x n, internal joint order), with valid and
// family flags (k), k at most kMaxCandidates.
//
// The interface: a case is a geometry struct (what its solver needs of the chain, made once
// per chain; it derives from CaseChain, the joint lines every case starts from) and a solve
// function over it, listed in kCases (the registry: name, candidates per pose). A
// CaseGeometry holds one of them (a std::variant in kCases' order), so each case carries
// only its own constants: the general 6R solver's 3 KB table is held by pointer in its own
// geometry. solve_pose dispatches on the variant. Adding a case: a geometry struct and a
// solve function (a header/source pair), an entry in CaseGeometryData and kCases, its
// binding (bind_closed_form.cpp) and its preparation and detection (armkit/ik/closed_form.py,
// armkit/ik/structure.py).
#pragma once

#include <cstdint>
#include <memory>
#include <variant>

#include "armkit/ik_general.hpp"
#include "armkit/vec.hpp"

namespace armkit {

//: Largest number of candidates per pose of any case solver (the general 6R arm's 16):
//: every per-pose buffer is sized by it.
constexpr int kMaxCandidates = kGeneralRoots;
//: Joints of a case's chain at most (6: the closed-form cases and the general 6R arm).
constexpr int kMaxCaseJoints = 6;

// How joints 1-3 of a spherical-wrist arm (or a point case) place the wrist centre
// (armkit.ik.cases.POSITION_CASES, same order).
enum class PositionCase : int {
    Parallel23 = 0, Parallel12 = 1, Intersect23 = 2, Intersect12Revolute = 3, Intersect12Prismatic = 4,
    General123 = 5
};
//: Their names (armkit.ik.cases.POSITION_CASES), in PositionCase's order.
constexpr const char* kPositionCaseNames[] = {"parallel-23", "parallel-12", "intersect-23", "intersect-12-revolute",
                                              "intersect-12-prismatic", "general-123"};

// The joint lines every case starts from: internal axes h and points p at q = 0 (n each),
// which joints are prismatic, and the length scale [m]: 1 + the largest coordinate of p.
struct CaseChain {
    int n = 0;
    Vec3 h[kMaxCaseJoints], p[kMaxCaseJoints];
    std::uint8_t prismatic[kMaxCaseJoints] = {};
    double size = 1.0;
};

// The constant part of a two-angle system P x(t1) - Q x(t2) = r, x(t) = [cos t, sin t],
// with P and r from the pose: Q, its inverse (zero when of rank 1), the constant f that r
// is measured from, and for Q of rank 1 the combinations lam (holds t1 alone) and mu.
struct TwoAngleSystem {
    double Q[2][2] = {{0, 0}, {0, 0}};
    double Q_inv[2][2] = {{0, 0}, {0, 0}};
    double f[2] = {0, 0};
    bool rank1 = false;
    double lam[2] = {0, 0}, mu[2] = {0, 0};
    bool snap_t2 = true;  // snap t2 to a double root at tangency (off where t2 is refined from sines)
};

// Joints 1-3 carry a point c (the wrist centre, or the tool point of position IK) to a
// target: o, where axes 1 and 2 (or 2 and 3) meet; for general axes (General123) the
// closest points o2, o3 of axes 2 and 3 and the two-angle system in q1, q3.
struct PointGeometry : CaseChain, TwoAngleSystem {
    PositionCase position_case = PositionCase::Parallel23;
    Vec3 c, o, o2, o3;
};

// A spherical wrist (axes 4-6 meet at c): joints 1-3 as PointGeometry, then the wrist; u a
// unit normal of h6.
struct SphericalGeometry : PointGeometry {
    Vec3 u;
};

// Axes 2-4 parallel to hp (u a unit normal of it): a two-angle system in q1, q5; p5, p6 the
// closest points of axes 5 and 6; the values q5_aligned (aligned of them) that turn axis 6
// parallel to hp, and b_aligned = |h5 x hp| |h5 x h6|.
struct ThreeParallelGeometry : CaseChain, TwoAngleSystem {
    Vec3 hp, u, p5, p6;
    double q5_aligned[4] = {0, 0, 0, 0};
    int aligned = 0;
    double b_aligned = 0.0;
};

// Axes 1-3 parallel to hp (u a unit normal of it): a two-angle system in q6, q4; o4, o5, o6
// points of axes 4-6 (o4, o5 closest to each other).
struct ParallelBaseGeometry : CaseChain, TwoAngleSystem {
    Vec3 hp, u, o4, o5, o6;
};

// SCARA / planar 2R or 3R: revolute joints (2 or 3) about hp (u a unit normal of it), at
// most one prismatic joint along it; y a point moved by the first two revolute joints only.
struct PlanarGeometry : CaseChain {
    Vec3 hp, u, y;
    int revolute[3] = {0, 0, 0};
    int revolute_count = 0;
    int prismatic_joint = -1;
};

// Any 6R arm: the elimination's constants (ik_general.hpp), made once, shared by copies.
struct GeneralGeometry : CaseChain {
    std::shared_ptr<const GeneralSixR> arm;
};

// One case's geometry; the alternatives in the order of kCases.
using CaseGeometry = std::variant<SphericalGeometry, ThreeParallelGeometry, ParallelBaseGeometry, PlanarGeometry,
                                  PointGeometry, GeneralGeometry>;

// One entry of the registry: the case's name (armkit.ik.cases.CASE_NAMES) and candidates per pose.
struct CaseEntry {
    const char* name;
    int candidates;
};

// The registry, in the order of CaseGeometry's alternatives. Point: joints 1-3 of any chain
// carry a tool point to a target position (position IK); general: any 6R arm, the last case.
constexpr CaseEntry kCases[] = {
    {"spherical", 8}, {"three-parallel", 8}, {"parallel-base", 8}, {"planar", 2}, {"point", 4}, {"general", kGeneralRoots},
};
constexpr int kCaseCount = int(sizeof(kCases) / sizeof(kCases[0]));
static_assert(kCaseCount == int(std::variant_size_v<CaseGeometry>), "one registry entry per case");

// The registry entry of a geometry's case.
inline const CaseEntry& case_entry(const CaseGeometry& g) { return kCases[g.index()]; }

// The joint lines of a geometry's chain.
inline const CaseChain& case_chain(const CaseGeometry& g) {
    return std::visit([](const auto& c) -> const CaseChain& { return c; }, g);
}

// The case solvers (ik_cases.cpp; ik_general.cpp for the general arm): every candidate for
// the joint motion G = (R, t) into q (k x n, row-major, internal joint order), valid and
// family (k), k = the case's candidates.
void solve_case(const SphericalGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);
void solve_case(const ThreeParallelGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);
void solve_case(const ParallelBaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);
void solve_case(const PlanarGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);
void solve_case(const PointGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);
void solve_case(const GeneralGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family);

// Every candidate of the geometry's case (dispatch on the variant).
inline void solve_pose(const CaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    std::visit([&](const auto& c) { solve_case(c, R, t, q, valid, family); }, g);
}

}  // namespace armkit
