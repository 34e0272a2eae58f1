// A spherical wrist (ik_case_spherical.hpp): joints 1-3 place the wrist centre (the point
// case), then the wrist turns h6 (SP2) and a normal of it (SP1) into place.
#include "armkit/ik_case_spherical.hpp"

#include <cmath>

#include "armkit/subproblems.hpp"

namespace armkit {

namespace {

// R123^T v for arm joints qa (3): a direction of the target in the wrist's frame.
Vec3 in_wrist_frame(const CaseChain& g, const double* qa, Vec3 v) {
    for (int j = 0; j < 3; ++j)
        if (!g.prismatic[j]) v = rotate(-g.h[j], qa[j], v);
    return v;
}

// The sine of the angle between axis 6's target direction a (in the wrist's frame) and
// axis 4: 0 where the wrist is aligned.
double wrist_misalignment(const CaseChain& g, Vec3 a) { return norm(cross(a, g.h[3])); }

// The point x (at q = 0) moved by arm joints qa (3).
Vec3 moved_by_arm(const CaseChain& g, const double* qa, Vec3 x) {
    for (int j = 2; j >= 0; --j)
        x = g.prismatic[j] ? x + qa[j] * g.h[j] : g.p[j] + rotate(g.h[j], qa[j], x - g.p[j]);
    return x;
}

//: Values of a free arm joint tried for a second member of its family.
constexpr int kFreeArmSamples = 16;

// Arm joint j's axis and a point of it (g.h[j], g.p[j] at q = 0) moved by the arm joints
// before it, qa (3).
void arm_line(const CaseChain& g, const double* qa, int j, Vec3& h, Vec3& p) {
    h = g.h[j], p = g.p[j];
    for (int k = j - 1; k >= 0; --k) {
        if (g.prismatic[k]) {
            p = p + qa[k] * g.h[k];
        } else {
            h = rotate(g.h[k], qa[k], h);
            p = g.p[k] + rotate(g.h[k], qa[k], p - g.p[k]);
        }
    }
}

// How far the arm joints other than the free one (free) are from moving the wrist centre
// along one line at qa (3): the smaller singular value of their two centre velocities over
// the larger (|va x vb| / s_max^2, exact where it is small; 0 where both vanish). Where it
// is 0 the family of the free joint is doubly singular even with the wrist turned away from
// aligned (the folded Staubli TX40 at q2 = 0: axes 1 and 3 then move the centre the same way).
double arm_conditioning(const PointGeometry& g, const double* qa, int free) {
    const Vec3 centre = moved_by_arm(g, qa, g.c);
    Vec3 v[2];
    int m = 0;
    for (int j = 0; j < 3; ++j) {
        if (j == free) continue;
        Vec3 h, p;
        arm_line(g, qa, j, h, p);
        v[m++] = g.prismatic[j] ? h : cross(h, centre - p);
    }
    const double a = dot(v[0], v[0]), d = dot(v[1], v[1]), b = dot(v[0], v[1]);
    const double largest = 0.5 * (a + d + std::sqrt((a - d) * (a - d) + 4.0 * b * b));
    return largest > 0.0 ? norm(cross(v[0], v[1])) / largest : 0.0;
}

// A free arm triple (its wrist centre on the axis of one of its revolute joints, which
// then turns freely while the wrist follows) whose family is doubly singular at the closed
// form's member gets a second member in an unused slot of arm: the free joint's value, of
// kFreeArmSamples round the circle, where the family is farthest from doubly singular (the
// smaller of the wrist's misalignment and arm_conditioning, largest). Doubly singular: the
// wrist aligned (within kNearlyAligned), or the other two arm joints moving the centre
// along one line (arm_conditioning within kNullSpace, as the family walk counts a singular
// value as zero). There the Jacobian lacks the family's direction (the wrist would have to
// turn infinitely fast; or two null directions, one of them off the family), so the walk to
// near cannot follow the family from it; from the second member it can.
void second_free_arm_member(const PointGeometry& g, const Mat3& R, ArmCandidates& arm) {
    const Vec3 axis6 = R * g.h[5];
    bool first[4];  // the triples of the closed form (not the members added here)
    for (int i = 0; i < 4; ++i) first[i] = arm.valid[i] && arm.free[i];
    for (int i = 0; i < 4; ++i) {
        if (!first[i]) continue;
        const Vec3 centre = moved_by_arm(g, arm.q[i], g.c);
        for (int j = 0; j < 3; ++j) {
            if (g.prismatic[j]) continue;
            double turned[3] = {arm.q[i][0], arm.q[i][1], arm.q[i][2]};
            turned[j] += 1.0;
            if (norm(moved_by_arm(g, turned, g.c) - centre) > kOutTolerance * g.size) continue;
            if (wrist_misalignment(g, in_wrist_frame(g, arm.q[i], axis6)) > kNearlyAligned &&
                arm_conditioning(g, arm.q[i], j) > kNullSpace)
                break;  // singly singular: the walk follows the family from the member itself
            int spare = -1;
            for (int e = 0; e < 4 && spare < 0; ++e)
                if (!arm.valid[e]) spare = e;
            if (spare < 0) return;
            double best = -1.0;
            for (int m = 0; m < kFreeArmSamples; ++m) {
                turned[j] = arm.q[i][j] + (m + 0.5) * (kTwoPi / kFreeArmSamples);
                const double farthest = std::fmin(wrist_misalignment(g, in_wrist_frame(g, turned, axis6)),
                                                  arm_conditioning(g, turned, j));
                if (farthest <= best) continue;
                best = farthest;
                for (int c = 0; c < 3; ++c) arm.q[spare][c] = turned[c];
            }
            arm.q[spare][j] = wrap_angle(arm.q[spare][j]);
            arm.valid[spare] = arm.free[spare] = true;
            break;
        }
    }
}

}  // namespace

// Spherical wrist: joints 1-3 for the wrist centre, then the wrist: 8 candidates.
void solve_case(const SphericalGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    const Vec3 h3 = g.h[3], h4 = g.h[4], h5 = g.h[5], u = g.u;
    const int n = g.n;
    ArmCandidates arm = wrist_centre_joints(g, R * g.c + t);
    second_free_arm_member(g, R, arm);
    // the wrist's rotation R_w = R123^T R_G, applied to h6 and a normal u of it
    for (int i = 0; i < 4; ++i) {
        const Vec3 a = in_wrist_frame(g, arm.q[i], R * h5), b = in_wrist_frame(g, arm.q[i], R * u);
        const AnglePairs2 q45 = sp2(a, h5, -h3, h4);
        // the wrist within kNearlyAligned of aligned: its family may be exact (q1-q3 carry
        // errors of up to ~1e-8 from a double root), walked later
        const bool nearly_aligned = wrist_misalignment(g, a) <= kNearlyAligned;
        for (int m = 0; m < 2; ++m) {
            // R6 u = R5^T R4^T R_w u
            const Vec3 target = rotate(-h4, q45.t2[m], rotate(-h3, q45.t1[m], b));
            const Angle1 q6 = sp1(u, target, h5);
            const int s = 2 * i + m;
            double* qs = q + n * s;
            qs[0] = arm.q[i][0];
            qs[1] = arm.q[i][1];
            qs[2] = arm.q[i][2];
            qs[3] = q45.t1[m];
            qs[4] = q45.t2[m];
            qs[5] = q6.t;
            valid[s] = arm.valid[i] && q45.ok[m];
            family[s] = arm.free[i] || q45.free1 || q45.free2 || q6.free || nearly_aligned;
        }
    }
}

// ------------------------------------------------------------------------ detection

namespace {

// The spherical wrist of `arm` (base: arm is a reversed chain, its wrist the user's base).
Detection<SphericalGeometry> spherical_on(const ArmLines& arm, bool base) {
    const std::string where = base ? "base" : "wrist";
    if (arm.prismatic[3] || arm.prismatic[4] || arm.prismatic[5])
        return CaseReason{CaseFit::Prismatic, "a joint of axes " + axes_text(arm, {3, 4, 5}) + " is prismatic"};
    Vec3 centre;
    if (!meet(arm, 3, 4, 5, centre))
        return CaseReason{CaseFit::Axes, "axes " + axes_text(arm, {3, 4, 5}) + " do not meet at one point"};
    const std::string meets = "spherical " + where + ": axes " + axes_text(arm, {3, 4, 5}) + " meet at one point";
    auto plan = position_plan(arm);
    if (auto* why = std::get_if<CaseReason>(&plan)) return CaseReason{why->fit, meets + ", but " + why->text};
    const PositionPlan& p = std::get<PositionPlan>(plan);
    SphericalGeometry g;
    static_cast<PointGeometry&>(g) = point_geometry(p, centre);
    g.u = unit_normal(p.lines.h[5]);
    return CaseMatch<SphericalGeometry>{g, p.lines, base ? "spherical-base" : "spherical-wrist",
                                        meets + " and " + p.clause + ": closed-form IK, up to 8 solutions",
                                        p.position_case == int(PositionCase::General123)};
}

}  // namespace

Detection<SphericalGeometry> detect_spherical(const ArmLines& arm) {
    if (arm.n != 6)
        return CaseReason{CaseFit::Joints, "a spherical wrist or base needs 6 joints, not " + std::to_string(arm.n)};
    Detection<SphericalGeometry> wrist = spherical_on(arm, false);
    if (std::holds_alternative<CaseMatch<SphericalGeometry>>(wrist)) return wrist;
    Detection<SphericalGeometry> base = spherical_on(reversed(arm), true);
    if (std::holds_alternative<CaseMatch<SphericalGeometry>>(base)) return base;
    const CaseReason &w = std::get<CaseReason>(wrist), &b = std::get<CaseReason>(base);
    if (w.fit == CaseFit::Position) return w;  // the more specific reason
    if (b.fit == CaseFit::Position) return b;
    return CaseReason{w.fit, w.text + ", nor do axes " + axes_text(arm, {0, 1, 2})};
}

}  // namespace armkit
