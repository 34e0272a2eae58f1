// The closed-form cases, one target at a time, behind one case interface: the registry.
//
// The chain is taken as screw axes at q = 0: T(q) = exp(xi_1 q_1) ... exp(xi_n q_n) M, so a
// target gives G = T M^-1, the motion of the joints alone. One solver per geometric case
// splits G (rotation R, translation t) into Paden-Kahan subproblems (subproblems.hpp) and
// writes every candidate into the rows of q (k x n, internal joint order), with valid and
// family flags (k), k at most kMaxCandidates.
//
// The interface: a case is a geometry struct (what its solver needs of the chain, made once
// per chain; it derives from CaseChain, the joint lines every case starts from, and holds
// only its own constants), a solve_case overload over it and a detect function (the chain's
// lines to its geometry, or the reason it does not apply: ik_detect.hpp), declared in the
// case's header ik_case_<name>.hpp and defined in its source ik_case_<name>.cpp (the general
// 6R arm: ik_general.hpp / .cpp). CaseGeometry holds one of them (a std::variant), and
// kCases lists them in the variant's order with their names, candidates per pose and detect
// functions: this file is the one place that registers a case. solve_pose dispatches on the
// variant; classify (ik_classify.hpp) runs the detect functions in the registry's order.
//
// Adding a case: its header/source pair (geometry, solve_case, detect); its alternative in
// CaseGeometry and its entry in kCases (here); its binding class (cpp/src/bind_closed_form.cpp,
// for tests that build a geometry by hand); its test.
#pragma once

#include <string>
#include <utility>
#include <variant>

#include "armkit/case_chain.hpp"
#include "armkit/ik_case_parallel_base.hpp"
#include "armkit/ik_case_planar.hpp"
#include "armkit/ik_case_point.hpp"
#include "armkit/ik_case_spherical.hpp"
#include "armkit/ik_case_three_parallel.hpp"
#include "armkit/ik_general.hpp"

namespace armkit {

//: Largest number of candidates per pose of any case solver (the general 6R arm's 16):
//: every per-pose buffer is sized by it.
constexpr int kMaxCandidates = kGeneralRoots;

// One case's geometry; the alternatives in the order of kCases.
using CaseGeometry = std::variant<SphericalGeometry, ThreeParallelGeometry, ParallelBaseGeometry, PlanarGeometry,
                                  PointGeometry, GeneralGeometry>;

// A case that applies to a chain: CaseMatch of any case.
struct CaseFound {
    CaseGeometry geometry;
    ArmLines lines;
    std::string kind, description;
    bool polish = false;
};
using CaseDetection = std::variant<CaseFound, CaseReason>;

// A case's detect function with its geometry put into the variant.
template <class G, Detection<G> (*Detect)(const ArmLines&)>
CaseDetection detect_as(const ArmLines& arm) {
    Detection<G> found = Detect(arm);
    if (auto* m = std::get_if<CaseMatch<G>>(&found))
        return CaseFound{CaseGeometry(std::move(m->geometry)), m->lines, std::move(m->kind), std::move(m->description),
                         m->polish};
    return std::get<CaseReason>(found);
}

// One entry of the registry: the case's name (armkit.ik.cases.CASE_NAMES), candidates per
// pose, whether it solves a whole pose (not only a position), and its detect function.
struct CaseEntry {
    const char* name;
    int candidates;
    bool whole_pose;
    CaseDetection (*detect)(const ArmLines&);
};

// The registry, in the order of CaseGeometry's alternatives (classify takes the first that
// applies). Point: joints 1-3 of any chain carry a tool point to a target position (position
// IK); general: any 6R or 5R1P arm, the last case.
constexpr CaseEntry kCases[] = {
    {"spherical", 8, true, &detect_as<SphericalGeometry, detect_spherical>},
    {"three-parallel", 8, true, &detect_as<ThreeParallelGeometry, detect_three_parallel>},
    {"parallel-base", 8, true, &detect_as<ParallelBaseGeometry, detect_parallel_base>},
    {"planar", 2, true, &detect_as<PlanarGeometry, detect_planar>},
    {"point", 4, false, &detect_as<PointGeometry, detect_point>},
    {"general", kGeneralRoots, true, &detect_as<GeneralGeometry, detect_general>},
};
constexpr int kCaseCount = int(sizeof(kCases) / sizeof(kCases[0]));
static_assert(kCaseCount == int(std::variant_size_v<CaseGeometry>), "one registry entry per case");

// The registry entry of a geometry's case.
inline const CaseEntry& case_entry(const CaseGeometry& g) { return kCases[g.index()]; }

// The joint lines of a geometry's chain.
inline const CaseChain& case_chain(const CaseGeometry& g) {
    return std::visit([](const auto& c) -> const CaseChain& { return c; }, g);
}

// Every candidate for the joint motion G = (R, t) of the geometry's case into q (k x n,
// row-major, internal joint order), valid and family (k), k = case_entry(g).candidates.
inline void solve_pose(const CaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    std::visit([&](const auto& c) { solve_case(c, R, t, q, valid, family); }, g);
}

}  // namespace armkit
