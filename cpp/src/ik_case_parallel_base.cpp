// Three parallel axes 1-3 (ik_case_parallel_base.hpp): two equations in q6, q4 alone (a
// two-angle system), then q5, q1 + q2 + q3 and a planar 2R.
#include "armkit/ik_case_parallel_base.hpp"

#include <cmath>

#include "armkit/subproblems.hpp"
#include "armkit/two_angle.hpp"

namespace armkit {

// Axes 1-3 parallel: (q6, q4), then q5, q1 + q2 + q3 and a planar 2R: 8 candidates. Their
// motion keeps h-components, which leaves two equations in q4 and q6: h . R4 h5 =
// (R_G^T h) . R6^T h5 (orientation, since R5 h5 = h5) and h . e4 o5 = h . G e6^-1 o5.
void solve_case(const ParallelBaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    const Vec3 h = g.hp, h3 = g.h[3], h4 = g.h[4], h5 = g.h[5];
    const Vec3 p0 = g.p[0], p1 = g.p[1], p2 = g.p[2];
    const Vec3 o4 = g.o4, o5 = g.o5, o6 = g.o6;
    const int n = g.n;
    const Vec3 gh = mul_transposed(R, h);  // R_G^T h
    const TrigCoeffs e1 = trig_coeffs(gh, -h5, h4);
    TrigCoeffs e2 = trig_coeffs(gh, -h5, o5 - o6);
    e2.constant += dot(R * o6 + t, h);
    const Mat2 P{{{e1.cos_coeff, e1.sin_coeff}, {e2.cos_coeff, e2.sin_coeff}}};
    const double r[2] = {g.f[0] - e1.constant, g.f[1] - e2.constant};
    AngleCandidates pair = two_angle_system(g, P, r);  // t1 = q6, t2 = q4
    const Vec3 z = R * o4 + t;
    // q5, q1 + q2 + q3 and the planar 2R's target for (q4, q6)
    auto wrist = [&](double q4, double q6, Angle1& q5, double& theta, double side) {
        // q5: R5^T (R4^T h) = R6 R_G^T h
        q5 = sp1(rotate(-h3, q4, h), rotate(h5, q6, gh), -h4);
        // q1 + q2 + q3: R123 = R_G R6^T R5^T R4^T, applied to a normal of h
        const Vec3 turned = rotate(-h5, q6, rotate(-h4, q5.t, rotate(-h3, q4, g.u)));
        theta = sp1(g.u, R * turned, h).t;
        // planar part: e1 e2 e3 y = z with y = e4 e5 e6 o4, z = G o4
        const Vec3 y6 = o6 + rotate(h5, q6, o4 - o6);
        if (q5.free) {  // axis 5 parallel to h: y = c5 + R(h, s5 q5) w, theta + s5 q5 constant
            const double s5 = sign_of(dot(rotate(h3, q4, h4), h));
            const Vec3 c5 = o4 + rotate(h3, q4, o5 - o4), w = rotate(h3, q4, y6 - o5);
            const Vec3 A = (z - p0) - rotate(h, theta + s5 * q5.t, w);
            wrist_family_representative(g, s5, q5.t, theta, A, c5 - p2, p1 - p0, p2 - p1, side);
        }
        Vec3 y = o5 + rotate(h4, q5.t, y6 - o5);
        y = o4 + rotate(h3, q4, y - o4);
        return (z - p0) - rotate(h, theta, y - p2);
    };
    const SlotAngles slots = family_slots(g, P, r, pair, wrist, p1 - p0, p2 - p1);
    for (int i = 0; i < 4; ++i) {
        Angle1 q5;
        double theta;
        Planar2 q12{};
        for (int b = 0; b < 2; ++b) {
            // a family of q5 (axis 5 parallel to h): one loop of it per elbow slot as well
            const double side = b == 0 ? 1.0 : -1.0;
            const double q4 = slots.t2[i][b], q6 = slots.t1[i][b];
            if (b == 0 || q4 != slots.t2[i][0] || q6 != slots.t1[i][0] || q5.free)
                q12 = planar_2r(h, p1 - p0, p2 - p1, wrist(q4, q6, q5, theta, side));
            const int s = 2 * i + b;
            double* qs = q + n * s;
            qs[0] = q12.ta[b];
            qs[1] = q12.tb[b];
            qs[2] = theta - q12.ta[b] - q12.tb[b];
            qs[3] = q4;
            qs[4] = q5.t;
            qs[5] = q6;
            valid[s] = slots.valid[i][b] && q12.ok[b];
            family[s] = pair.free[i] || q5.free || q12.free;
        }
    }
}

// ------------------------------------------------------------------------ detection

Detection<ParallelBaseGeometry> detect_parallel_base(const ArmLines& arm) {
    CaseReason why;
    if (!six_revolute(arm, "the parallel-base case", why)) return why;
    for (const ArmLines& lines : {arm, reversed(arm)}) {
        if (!three_parallel_block(lines, 0)) continue;
        const ArmLines a = aligned(lines, {0, 1, 2}, lines.h[0]);
        // two equations in q6, q4; o4, o5, o6 points of axes 4-6 (o4, o5 closest to each other)
        ParallelBaseGeometry g;
        static_cast<CaseChain&>(g) = a;
        const Vec3* h = a.h;
        const Vec3 hp = h[0];
        Vec3 o5b;
        closest_points(a.p[3], h[3], a.p[4], h[4], g.o4, g.o5);
        closest_points(a.p[4], h[4], a.p[5], h[5], o5b, g.o6);
        const TrigCoeffs r0 = trig_coeffs(hp, h[3], h[4]), r1 = trig_coeffs(hp, h[3], g.o5 - g.o4);
        const double Q[2][2] = {{r0.cos_coeff, r0.sin_coeff}, {r1.cos_coeff, r1.sin_coeff}};
        static_cast<TwoAngleSystem&>(g) = two_angle_constants(Q, r0.constant, r1.constant + dot(hp, g.o4), true);
        g.hp = hp;
        g.u = unit_normal(hp);
        const bool polish = !g.rank1;
        const std::string axes = axes_text(a, {0, 1, 2});
        return CaseMatch<ParallelBaseGeometry>{
            g, a, "three-parallel", "three parallel axes: axes " + axes + " are parallel: closed-form IK, up to 8 solutions",
            polish};
    }
    return CaseReason{CaseFit::Axes, "neither axes 1, 2, 3 nor 4, 5, 6 are parallel (with the axes next to them not)"};
}

}  // namespace armkit
