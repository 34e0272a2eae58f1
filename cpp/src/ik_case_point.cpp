// Joints 1-3 carry a point to a target (ik_case_point.hpp): SP3 / SP4 / SP2 / planar 2R by
// which pair of axes 1-3 meets or is parallel, a quadratic for a prismatic third joint (a
// linear equation when axes 1, 2 are parallel), a two-angle system in q1, q3 for general axes.
#include "armkit/ik_case_point.hpp"

#include <algorithm>
#include <cmath>

#include "armkit/subproblems.hpp"

namespace armkit {

namespace {

// Both s with |v + s h| = d, and whether each is a real root. Within kTangentTolerance of
// tangency (the line touches the sphere) the double root once: the square root of a
// rounding error (~1e-8 |v|) would split it.
Angles2 slide_to_sphere(Vec3 v, Vec3 h, double d) {
    const double b = dot(v, h), size = dot(v, v) + d * d;
    const double disc = b * b - dot(v, v) + d * d;
    const bool exists = disc >= -kOutTolerance * size;
    const bool touch = disc <= kTangentTolerance * size;
    const double root = touch ? 0.0 : std::sqrt(disc);
    return {{-b + root, -b - root}, {exists, exists && !touch}, false};
}

// Joints 1-3 for general axes: a two-angle system in q1, q3 (o2, o3: the closest points of
// axes 2 and 3), then q2 by SP1.
ArmCandidates general_position(const PointGeometry& g, Vec3 w) {
    const Vec3 h0 = g.h[0], h1 = g.h[1], h2 = g.h[2], p0 = g.p[0];
    const Vec3 o2 = g.o2, o3 = g.o3, c = g.c;
    const Vec3 u = w - p0;
    TrigCoeffs height = trig_coeffs(h1, -h0, u);
    TrigCoeffs distance = trig_coeffs(2.0 * (p0 - o2), -h0, u);
    height.constant += dot(h1, p0 - o2);
    distance.constant += dot(p0 - o2, p0 - o2) + dot(u, u);
    const Mat2 P{{{height.cos_coeff, height.sin_coeff}, {distance.cos_coeff, distance.sin_coeff}}};
    const double r[2] = {g.f[0] - height.constant, g.f[1] - distance.constant};
    const AngleCandidates pair = two_angle_system(g, P, r);
    ArmCandidates out{};
    for (int i = 0; i < 4; ++i) {
        const Vec3 y = p0 + rotate(-h0, pair.t1[i], u);
        const Vec3 x = o3 + rotate(h2, pair.t2[i], c - o3);
        const Angle1 q2 = sp1(x - o2, y - o2, h1, g.size);
        out.q[i][0] = pair.t1[i];
        out.q[i][1] = q2.t;
        out.q[i][2] = pair.t2[i];
        out.valid[i] = pair.valid[i];
        out.free[i] = pair.free[i] || q2.free;
    }
    return out;
}

}  // namespace

// Joints 1-3 that put the wrist centre g.c at w: four triples.
ArmCandidates wrist_centre_joints(const PointGeometry& g, Vec3 w) {
    if (g.position_case == PositionCase::General123) return general_position(g, w);
    const Vec3 c = g.c, o = g.o;
    const Vec3 h0 = g.h[0], h1 = g.h[1], h2 = g.h[2];
    const Vec3 p0 = g.p[0], p1 = g.p[1], p2 = g.p[2];
    ArmCandidates out{};
    auto put = [&out](int s, double q1, double q2, double q3, bool valid, bool free) {
        out.q[s][0] = q1;
        out.q[s][1] = q2;
        out.q[s][2] = q3;
        out.valid[s] = valid;
        out.free[s] = free;
    };
    switch (g.position_case) {
        case PositionCase::Parallel23: {
            const Angles2 q1 = sp4(h1, w - p0, -h0, dot(h1, c - p0));
            for (int i = 0; i < 2; ++i) {
                const Vec3 y = p0 + rotate(-h0, q1.t[i], w - p0);
                const Planar2 q23 = planar_2r(h1, p2 - p1, c - p2, y - p1);
                for (int j = 0; j < 2; ++j)
                    put(2 * i + j, q1.t[i], q23.ta[j], q23.tb[j], q1.ok[i] && q23.ok[j], q1.free || q23.free);
            }
            break;
        }
        case PositionCase::Parallel12: {
            const Angles2 q3 = sp4(h0, c - p2, h2, dot(w - p2, h0));
            for (int i = 0; i < 2; ++i) {
                const Vec3 x = p2 + rotate(h2, q3.t[i], c - p2);
                const Planar2 q12 = planar_2r(h0, p1 - p0, x - p1, w - p0);
                for (int j = 0; j < 2; ++j)
                    put(2 * i + j, q12.ta[j], q12.tb[j], q3.t[i], q3.ok[i] && q12.ok[j], q3.free || q12.free);
            }
            break;
        }
        case PositionCase::Intersect23: {
            const Angles2 q1 = sp3(w - p0, o - p0, -h0, norm(c - o));
            for (int i = 0; i < 2; ++i) {
                const Vec3 y = p0 + rotate(-h0, q1.t[i], w - p0);
                const AnglePairs2 q23 = sp2(y - o, c - o, -h1, h2, g.size);
                for (int j = 0; j < 2; ++j)
                    put(2 * i + j, q1.t[i], q23.t1[j], q23.t2[j], q1.ok[i] && q23.ok[j],
                        q1.free || q23.free1 || q23.free2);
            }
            break;
        }
        case PositionCase::Parallel12Prismatic: {
            // rotations about axes 1, 2 (parallel) keep the height along them: the slide sets it
            const double q3 = dot(h0, w - c) / dot(h0, h2);
            const Planar2 q12 = planar_2r(h0, p1 - p0, c + q3 * h2 - p1, w - p0);
            for (int j = 0; j < 2; ++j) put(j, q12.ta[j], q12.tb[j], q3, q12.ok[j], q12.free);
            break;
        }
        default: {  // Intersect12Revolute / Intersect12Prismatic
            const bool slide = g.position_case == PositionCase::Intersect12Prismatic;
            const double d = norm(w - o);
            const Angles2 q3 = slide ? slide_to_sphere(c - o, h2, d) : sp3(c - p2, o - p2, h2, d);
            for (int i = 0; i < 2; ++i) {
                const Vec3 x = slide ? c + q3.t[i] * h2 : p2 + rotate(h2, q3.t[i], c - p2);
                const AnglePairs2 q12 = sp2(w - o, x - o, -h0, h1, g.size);
                for (int j = 0; j < 2; ++j)
                    put(2 * i + j, q12.t1[j], q12.t2[j], q3.t[i], q3.ok[i] && q12.ok[j],
                        q3.free || q12.free1 || q12.free2);
            }
            break;
        }
    }
    return out;
}

// Joints 1-3 carrying the tool point g.c to w = t (position IK; G = T, no M^-1): 4 candidates.
void solve_case(const PointGeometry& g, const Mat3&, Vec3 w, double* q, bool* valid, bool* family) {
    const ArmCandidates a = wrist_centre_joints(g, w);
    for (int s = 0; s < 4; ++s) {
        for (int j = 0; j < 3; ++j) q[3 * s + j] = a.q[s][j];
        valid[s] = a.valid[s];
        family[s] = a.valid[s] && a.free[s];
    }
}

// ------------------------------------------------------------------------ detection

PointGeometry point_geometry(const PositionPlan& plan, Vec3 c) {
    PointGeometry g;
    static_cast<CaseChain&>(g) = plan.lines;
    g.position_case = PositionCase(plan.position_case);
    g.c = c;
    g.o = plan.o;
    if (g.position_case == PositionCase::General123) {
        // with y = e1^-1 G c (q1) and x = e3 c (q3), e2 x = y keeps the height along axis 2
        // and the distance to a point o2 of it, each first order in its angle
        const Vec3* h = plan.lines.h;
        const Vec3* p = plan.lines.p;
        closest_points(p[1], h[1], p[2], h[2], g.o2, g.o3);
        const Vec3 d = g.o3 - g.o2, v = c - g.o3;
        const TrigCoeffs height = trig_coeffs(h[1], h[2], v), distance = trig_coeffs(2.0 * d, h[2], v);
        const double Q[2][2] = {{height.cos_coeff, height.sin_coeff}, {distance.cos_coeff, distance.sin_coeff}};
        static_cast<TwoAngleSystem&>(g) =
            two_angle_constants(Q, height.constant + dot(h[1], d), distance.constant + dot(d, d) + dot(v, v), true);
    }
    return g;
}

Detection<PointGeometry> detect_point(const ArmLines& arm) {
    if (arm.n != 3) return CaseReason{CaseFit::Joints, "position IK of joints 1-3 takes a chain of 3 joints"};
    auto plan = position_plan(arm);
    if (auto* why = std::get_if<CaseReason>(&plan)) return *why;
    const PositionPlan& p = std::get<PositionPlan>(plan);
    return CaseMatch<PointGeometry>{point_geometry(p, arm.M.position()), p.lines, "point", p.clause, false};
}

}  // namespace armkit
