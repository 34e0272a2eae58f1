#include "armkit/ik_detect.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "armkit/fk.hpp"
#include "armkit/ik_case_point.hpp"
#include "armkit/tolerances.hpp"

namespace armkit {

namespace {

// arm.size (1 + the largest |coordinate| of the points) and arm.scale (M's position too).
void measure(ArmLines& arm) {
    double largest = 0.0;
    for (int j = 0; j < arm.n; ++j)
        largest = std::max({largest, std::fabs(arm.p[j].x), std::fabs(arm.p[j].y), std::fabs(arm.p[j].z)});
    arm.size = 1.0 + largest;
    const Vec3 t = arm.M.position();
    arm.scale = 1.0 + std::max({largest, std::fabs(t.x), std::fabs(t.y), std::fabs(t.z)});
}

}  // namespace

ArmLines arm_lines(const Chain& chain) {
    if (chain.n < 1 || chain.n > kMaxCaseJoints)
        throw std::invalid_argument("arm_lines: a case's chain has 1 to 6 joints");
    ArmLines arm;
    arm.n = chain.n;
    const double zero[kMaxJoints] = {};
    Vec3 axes[kMaxJoints], points[kMaxJoints];
    arm.M = joint_axes(chain, zero, axes, points);
    for (int j = 0; j < chain.n; ++j) {
        arm.h[j] = axes[j];
        arm.p[j] = points[j];
        arm.prismatic[j] = chain.prismatic[j];
        arm.index[j] = j;
        arm.sign[j] = 1.0;
    }
    measure(arm);
    return arm;
}

ArmLines first_lines(const ArmLines& arm, int count, Vec3 c) {
    ArmLines out = arm;
    out.n = count;
    out.M = Pose();
    out.M(0, 3) = c.x, out.M(1, 3) = c.y, out.M(2, 3) = c.z;
    measure(out);
    return out;
}

ArmLines reversed(const ArmLines& arm) {
    ArmLines out = arm;
    const Pose M_inv = inverse(arm.M);
    const Mat3 R_t = M_inv.rotation();
    const Vec3 t = arm.M.position();
    const int n = arm.n;
    for (int j = 0; j < n; ++j) {
        const int k = n - 1 - j;
        out.h[j] = R_t * arm.h[k];
        out.p[j] = R_t * (arm.p[k] - t);
        out.prismatic[j] = arm.prismatic[k];
        out.index[j] = arm.index[k];
        out.sign[j] = -arm.sign[k];
    }
    out.M = M_inv;
    out.inverted = !arm.inverted;
    measure(out);
    return out;
}

ArmLines aligned(const ArmLines& arm, std::initializer_list<int> joints, Vec3 h) {
    ArmLines out = arm;
    for (int j : joints)
        if (dot(arm.h[j], h) < 0) out.h[j] = -arm.h[j], out.sign[j] = -arm.sign[j];
    return out;
}

bool parallel(const ArmLines& arm, int i, int j) { return norm(cross(arm.h[i], arm.h[j])) <= arm.tolerance; }

double distance_to_line(const ArmLines& arm, Vec3 x, int i) {
    const Vec3 d = x - arm.p[i];
    return norm(d - dot(d, arm.h[i]) * arm.h[i]);
}

void closest_points(Vec3 pa, Vec3 ha, Vec3 pb, Vec3 hb, Vec3& a, Vec3& b) {
    // least squares s ha - t hb = pb - pa (the normal equations of two non-parallel lines)
    const Vec3 d = pb - pa;
    const double c = dot(ha, hb), aa = dot(ha, ha), bb = dot(hb, hb), da = dot(d, ha), db = dot(d, hb);
    const double det = aa * bb - c * c;
    const double s = det > 0.0 ? (bb * da - c * db) / det : 0.0;
    const double t = det > 0.0 ? (c * da - aa * db) / det : 0.0;
    a = pa + s * ha;
    b = pb + t * hb;
}

bool intersection(const ArmLines& arm, int i, int j, Vec3& point) {
    if (arm.prismatic[i] || arm.prismatic[j] || parallel(arm, i, j)) return false;
    Vec3 a, b;
    closest_points(arm.p[i], arm.h[i], arm.p[j], arm.h[j], a, b);
    point = 0.5 * (a + b);
    return norm(a - b) <= arm.tolerance * arm.scale;
}

bool meet(const ArmLines& arm, int i, int j, int k, Vec3& point) {
    if (!intersection(arm, i, j, point) || parallel(arm, j, k)) return false;
    return distance_to_line(arm, point, k) <= arm.tolerance * arm.scale;
}

Vec3 unit_normal(Vec3 h) {
    const double a[3] = {std::fabs(h.x), std::fabs(h.y), std::fabs(h.z)};
    const int smallest = int(std::min_element(a, a + 3) - a);
    const Vec3 e = smallest == 0 ? Vec3{1, 0, 0} : (smallest == 1 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
    const Vec3 u = cross(h, e);
    return (1.0 / norm(u)) * u;
}

TwoAngleSystem two_angle_constants(const double (&Q)[2][2], double f0, double f1, bool snap_t2) {
    TwoAngleSystem s;
    Eigen::Matrix2d A;
    A << Q[0][0], Q[0][1], Q[1][0], Q[1][1];
    const Eigen::JacobiSVD<Eigen::Matrix2d> svd(A, Eigen::ComputeFullU);
    const Eigen::Vector2d S = svd.singularValues();
    const Eigen::Matrix2d U = svd.matrixU();
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) s.Q[i][j] = Q[i][j];
    s.f[0] = f0, s.f[1] = f1;
    s.rank1 = S(1) <= kRankOne * S(0);
    if (!s.rank1) {
        const Eigen::Matrix2d inv = A.inverse();
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) s.Q_inv[i][j] = inv(i, j);
    }
    s.lam[0] = U(0, 1), s.lam[1] = U(1, 1);
    s.mu[0] = U(0, 0), s.mu[1] = U(1, 0);
    s.snap_t2 = snap_t2;
    return s;
}

std::string axes_text(const ArmLines& arm, std::initializer_list<int> joints) {
    int numbers[kMaxCaseJoints], count = 0;
    for (int j : joints) numbers[count++] = arm.index[j] + 1;
    std::sort(numbers, numbers + count);
    std::string text;
    for (int c = 0; c < count; ++c) text += (c ? ", " : "") + std::to_string(numbers[c]);
    return text;
}

std::variant<PositionPlan, CaseReason> position_plan(const ArmLines& arm) {
    const bool revolute[3] = {!arm.prismatic[0], !arm.prismatic[1], !arm.prismatic[2]};
    PositionPlan plan;
    plan.lines = arm;
    const bool all = revolute[0] && revolute[1] && revolute[2];
    if (all && parallel(arm, 1, 2) && !parallel(arm, 0, 1)) {
        plan.position_case = int(PositionCase::Parallel23);
        plan.lines = aligned(arm, {1, 2}, arm.h[1]);
        plan.clause = "axes " + axes_text(arm, {1, 2}) + " are parallel";
        return plan;
    }
    if (revolute[0] && revolute[1] && intersection(arm, 0, 1, plan.o)) {
        plan.position_case = int(arm.prismatic[2] ? PositionCase::Intersect12Prismatic
                                                  : PositionCase::Intersect12Revolute);
        plan.clause = "axes " + axes_text(arm, {0, 1}) + " meet";
        return plan;
    }
    if (all) {
        if (intersection(arm, 1, 2, plan.o)) {
            plan.position_case = int(PositionCase::Intersect23);
            plan.clause = "axes " + axes_text(arm, {1, 2}) + " meet";
            return plan;
        }
        if (parallel(arm, 0, 1) && !parallel(arm, 1, 2)) {
            plan.position_case = int(PositionCase::Parallel12);
            plan.lines = aligned(arm, {0, 1}, arm.h[0]);
            plan.clause = "axes " + axes_text(arm, {0, 1}) + " are parallel";
            return plan;
        }
        if (!parallel(arm, 0, 1) && !parallel(arm, 1, 2)) {
            plan.position_case = int(PositionCase::General123);
            plan.clause = "axes " + axes_text(arm, {0, 1, 2}) + " neither meet nor are parallel (a quartic)";
            return plan;
        }
    }
    return CaseReason{CaseFit::Position, "joints " + axes_text(arm, {0, 1, 2}) +
                                             " are not solved in closed form here (a prismatic joint, or "
                                             "degenerate axes)"};
}

bool six_revolute(const ArmLines& arm, const std::string& what, CaseReason& why) {
    if (arm.n != 6) {
        why = CaseReason{CaseFit::Joints, what + " needs 6 joints, not " + std::to_string(arm.n)};
        return false;
    }
    for (int j = 0; j < 6; ++j)
        if (arm.prismatic[j]) {
            const std::string joint = std::to_string(arm.index[j] + 1);
            why = CaseReason{CaseFit::Prismatic,
                             "joint " + joint + " is prismatic: " + what + " takes revolute joints only"};
            return false;
        }
    return true;
}

void wrist_subcase_gaps(const ArmLines& lines, double& meeting, double& aligning) {
    const Vec3 h5 = lines.h[4], h6 = lines.h[5], hp = lines.h[1];
    Vec3 a, b;
    closest_points(lines.p[4], h5, lines.p[5], h6, a, b);
    meeting = norm(a - b) / lines.scale;
    // the angles axis 5 makes with axis 6 and with hp, each folded into [0, pi / 2]
    const double to6 = std::atan2(norm(cross(h5, h6)), std::fabs(dot(h5, h6)));
    const double to_hp = std::atan2(norm(cross(h5, hp)), std::fabs(dot(h5, hp)));
    aligning = std::fabs(to6 - to_hp);
}

namespace {

// Axes 5 and 6 of a three-parallel arm's lines (internal 4, 5) moved onto the class's
// sub-cases where they are within lines.tolerance of them (wrist_subcase_gaps): made to meet
// (through the middle of their closest points), and axis 6 turned about its point nearest
// axis 5, in the plane of axes 5 and 6, to the angle with axis 5 that hp makes.
void snap_wrist_subcases(const ArmLines& lines, ArmLines& out) {
    double meeting, aligning;
    wrist_subcase_gaps(lines, meeting, aligning);
    const Vec3 h5 = lines.h[4], h6 = lines.h[5];
    Vec3 a, b;
    closest_points(lines.p[4], h5, lines.p[5], h6, a, b);
    out.p[5] = b;
    if (meeting <= lines.tolerance) out.p[4] = out.p[5] = 0.5 * (a + b);
    if (aligning <= lines.tolerance) {
        const double c = dot(h5, h6), target = std::fabs(dot(h5, lines.h[1])) * (c < 0.0 ? -1.0 : 1.0);
        const Vec3 w = h6 - c * h5;
        out.h[5] = target * h5 + (std::sqrt(std::fmax(0.0, 1.0 - target * target)) / norm(w)) * w;
    }
}

}  // namespace

bool snap_to_class(const ArmLines& arm, const char* kind, ArmLines& out) {
    out = arm;
    out.tolerance = kClassTolerance;
    const std::string which = kind;
    if (which == "three-parallel" || which == "parallel-base") {
        const int first = which == "three-parallel" ? 1 : 0;
        bool any = false;
        for (const ArmLines& lines : {arm, reversed(arm)}) {
            bool block = parallel(lines, first, first + 1) && parallel(lines, first, first + 2);
            if (!block) continue;
            out = lines;
            for (int j = first + 1; j <= first + 2; ++j)
                out.h[j] = dot(lines.h[j], lines.h[first]) < 0 ? -lines.h[first] : lines.h[first];
            if (first == 1) snap_wrist_subcases(lines, out);
            any = true;
            break;
        }
        out.tolerance = kClassTolerance;
        return any;
    }
    for (const ArmLines& lines : {arm, reversed(arm)}) {
        Vec3 centre;
        if (lines.prismatic[3] || lines.prismatic[4] || lines.prismatic[5] || !meet(lines, 3, 4, 5, centre)) continue;
        auto plan = position_plan(lines);
        if (!std::holds_alternative<PositionPlan>(plan)) continue;
        const PositionPlan& p = std::get<PositionPlan>(plan);
        out = lines;
        for (int j = 3; j < 6; ++j) out.p[j] = centre;
        switch (PositionCase(p.position_case)) {
            case PositionCase::Parallel23: out.h[2] = dot(lines.h[2], lines.h[1]) < 0 ? -lines.h[1] : lines.h[1]; break;
            case PositionCase::Parallel12: out.h[1] = dot(lines.h[1], lines.h[0]) < 0 ? -lines.h[0] : lines.h[0]; break;
            case PositionCase::Intersect12Revolute:
            case PositionCase::Intersect12Prismatic: out.p[0] = out.p[1] = p.o; break;
            case PositionCase::Intersect23: out.p[1] = out.p[2] = p.o; break;
            case PositionCase::General123: break;
        }
        out.tolerance = kClassTolerance;
        return true;
    }
    return false;
}

}  // namespace armkit
