#include "armkit/ik_classify.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "armkit/fk.hpp"
#include "armkit/random.hpp"
#include "armkit/tolerances.hpp"

namespace armkit {

namespace {

//: Random configurations at which generic_rank evaluates the Jacobian.
constexpr int kRankSamples = 8;

// Every case's reason set to one (the arm itself has no closed form).
void no_case(ArmCase& out, const std::string& kind, const std::string& description) {
    out.kind = kind;
    out.description = description;
    for (CaseReason& why : out.why_not) why = CaseReason{CaseFit::Degenerate, description};
}

}  // namespace

int generic_rank(const Chain& chain, double tol, int joints, bool position_only) {
    Random random(0);
    int rank = 0;
    const int n = chain.n, moving = joints < 0 ? n : std::min(joints, n), rows = position_only ? 3 : 6;
    for (int s = 0; s < kRankSamples; ++s) {
        double q[kMaxJoints] = {};
        for (int j = 0; j < moving; ++j) {
            const bool finite = std::isfinite(chain.lower[j]) && std::isfinite(chain.upper[j]);
            q[j] = random.uniform(finite ? chain.lower[j] : -1.0, finite ? chain.upper[j] : 1.0);
        }
        Vec3 axes[kMaxJoints], points[kMaxJoints];
        const Pose T = joint_axes(chain, q, axes, points);
        double J[6 * kMaxJoints];
        jacobian_from_axes(T, axes, points, chain.prismatic.data(), n, J);
        const Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>> A(J, 6, n);
        const Eigen::VectorXd S =
            Eigen::JacobiSVD<Eigen::MatrixXd>(A.topLeftCorner(rows, moving)).singularValues();
        int r = 0;
        for (int k = 0; k < int(S.size()); ++k) r += S(k) > tol * S(0);
        rank = std::max(rank, r);
    }
    return rank;
}

ArmCase classify(const Chain& chain) {
    ArmCase out;
    const int n = chain.n;
    if (n > kMaxCaseJoints) {
        no_case(out, "none", std::to_string(n) + " joints: a redundant arm has infinitely many solutions per pose, so "
                                                 "no closed form; use numeric IK");
        return out;
    }
    const ArmLines arm = arm_lines(chain);
    out.lines = arm;
    for (int i = 0; i + 1 < n; ++i)
        if (!arm.prismatic[i] && !arm.prismatic[i + 1] && parallel(arm, i, i + 1) &&
            distance_to_line(arm, arm.p[i + 1], i) <= arm.tolerance * arm.scale) {
            no_case(out, "none", "axes " + std::to_string(i + 1) + " and " + std::to_string(i + 2) +
                                     " are the same line: the arm has fewer degrees of freedom than joints, no closed "
                                     "form; use numeric IK");
            return out;
        }
    const int rank = generic_rank(chain), full = std::min(6, n);
    if (rank < full) {
        const std::string r = std::to_string(rank);
        no_case(out, "rank-deficient",
                "the Jacobian has rank " + r + " at every configuration tried (not " + std::to_string(full) +
                    "): the " + std::to_string(n) + " joints move the tool in only " + r +
                    " independent directions, so the arm reaches a " + r +
                    "-dimensional set of poses and has no closed form here; use numeric IK");
        return out;
    }
    for (int c = 0; c < kCaseCount; ++c) {
        const CaseEntry& entry = kCases[c];
        if (!entry.whole_pose) {
            out.why_not[c] = CaseReason{CaseFit::PositionOnly, "joints 1-3 carrying a tool point: a case of position "
                                                               "IK (robot.ik_position), not of a whole pose"};
            continue;
        }
        if (out.chosen >= 0 && c == kCaseCount - 1) {  // the general solver: only where no class applies
            out.why_not[c] = CaseReason{CaseFit::Earlier, std::string("not needed: the ") + kCases[out.chosen].name +
                                                              " case applies"};
            continue;
        }
        CaseDetection found = entry.detect(arm);
        if (auto* why = std::get_if<CaseReason>(&found)) {
            out.why_not[c] = std::move(*why);
            continue;
        }
        if (out.chosen >= 0) {
            out.why_not[c] = CaseReason{CaseFit::Earlier, std::string("applies too, but the ") +
                                                              kCases[out.chosen].name + " case is listed first"};
            continue;
        }
        CaseFound& match = std::get<CaseFound>(found);
        out.chosen = c;
        out.kind = std::move(match.kind);
        out.description = std::move(match.description);
        out.max_solutions = entry.candidates;
        out.geometry = std::move(match.geometry);
        out.lines = match.lines;
        out.polish = match.polish;
        out.why_not[c] = CaseReason{};
    }
    if (out.chosen >= 0) return out;
    const CaseReason& spherical = out.why_not[0];
    if (spherical.fit == CaseFit::Position)
        out.description = spherical.text + "; use numeric IK";
    else if (n == 6)  // two or more prismatic joints (the general solver takes every other 6-joint arm)
        out.description = "6 joints in no closed-form class, and " + out.why_not[kCaseCount - 1].text;
    else
        out.description = std::to_string(n) + " joints that are not a planar 2R/3R arm or a SCARA (parallel revolute "
                                               "axes, prismatic along them): no closed form; use numeric IK";
    return out;
}

ClosedForm closed_form_of(const Chain& chain, const ArmCase& arm) {
    ClosedForm cf;
    cf.chain = chain;
    cf.geometry = arm.geometry;
    for (int j = 0; j < chain.n; ++j) {
        cf.index[j] = arm.lines.index[j];
        cf.sign[j] = arm.lines.sign[j];
    }
    cf.M_inv = inverse(arm.lines.M);
    cf.inverted = arm.lines.inverted;
    cf.k = kCases[arm.chosen].candidates;
    // fewer than 6 joints are over-determined: FK decides; for 6 every subproblem checks its
    // own existence, so the flags are exact, except where a quartic or an elimination is polished
    cf.verify = chain.n < 6 || arm.polish;
    cf.polish = arm.polish;
    if (std::holds_alternative<GeneralGeometry>(arm.geometry)) {
        cf.polish_steps = kGeneralNewtonSteps;
        cf.polish_stop = kPolished * arm.lines.size;
    }
    cf.verify_tolerance = kCandidateTolerance * arm.lines.scale;
    return cf;
}

}  // namespace armkit
