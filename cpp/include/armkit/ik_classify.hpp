// Which case solves a chain, and why each other case does not: the registry's detect
// functions run in order (ik_cases.hpp), after the tests that no case can pass (two axes on
// one line, a Jacobian of deficient rank, more than 6 joints). Then the per-pose loop's
// constants (ClosedForm) from the chosen case.
#pragma once

#include <string>

#include "armkit/chain.hpp"
#include "armkit/closed_form.hpp"
#include "armkit/ik_cases.hpp"

namespace armkit {

// The case chosen for a chain (chosen: its index in kCases, -1 for none), the kind of arm
// (armkit.ik.ArmStructure.kind: a case's kind, "rank-deficient" or "none"), one sentence on
// why, and for every registered case why it does not apply (fit Applies for the chosen one).
struct ArmCase {
    int chosen = -1;
    std::string kind = "none", description;
    int max_solutions = 0;
    CaseGeometry geometry;
    ArmLines lines;
    bool polish = false;
    CaseReason why_not[kCaseCount];
};

ArmCase classify(const Chain& chain);

// The rank of the chain's Jacobian at a generic configuration: the largest over
// kRankSamples seeded random configurations inside the limits ([-1, 1] where a limit is
// infinite), singular values below tol times the largest counting as zero. `joints` >= 0:
// only the first `joints` joints move (the others at 0) and only their columns count;
// `position_only`: only the tool point's rows (how many directions it can move in).
int generic_rank(const Chain& chain, double tol = kRankTolerance, int joints = -1, bool position_only = false);

// The per-pose loop's constants for the chosen case of `arm` (arm.chosen >= 0).
ClosedForm closed_form_of(const Chain& chain, const ArmCase& arm);

}  // namespace armkit
