// SCARA and planar 2R/3R arms (ik_case_planar.hpp): angle sum, height along the axes, planar 2R.
#include "armkit/ik_case_planar.hpp"

#include "armkit/subproblems.hpp"

namespace armkit {

// SCARA / planar arm: angle sum, height, planar 2R: 2 candidates.
void solve_case(const PlanarGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    const Vec3 h = g.hp, y = g.y;
    const int* rev = g.revolute;
    const int n = g.n;
    const double theta = sp1(g.u, R * g.u, h).t;
    const Vec3 Gy = R * y + t;
    const double slide = g.prismatic_joint >= 0 ? dot(Gy - y, h) : 0.0;
    const Vec3 p_a = g.p[rev[0]], p_b = g.p[rev[1]];
    const Planar2 ab = planar_2r(h, p_b - p_a, y - p_b, (Gy - slide * h) - p_a);
    for (int b = 0; b < 2; ++b) {
        double* qs = q + n * b;
        for (int j = 0; j < n; ++j) qs[j] = 0.0;
        qs[rev[0]] = ab.ta[b];
        qs[rev[1]] = ab.tb[b];
        if (g.revolute_count == 3) qs[rev[2]] = theta - ab.ta[b] - ab.tb[b];
        if (g.prismatic_joint >= 0) qs[g.prismatic_joint] = slide;
        valid[b] = ab.ok[b];
        family[b] = ab.free;
    }
}

// ------------------------------------------------------------------------ detection

Detection<PlanarGeometry> detect_planar(const ArmLines& arm) {
    if (arm.n < 2 || arm.n > 4)
        return CaseReason{CaseFit::Joints, "a SCARA or planar arm has 2 to 4 joints, not " + std::to_string(arm.n)};
    PlanarGeometry g;
    int prismatic[kMaxCaseJoints], prismatic_count = 0;
    for (int j = 0; j < arm.n; ++j) {
        if (!arm.prismatic[j] && g.revolute_count < 3) g.revolute[g.revolute_count] = j;
        if (arm.prismatic[j]) prismatic[prismatic_count++] = j;
        else ++g.revolute_count;
    }
    if (g.revolute_count < 2 || g.revolute_count > 3 || prismatic_count > 1)
        return CaseReason{CaseFit::Prismatic,
                          "a SCARA or planar arm has 2 or 3 revolute joints and at most one prismatic"};
    for (int j = 0; j < arm.n; ++j)
        if (!parallel(arm, g.revolute[0], j))
            return CaseReason{CaseFit::Axes, "axes " + axes_text(arm, {g.revolute[0], j}) + " are not parallel"};
    ArmLines a = arm;
    for (int j = 0; j < arm.n; ++j)
        if (dot(arm.h[j], arm.h[g.revolute[0]]) < 0) a.h[j] = -arm.h[j], a.sign[j] = -arm.sign[j];
    static_cast<CaseChain&>(g) = a;
    g.hp = a.h[g.revolute[0]];
    g.u = unit_normal(g.hp);
    g.y = g.revolute_count == 3 ? a.p[g.revolute[2]] : a.p[g.revolute[1]] + g.u;
    g.prismatic_joint = prismatic_count ? prismatic[0] : -1;
    std::string axes;
    for (int r = 0; r < g.revolute_count; ++r) axes += (r ? ", " : "") + std::to_string(a.index[g.revolute[r]] + 1);
    std::string kind, what;
    if (prismatic_count) {
        kind = "scara";
        what = "SCARA: revolute axes " + axes + " are parallel and prismatic joint " +
               std::to_string(a.index[prismatic[0]] + 1) + " moves along them";
    } else {
        kind = "planar-" + std::to_string(g.revolute_count) + "r";
        what = "planar " + std::to_string(g.revolute_count) + "R arm: axes " + axes + " are parallel";
    }
    return CaseMatch<PlanarGeometry>{g, a, kind, what + ": closed-form IK, up to 2 solutions", false};
}

}  // namespace armkit
