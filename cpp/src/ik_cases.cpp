// The closed-form case solvers (port of armkit/ik/cases.py; see ik_cases.hpp).
//
// Spherical wrist: joints 1-3 place the wrist centre (SP3 / SP4 / SP2 / planar 2R by which
// pair of axes 1-3 meets or is parallel; a prismatic third joint gives a quadratic; general
// axes a two-angle system), then the wrist turns h6 (SP2) and a normal of it (SP1) into
// place. Three parallel axes 2-4: two equations in q1, q5 alone (two_angle_system), then
// q6 (SP1), q2 + q3 + q4 (SP1) and a planar 2R; axes 1-3 parallel the same in q6, q4.
// SCARA and planar 2R/3R: angle sum, height along the axes, planar 2R.
#include "armkit/ik_cases.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "armkit/quartic.hpp"
#include "armkit/subproblems.hpp"

namespace armkit {

namespace {

// The 2x2 matrix of a two-angle system P x(t1) - Q x(t2) = r, x(t) = [cos t, sin t].
struct Mat2 {
    double m[2][2];
};

// The four candidates of a two-angle system.
struct AngleCandidates {
    double t1[4], t2[4];
    bool valid[4], free[4];
};

// The three joints of each of four candidates for joints 1-3 (spherical wrist).
struct ArmCandidates {
    double q[4][3];
    bool valid[4], free[4];
};

double sign_of(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

// ------------------------------------------------------------ two-angle system

// t1 with m . x(t1) = mr (or as close as it gets). When the first equation leaves t1 free,
// the second, mP . x(t1) - mQ . x(t2) = mr, still ties t2 to it; this t1 puts its
// right-hand side at 0, the middle of the range t2 can reach.
double family_representative(double m0, double m1, double mr) {
    const double m = std::sqrt(m0 * m0 + m1 * m1);
    if (m == 0.0) return 0.0;
    return std::atan2(m1, m0) + std::acos(std::min(std::max(mr / m, -1.0), 1.0));
}

// The system when Q has rank 1: lam holds t1 alone, mu then t2.
void rank1(const TwoAngleSystem& g, const Mat2& P, const double* r, double size, AngleCandidates& out) {
    const double l0 = g.lam[0], l1 = g.lam[1], m0 = g.mu[0], m1 = g.mu[1];
    const double lP0 = l0 * P.m[0][0] + l1 * P.m[1][0], lP1 = l0 * P.m[0][1] + l1 * P.m[1][1];
    Angles2 first = solve_trig_linear(lP0, lP1, r[0] * l0 + r[1] * l1, size, true);
    const double mP0 = m0 * P.m[0][0] + m1 * P.m[1][0], mP1 = m0 * P.m[0][1] + m1 * P.m[1][1];
    const double mr = r[0] * m0 + r[1] * m1;
    if (first.free) {  // t1 free: the member whose t2 equation is easiest (middle of its range)
        const double rep = family_representative(mP0, mP1, mr);
        first.t[0] = first.t[1] = rep;
    }
    const double mQ0 = m0 * g.Q[0][0] + m1 * g.Q[1][0], mQ1 = m0 * g.Q[0][1] + m1 * g.Q[1][1];
    for (int i = 0; i < 2; ++i) {
        const double rhs = mP0 * std::cos(first.t[i]) + mP1 * std::sin(first.t[i]) - mr;
        const Angles2 second = solve_trig_linear(mQ0, mQ1, rhs, size, g.snap_t2);
        for (int j = 0; j < 2; ++j) {
            out.t1[2 * i + j] = first.t[i];
            out.t2[2 * i + j] = second.t[j];
            out.valid[2 * i + j] = first.ok[i] && second.ok[j];
            out.free[2 * i + j] = first.free || second.free;
        }
    }
}

// F(t) = A0 + A1 cos t + B1 sin t + A2 cos 2t + B2 sin 2t and F'(t).
void quartic_equation(const double* A, double t, double& F, double& dF) {
    const double c = std::cos(t), s = std::sin(t), c2 = std::cos(2.0 * t), s2 = std::sin(2.0 * t);
    F = A[0] + A[1] * c + A[2] * s + A[3] * c2 + A[4] * s2;
    dF = -A[1] * s + A[2] * c - 2.0 * A[3] * s2 + 2.0 * A[4] * c2;
}

// The k-th derivative of F (A as in quartic_equation) at t:
// d^k/dt^k (a cos mt + b sin mt) = m^k (a cos(mt + k pi/2) + b sin(mt + k pi/2)).
double trig_derivative(const double* A, double t, int k) {
    const double shift = 0.5 * k * 3.141592653589793, m2 = std::pow(2.0, k);
    return (k == 0 ? A[0] : 0.0) + A[1] * std::cos(t + shift) + A[2] * std::sin(t + shift) +
           m2 * (A[3] * std::cos(2.0 * t + shift) + A[4] * std::sin(2.0 * t + shift));
}

// t2 of the two-angle system for t1: x(t2) = Q^-1 (P x(t1) - r), its direction.
double second_angle(const TwoAngleSystem& g, const Mat2& P, const double* r, double t1) {
    const auto& Qi = g.Q_inv;
    const double c = std::cos(t1), s = std::sin(t1);
    const double v0 = P.m[0][0] * c + P.m[0][1] * s - r[0], v1 = P.m[1][0] * c + P.m[1][1] * s - r[1];
    return std::atan2(Qi[1][0] * v0 + Qi[1][1] * v1, Qi[0][0] * v0 + Qi[0][1] * v1);
}

// Roots of the quartic in exp(i t1), with t2 from Q^-1; F's coefficients into A (5).
void quartic(const TwoAngleSystem& g, const Mat2& P, const double* r, AngleCandidates& out, double* A) {
    const auto& Qi = g.Q_inv;
    const double W00 = Qi[0][0] * P.m[0][0] + Qi[0][1] * P.m[1][0];
    const double W01 = Qi[0][0] * P.m[0][1] + Qi[0][1] * P.m[1][1];
    const double W10 = Qi[1][0] * P.m[0][0] + Qi[1][1] * P.m[1][0];
    const double W11 = Qi[1][0] * P.m[0][1] + Qi[1][1] * P.m[1][1];
    const double w0[2] = {Qi[0][0] * r[0] + Qi[0][1] * r[1], Qi[1][0] * r[0] + Qi[1][1] * r[1]};
    const double S00 = W00 * W00 + W10 * W10, S11 = W01 * W01 + W11 * W11, S01 = W00 * W01 + W10 * W11;
    const double m0 = W00 * w0[0] + W10 * w0[1], m1 = W01 * w0[0] + W11 * w0[1];
    // F(t) = |W x(t) - w0|^2 - 1 = A0 + A1 cos t + B1 sin t + A2 cos 2t + B2 sin 2t
    A[0] = 0.5 * (S00 + S11) + w0[0] * w0[0] + w0[1] * w0[1] - 1.0;
    A[1] = -2.0 * m0, A[2] = -2.0 * m1;       // A1, B1
    A[3] = 0.5 * (S00 - S11), A[4] = S01;     // A2, B2
    // z^2 F in z = exp(i t): coefficients of z^4 ... z^0
    const Complex coeffs[5] = {Complex(A[3], -A[4]) / 2.0, Complex(A[1], -A[2]) / 2.0, Complex(A[0], 0.0),
                               Complex(A[1], A[2]) / 2.0, Complex(A[3], A[4]) / 2.0};
    double size = 0.0;
    for (const Complex& c : coeffs) size = std::max(size, std::abs(c));
    if (std::abs(coeffs[0]) > kQuarticLeading * size) {
        Complex roots[4];
        quartic_roots(coeffs, roots);
        for (int i = 0; i < 4; ++i) {
            double t = std::atan2(roots[i].imag(), roots[i].real());
            for (int step = 0; step < 3; ++step) {  // Newton on F(t), the real equation
                double F, dF;
                quartic_equation(A, t, F, dF);
                if (std::abs(dF) > 1e-300) t -= std::min(std::max(F / dF, -0.1), 0.1);
            }
            out.t1[i] = t;
            out.valid[i] = std::abs(std::abs(roots[i]) - 1.0) <= kUnitCircle;
        }
    } else {  // degenerate: F is of degree 1, a cos t + b sin t = -A0
        const Angles2 lin = solve_trig_linear(A[1], A[2], -A[0], size, true);
        for (int i = 0; i < 4; ++i) {
            out.t1[i] = lin.t[i % 2];
            out.valid[i] = i < 2 ? lin.ok[i] : false;
        }
    }
    for (int i = 0; i < 4; ++i) out.t2[i] = second_angle(g, P, r, out.t1[i]);
}

// P x(t1) - Q x(t2) - r (F) and its derivatives by t1 (d1) and t2 (d2).
void system_residual(const double (&Q)[2][2], const Mat2& P, const double* r, double t1, double t2, double* F,
                     double* d1, double* d2) {
    const double c1 = std::cos(t1), s1 = std::sin(t1), c2 = std::cos(t2), s2 = std::sin(t2);
    F[0] = P.m[0][0] * c1 + P.m[0][1] * s1 - Q[0][0] * c2 - Q[0][1] * s2 - r[0];
    F[1] = P.m[1][0] * c1 + P.m[1][1] * s1 - Q[1][0] * c2 - Q[1][1] * s2 - r[1];
    d1[0] = -P.m[0][0] * s1 + P.m[0][1] * c1;
    d1[1] = -P.m[1][0] * s1 + P.m[1][1] * c1;
    d2[0] = Q[0][0] * s2 - Q[0][1] * c2;
    d2[1] = Q[1][0] * s2 - Q[1][1] * c2;
}

// Newton steps on P x(t1) - Q x(t2) = r itself (Q^-1 may be ill-conditioned); returns the
// remaining residual max |P x(t1) - Q x(t2) - r|.
double polish(const double (&Q)[2][2], const Mat2& P, const double* r, double& t1, double& t2) {
    double F[2], d1[2], d2[2];
    for (int step = 0; step < 6; ++step) {  // quadratic convergence; linear near a double root
        system_residual(Q, P, r, t1, t2, F, d1, d2);
        const double det = d1[0] * d2[1] - d1[1] * d2[0];
        const double scale = 1.0 + std::max(std::abs(d1[0]), std::abs(d1[1])) *
                                       std::max(std::abs(d2[0]), std::abs(d2[1]));
        if (std::abs(det) > kTwoAngleSingular * scale) {
            t1 -= std::min(std::max((d2[1] * F[0] - d2[0] * F[1]) / det, -0.1), 0.1);
            t2 -= std::min(std::max((d1[0] * F[1] - d1[1] * F[0]) / det, -0.1), 0.1);
        }
    }
    system_residual(Q, P, r, t1, t2, F, d1, d2);
    return std::max(std::abs(F[0]), std::abs(F[1]));
}

// The size of the terms of P x(t1) - Q x(t2) = r that depend on the pose.
double system_size(const Mat2& P, const double* r) {
    return 1.0 + std::max(std::max(std::abs(P.m[0][0]), std::abs(P.m[0][1])),
                          std::max(std::abs(P.m[1][0]), std::abs(P.m[1][1]))) +
           std::max(std::abs(r[0]), std::abs(r[1]));
}

// t2 for t1 of a candidate of the two-angle system whose t1 is free (branch: candidate
// index i, whose t2 branch is i % 2 when Q has rank 1); ok: that t2 exists.
double family_t2(const TwoAngleSystem& g, const Mat2& P, const double* r, double t1, int i, double size, bool& ok) {
    ok = true;
    if (!g.rank1) return second_angle(g, P, r, t1);
    const double m0 = g.mu[0], m1 = g.mu[1];
    const double mP0 = m0 * P.m[0][0] + m1 * P.m[1][0], mP1 = m0 * P.m[0][1] + m1 * P.m[1][1];
    const double mQ0 = m0 * g.Q[0][0] + m1 * g.Q[1][0], mQ1 = m0 * g.Q[0][1] + m1 * g.Q[1][1];
    const double rhs = mP0 * std::cos(t1) + mP1 * std::sin(t1) - (r[0] * m0 + r[1] * m1);
    const Angles2 second = solve_trig_linear(mQ0, mQ1, rhs, size, g.snap_t2);
    ok = second.ok[i % 2];
    return second.t[i % 2];
}

// A multiple root of the system near (t1, t2) (residual: its residual), put there exactly.
// Newton steps reach a root of F of multiplicity m only to about eps^(1/m) (1e-8 double,
// 1e-4 quadruple; F's coefficients carry Q^-1's condition too); there F^(m-1) has a simple
// root, which Newton steps on it reach to eps. For m = 4, 3, 2 within 1e-3 of t1: taken
// where it solves P x(t1) - Q x(t2) = r no worse than (t1, t2) or to the rounding level of
// terms of size (the m roots are then one, as far as the equations can tell).
void merge_multiple_root(const TwoAngleSystem& g, const Mat2& P, const double* r, const double* A, double size,
                         double& t1, double& t2, double& residual) {
    const double rounding = 8.0 * std::numeric_limits<double>::epsilon() * size;
    for (int m = 4; m >= 2; --m) {
        double c = t1;
        bool near = true;
        for (int step = 0; step < 6 && near; ++step) {
            const double slope = trig_derivative(A, c, m);
            if (!(std::abs(slope) > 1e-300)) break;
            c -= trig_derivative(A, c, m - 1) / slope;
            near = std::abs(c - t1) <= kMultipleRootReach;
        }
        if (!near) continue;
        const double c2 = second_angle(g, P, r, c);
        double F[2], d1[2], d2[2];
        system_residual(g.Q, P, r, c, c2, F, d1, d2);
        const double at_c = std::max(std::abs(F[0]), std::abs(F[1]));
        if (at_c <= std::max(residual, rounding)) {
            t1 = c, t2 = c2, residual = at_c;
            return;
        }
    }
}

// All (t1, t2) with P x(t1) - Q x(t2) = r (Q = g.Q fixed by the chain; P, r by the pose).
// Q of rank 1: a combination of the equations holds t1 alone, then t2 the same way (up to
// 2 x 2 pairs). Otherwise x(t2) = Q^-1 (P x(t1) - r) on the unit circle is a quartic in
// exp(i t1) (then Newton steps on the equations themselves); where it vanishes, every t1
// (candidate 0, t1 = 0). free: t1 (or t2) arbitrary (family_t2 then gives t2 for any t1).
AngleCandidates two_angle_system(const TwoAngleSystem& g, const Mat2& P, const double* r) {
    const double size = system_size(P, r);
    AngleCandidates out{};
    if (g.rank1) {
        rank1(g, P, r, size, out);
        return out;
    }
    double A[5];
    quartic(g, P, r, out, A);
    const double amplified = std::max(std::max(std::abs(g.Q_inv[0][0]), std::abs(g.Q_inv[0][1])),
                                      std::max(std::abs(g.Q_inv[1][0]), std::abs(g.Q_inv[1][1]))) * size;
    if (std::abs(A[0]) + std::abs(A[1]) + std::abs(A[2]) + std::abs(A[3]) + std::abs(A[4]) <=
        kIdentityTolerance * (1.0 + amplified)) {
        // F vanishes: the two equations are one, every t1 has its t2 (a family)
        for (int i = 0; i < 4; ++i) {
            out.t1[i] = 0.0;
            out.t2[i] = second_angle(g, P, r, 0.0);
            out.valid[i] = i == 0;
            out.free[i] = true;
        }
        return out;
    }
    for (int i = 0; i < 4; ++i) {
        double residual = polish(g.Q, P, r, out.t1[i], out.t2[i]);
        merge_multiple_root(g, P, r, A, size, out.t1[i], out.t2[i], residual);
        out.valid[i] = out.valid[i] && residual <= kTwoAngleResidual * size;
        out.free[i] = false;
    }
    return out;
}

// ------------------------------------------------------------- spherical wrist

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

// A free arm triple (its wrist centre on the axis of one of its revolute joints, which
// then turns freely while the wrist follows) whose wrist is aligned (within kNearlyAligned)
// gets a second member in an unused slot of arm: the free joint where the wrist is farthest
// from aligned. At the first the Jacobian lacks the family's direction (the wrist would
// have to turn infinitely fast), which the walk to near follows; at the second it has it.
void second_free_arm_member(const PointGeometry& g, const Mat3& R, ArmCandidates& arm) {
    const Vec3 axis6 = R * g.h[5];
    bool first[4];  // the triples of the closed form (not the members added here)
    for (int i = 0; i < 4; ++i) first[i] = arm.valid[i] && arm.free[i];
    for (int i = 0; i < 4; ++i) {
        if (!(first[i] && wrist_misalignment(g, in_wrist_frame(g, arm.q[i], axis6)) <= kNearlyAligned)) continue;
        int spare = -1;
        for (int e = 0; e < 4 && spare < 0; ++e)
            if (!arm.valid[e]) spare = e;
        if (spare < 0) return;
        const Vec3 centre = moved_by_arm(g, arm.q[i], g.c);
        for (int j = 0; j < 3; ++j) {
            if (g.prismatic[j]) continue;
            double turned[3] = {arm.q[i][0], arm.q[i][1], arm.q[i][2]};
            turned[j] += 1.0;
            if (norm(moved_by_arm(g, turned, g.c) - centre) > kOutTolerance * g.size) continue;
            double best = -1.0;
            for (int m = 0; m < kFreeArmSamples; ++m) {
                turned[j] = arm.q[i][j] + (m + 0.5) * (kTwoPi / kFreeArmSamples);
                const double misaligned = wrist_misalignment(g, in_wrist_frame(g, turned, axis6));
                if (misaligned <= best) continue;
                best = misaligned;
                for (int c = 0; c < 3; ++c) arm.q[spare][c] = turned[c];
            }
            arm.q[spare][j] = wrap_angle(arm.q[spare][j]);
            arm.valid[spare] = arm.free[spare] = true;
            break;
        }
    }
}

// Spherical wrist: joints 1-3 for the wrist centre, then the wrist: 8 candidates.
void spherical(const SphericalGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
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

// ----------------------------------------------------------- three parallel axes

// Near an aligned wrist, q5 from a sine (accurate) rather than a cosine (~1e-8). h6 . R5^T h
// is the cosine-like quantity the equations give; at a distance d from the aligned value it
// differs from +-1 by b (1 - cos d) only, lost below d ~ 1e-8. S = |h6 x R_G^T R1 h| keeps
// its relative accuracy: b (1 - cos d) = S^2 / (1 + sqrt(1 - S^2)). The two branches of
// candidate pair s straddle the aligned value.
double q5_near_aligned_wrist(const ThreeParallelGeometry& g, const Mat3& R, double q1, double q5, int s) {
    if (g.aligned == 0) return q5;
    int nearest = 0;
    double gap = std::numeric_limits<double>::infinity();
    for (int a = 0; a < g.aligned; ++a) {
        const double d = wrap_angle(q5 - g.q5_aligned[a]);
        if (std::abs(d) < std::abs(gap)) {
            nearest = a;
            gap = d;
        }
    }
    if (std::abs(gap) > kAlignedWristReach) return q5;
    const Vec3 v = mul_transposed(R, rotate(g.h[0], q1, g.hp));
    const Vec3 c = cross(g.h[5], v);
    const double S2 = std::min(dot(c, c), 1.0);
    const double one_minus_cos = S2 / (1.0 + std::sqrt(1.0 - S2)) / g.b_aligned;
    const double d = 2.0 * std::asin(std::min(std::sqrt(0.5 * one_minus_cos), 1.0));
    double sign;
    if (gap > 0)
        sign = 1.0;
    else if (gap < 0)
        sign = -1.0;
    else
        sign = s % 2 == 0 ? 1.0 : -1.0;  // (+d, -d) pairs
    return g.q5_aligned[nearest] + sign * d;
}

// Put q5 exactly where axis 6 is parallel to h when a quartic root is that close to it.
// There the quartic has a double root, which Newton steps reach only to ~1e-8; the exact
// value lets the family (q6 against q2 + q3 + q4) be recognised. q1 is then solved from
// P x1 = r + Q x5 (a 2x2 linear system).
void snap_to_aligned_wrist(const ThreeParallelGeometry& g, const Mat2& P, const double* r, double* t1, double* t5) {
    const double det = P.m[0][0] * P.m[1][1] - P.m[0][1] * P.m[1][0];
    const double size = 1.0 + std::max(std::max(std::abs(P.m[0][0]), std::abs(P.m[0][1])),
                                       std::max(std::abs(P.m[1][0]), std::abs(P.m[1][1])));
    if (g.aligned == 0 || std::abs(det) <= kAlignedWristSolvable * size) return;
    const auto& Q = g.Q;
    for (int i = 0; i < 4; ++i) {
        int nearest = 0;
        double gap = std::numeric_limits<double>::infinity();
        for (int a = 0; a < g.aligned; ++a) {
            const double d = std::abs(wrap_angle(t5[i] - g.q5_aligned[a]));
            if (d < gap) {
                nearest = a;
                gap = d;
            }
        }
        if (gap > kAlignedWristSnap) continue;
        const double q5 = g.q5_aligned[nearest];
        const double rhs0 = r[0] + Q[0][0] * std::cos(q5) + Q[0][1] * std::sin(q5);
        const double rhs1 = r[1] + Q[1][0] * std::cos(q5) + Q[1][1] * std::sin(q5);
        t1[i] = std::atan2((P.m[0][0] * rhs1 - P.m[1][0] * rhs0) / det, (P.m[1][1] * rhs0 - P.m[0][1] * rhs1) / det);
        t5[i] = q5;
    }
}

// A wrist axis parallel to the three parallel axes (axis 6 to axes 2-4, or axis 5 to axes
// 1-3): the member of the family that is best reachable. Along the family the angle sum
// theta of the three parallel joints changes against the wrist joint's angle qw (theta + s qw
// constant, s = +-1: the wrist axis along or against h), and the planar target A - R(h,
// theta) B turns on a circle; choose the angle that puts its length where the planar 2R
// of links a, b reaches best (|v|^2 = |a|^2 + |b|^2). |v|^2 is a sinusoid in theta, so the
// 2R reaches it on at most two intervals of theta, each a separate loop of the family: the
// two angles where it crosses that middle value (side = +1 or -1) lie one in each. Returns
// qw and theta.
template <class G>
void wrist_family_representative(const G& g, double s, double& qw, double& theta, Vec3 A, Vec3 B,
                                 Vec3 a, Vec3 b, double side) {
    const Vec3 h = g.hp;
    A = detail::in_plane(A, h);
    B = detail::in_plane(B, h);
    a = detail::in_plane(a, h);
    b = detail::in_plane(b, h);
    const double wanted = 0.5 * (dot(A, A) + dot(B, B) - dot(a, a) - dot(b, b));  // A . R(h, phi) B
    const double cos_part = dot(A, B), sin_part = dot(A, cross(h, B));
    const double r = std::sqrt(cos_part * cos_part + sin_part * sin_part);
    if (r == 0.0) return;
    const double phi = std::atan2(sin_part, cos_part) + side * std::acos(std::min(std::max(wanted / r, -1.0), 1.0));
    qw = qw + s * (theta - phi);
    theta = phi;
}

//: Members of a family of the two-angle system sampled round the circle for its loops.
constexpr int kFamilyMembers = 64;
//: Loops of one family given a member at most: its candidates' slots, 4 x 2 elbows where
//: the quartic vanishes, 2 x 2 for a t2 branch where Q has rank 1 (family_slots keeps the
//: best reached of any more).
constexpr int kMaxLoops = 8;

// A member (t1, t2) of a family of the two-angle system, and f there (see family_loops).
struct FamilyMember {
    double t1, t2, f;
};

// The least value of value(t, t2) on [lo, hi] (a bracket of one local minimum) by
// golden-section search, with its t2.
template <class Value>
FamilyMember golden_minimum(Value value, double lo, double hi) {
    constexpr double golden = 0.6180339887498949;
    constexpr int kGoldenSteps = 80;  // the bracket shrinks to rounding long before
    FamilyMember left{hi - golden * (hi - lo), 0.0, 0.0}, right{lo + golden * (hi - lo), 0.0, 0.0};
    left.f = value(left.t1, left.t2), right.f = value(right.t1, right.t2);
    FamilyMember best = left.f < right.f ? left : right;
    for (int k = 0; k < kGoldenSteps && hi - lo > 4.0 * std::numeric_limits<double>::epsilon() * (1.0 + std::abs(hi)); ++k) {
        if (left.f < right.f) {
            hi = right.t1, right = left;
            left.t1 = hi - golden * (hi - lo), left.f = value(left.t1, left.t2);
        } else {
            lo = left.t1, left = right;
            right.t1 = lo + golden * (hi - lo), right.f = value(right.t1, right.t2);
        }
        if (left.f < best.f) best = left;
        if (right.f < best.f) best = right;
    }
    return best;
}

//: Bisection steps for a crossing of the middle reach (the bracket then is at rounding).
constexpr int kBisectionSteps = 52;

// The point between members a and b (f of opposite signs) where f(t1) = 0, by bisection
// (stops where t1 has no t2); returns the end with the smaller |f|.
template <class Reach>
FamilyMember bisect_middle(Reach reach, FamilyMember a, FamilyMember b) {
    for (int k = 0; k < kBisectionSteps; ++k) {
        FamilyMember mid{0.5 * (a.t1 + b.t1), 0.0, 0.0};
        mid.f = reach(mid.t1, mid.t2);
        if (!std::isfinite(mid.f)) break;
        ((mid.f < 0.0) == (a.f < 0.0) ? a : b) = mid;
    }
    return std::abs(a.f) <= std::abs(b.f) ? a : b;
}

// Candidate i of pair has a free t1 (a family of the two-angle system): a member (t1, t2)
// on each loop of the family, the one whose planar target (target_of(t2, t1, ...), for the
// 2R of links a, b) the 2R reaches best, into loops (at most kMaxLoops, best first; their
// number returned). With f(t1) = (|v|^2 - (|a|^2 + |b|^2)) / (2 |a| |b|), the 2R reaches
// where |f| <= 1, best where f = 0, and each interval of t1 where it reaches is one loop
// (its two elbows meet at the ends). f is sampled at kFamilyMembers values of t1 round the
// circle, each sampled extremum refined by golden-section search (a loop narrower than the
// samples lies beside one, and a loop that touches the 2R's reach at one point is one), and
// the pieces between are taken as monotone: a loop's member is where f crosses 0 (bisection),
// else its point of least |f|. Every member solves the system exactly; which one stands for a
// loop only decides whether the rest of the chain can follow (the walk to near comes later).
template <class G, class Target>
int family_loops(const G& g, const Mat2& P, const double* r, int i, double start, Target target_of,
                 Vec3 a, Vec3 b, FamilyMember* loops) {
    const Vec3 h = g.hp;
    a = detail::in_plane(a, h);
    b = detail::in_plane(b, h);
    const double middle = dot(a, a) + dot(b, b), half_width = std::max(2.0 * std::sqrt(dot(a, a) * dot(b, b)), 1e-300);
    const double size = system_size(P, r);
    const double band = 1.0 + kFamilyReach * (1.0 + middle / half_width);  // |f| within: reached, to rounding
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    // f(t1), and t2; NaN where t1 has no t2
    auto reach = [&](double t1, double& t2) {
        bool ok;
        t2 = family_t2(g, P, r, t1, i, size, ok);
        if (!ok) return kNaN;
        Angle1 wrist;
        double theta;
        const Vec3 v = detail::in_plane(target_of(t2, t1, wrist, theta, 1.0), h);
        return (dot(v, v) - middle) / half_width;
    };
    auto finite_or = [](double v, double otherwise) { return std::isfinite(v) ? v : otherwise; };
    constexpr double kInf = std::numeric_limits<double>::infinity();
    auto lowest = [&](double t1, double& t2) { return finite_or(reach(t1, t2), kInf); };
    auto highest = [&](double t1, double& t2) { return finite_or(-reach(t1, t2), kInf); };
    // the samples and their refined extrema, in order round the circle from start
    constexpr double step = kTwoPi / kFamilyMembers;
    FamilyMember sample[kFamilyMembers], knots[2 * kFamilyMembers];
    for (int m = 0; m < kFamilyMembers; ++m) {
        sample[m].t1 = start + m * step;
        sample[m].f = reach(sample[m].t1, sample[m].t2);
    }
    int count = 0;
    for (int m = 0; m < kFamilyMembers; ++m) {
        knots[count++] = sample[m];
        const double before = sample[(m + kFamilyMembers - 1) % kFamilyMembers].f, here = sample[m].f,
                     after = sample[(m + 1) % kFamilyMembers].f;
        if (!(std::isfinite(before) && std::isfinite(here) && std::isfinite(after))) continue;
        const double lo = sample[m].t1 - step, hi = sample[m].t1 + step;
        FamilyMember extremum;
        if (here <= before && here <= after) {
            extremum = golden_minimum(lowest, lo, hi);
        } else if (here >= before && here >= after) {
            extremum = golden_minimum(highest, lo, hi);
            extremum.f = -extremum.f;
        } else {
            continue;
        }
        if (!std::isfinite(extremum.f)) continue;
        if (extremum.t1 < start) extremum.t1 += kTwoPi;
        knots[count++] = extremum;
    }
    std::sort(knots, knots + count, [](const FamilyMember& x, const FamilyMember& y) { return x.t1 < y.t1; });
    auto inside = [&](double f) { return std::abs(f) <= band; };  // false for NaN
    int first_out = -1;
    for (int k = 0; k < count && first_out < 0; ++k)
        if (!inside(knots[k].f)) first_out = k;
    // the pieces between knots, from one where the 2R does not reach (else the whole circle is one loop)
    FamilyMember found[2 * kFamilyMembers];
    int loops_found = 0;
    bool open = false;
    FamilyMember best{};
    auto consider = [&](const FamilyMember& x) {
        if (!open || std::abs(x.f) < std::abs(best.f)) best = x;
        open = true;
    };
    auto close = [&]() {
        if (open) found[loops_found++] = best;
        open = false;
    };
    const int from = first_out < 0 ? 0 : first_out;
    for (int k = 0; k < count; ++k) {
        const FamilyMember& x = knots[(from + k) % count];
        FamilyMember y = knots[(from + k + 1) % count];
        if (from + k + 1 == count) y.t1 += kTwoPi;  // the last piece closes the circle
        const bool in_x = inside(x.f), in_y = inside(y.f);
        if (in_x) consider(x);
        if (std::isfinite(x.f) && std::isfinite(y.f) && (x.f < 0.0) != (y.f < 0.0)) {
            const FamilyMember middle = bisect_middle(reach, x, y);
            if (inside(middle.f)) consider(middle);  // a bisection a NaN stopped may end outside
        }
        if (open && !in_y && first_out >= 0) close();
    }
    if (first_out < 0) close();  // one loop round the whole circle
    std::sort(found, found + loops_found,
              [](const FamilyMember& x, const FamilyMember& y) { return std::abs(x.f) < std::abs(y.f); });
    loops_found = std::min(loops_found, kMaxLoops);
    for (int k = 0; k < loops_found; ++k) loops[k] = found[k];
    return loops_found;
}

// The angles (t1, t2) each slot (candidate i, elbow b) of the two-angle system stands on,
// and whether it is a solution. A family (free t1) is spread over its candidates (all four
// where the quartic vanishes, the two of one t2 branch where Q has rank 1): a member of
// each of its loops (family_loops), each with both elbows, or with more loops than
// candidates one per elbow; a family the 2R reaches nowhere leaves its candidates invalid.
struct SlotAngles {
    double t1[4][2], t2[4][2];
    bool valid[4][2];
};

template <class G, class Target>
SlotAngles family_slots(const G& g, const Mat2& P, const double* r, const AngleCandidates& pair,
                        Target target_of, Vec3 a, Vec3 b) {
    SlotAngles slots{};
    for (int i = 0; i < 4; ++i)
        for (int e = 0; e < 2; ++e)
            slots.t1[i][e] = pair.t1[i], slots.t2[i][e] = pair.t2[i], slots.valid[i][e] = pair.valid[i];
    for (int branch = 0; branch < (g.rank1 ? 2 : 1); ++branch) {
        int group[4], size = 0;
        for (int i = 0; i < 4; ++i)
            if (pair.free[i] && (!g.rank1 || i % 2 == branch)) group[size++] = i;
        if (size == 0) continue;
        FamilyMember loops[kMaxLoops];
        const int count = family_loops(g, P, r, group[0], pair.t1[group[0]], target_of, a, b, loops);
        for (int k = 0; k < size; ++k)
            for (int e = 0; e < 2; ++e) {
                const int m = count <= size ? k : (2 * k + e < count ? 2 * k + e : 2 * k);
                const int i = group[k];
                slots.valid[i][e] = m < count;
                if (m < count) slots.t1[i][e] = loops[m].t1, slots.t2[i][e] = loops[m].t2;
            }
    }
    return slots;
}

// Axes 2-4 parallel: (q1, q5), then q6, q2 + q3 + q4 and a planar 2R: 8 candidates.
void three_parallel(const ThreeParallelGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    const Vec3 h = g.hp, h0 = g.h[0], h4 = g.h[4], h5 = g.h[5];
    const Vec3 p0 = g.p[0], p1 = g.p[1], p2 = g.p[2], p3 = g.p[3];
    const Vec3 p5 = g.p5, p6 = g.p6;
    const int n = g.n;
    const Vec3 G_p6 = R * p6 + t;
    const TrigCoeffs e1 = trig_coeffs(h, -h0, R * h5);
    const TrigCoeffs e2 = trig_coeffs(h, -h0, G_p6 - p0);
    const Mat2 P{{{e1.cos_coeff, e1.sin_coeff}, {e2.cos_coeff, e2.sin_coeff}}};  // P x1 - Q x5 = r
    const double r[2] = {g.f[0] - e1.constant, g.f[1] - e2.constant};
    AngleCandidates pair = two_angle_system(g, P, r);
    if (g.rank1) {
        for (int i = 0; i < 4; ++i) pair.t2[i] = q5_near_aligned_wrist(g, R, pair.t1[i], pair.t2[i], i);
    } else {
        snap_to_aligned_wrist(g, P, r, pair.t1, pair.t2);
    }
    // axis 6 within kAlignedToRounding of h at q5
    auto axis6_parallel_to_rounding = [&](double q5) { return norm(cross(rotate(-h4, q5, h), h5)) <= kAlignedToRounding; };
    // q6, q2 + q3 + q4 and the planar 2R's target for (q1, q5)
    // (nearly_free: q6 within kAlignedToRounding of free counts as free)
    auto arm = [&](double q5, double q1, Angle1& q6, double& theta, double side, bool nearly_free) {
        // q6: R6^T (R5^T h) = R_G^T R1 h
        const Vec3 v = rotate(-h4, q5, h);
        q6 = sp1(v, mul_transposed(R, rotate(h0, q1, h)), -h5);
        q6.free = q6.free || (nearly_free && axis6_parallel_to_rounding(q5));
        // q2 + q3 + q4: R234 = R1^T R_G R6^T R5^T, applied to a normal of h
        const Vec3 turned = rotate(-h0, q1, R * rotate(-h5, q6.t, rotate(-h4, q5, g.u)));
        theta = sp1(g.u, turned, h).t;
        // planar part: e2 e3 e4 y = z with y = e5 p6, z = e1^-1 G p6
        const Vec3 y = p5 + rotate(h4, q5, p6 - p5);
        const Vec3 z = p0 + rotate(-h0, q1, G_p6 - p0);
        if (q6.free)  // axis 6 parallel to h: a family of q6, one loop of it per elbow slot
            wrist_family_representative(g, sign_of(dot(v, h5)), q6.t, theta, z - p1, y - p3, p2 - p1, p3 - p2, side);
        return (z - p1) - rotate(h, theta, y - p3);
    };
    const SlotAngles slots = family_slots(
        g, P, r, pair, [&](double q5, double q1, Angle1& q6, double& theta, double side) { return arm(q5, q1, q6, theta, side, false); },
        p2 - p1, p3 - p2);
    for (int i = 0; i < 4; ++i) {
        Angle1 q6;
        double theta;
        Planar2 q23{};
        for (int b = 0; b < 2; ++b) {
            const double q1 = slots.t1[i][b], q5 = slots.t2[i][b];
            const double side = b == 0 ? 1.0 : -1.0;
            if (b == 0 || q1 != slots.t1[i][0] || q5 != slots.t2[i][0] || q6.free)
                q23 = planar_2r(h, p2 - p1, p3 - p2, arm(q5, q1, q6, theta, side, false));
            // axis 6 within kAlignedToRounding of h, and the 2R cannot follow: q1 and q5 carry
            // the errors of a near-tangent root (seen 4e-12, leaving q6 0.008 off), so q6 is
            // taken as free (which misses the pose by about that angle times the arm's size),
            // the family's member refined by FK later
            if (!q23.ok[b] && !q6.free && axis6_parallel_to_rounding(q5)) {
                Angle1 free6;
                double free_theta;
                const Planar2 again = planar_2r(h, p2 - p1, p3 - p2, arm(q5, q1, free6, free_theta, side, true));
                if (free6.free && again.ok[b]) q23 = again, q6 = free6, theta = free_theta;
            }
            const int s = 2 * i + b;
            double* qs = q + n * s;
            qs[0] = q1;
            qs[1] = q23.ta[b];
            qs[2] = q23.tb[b];
            qs[3] = theta - q23.ta[b] - q23.tb[b];
            qs[4] = q5;
            qs[5] = q6.t;
            valid[s] = slots.valid[i][b] && q23.ok[b];
            family[s] = pair.free[i] || q6.free || q23.free;
        }
    }
}

// ------------------------------------------------------ parallel axes 1-3 (or 4-6)

// Axes 1-3 parallel: (q6, q4), then q5, q1 + q2 + q3 and a planar 2R: 8 candidates. Their
// motion keeps h-components, which leaves two equations in q4 and q6: h . R4 h5 =
// (R_G^T h) . R6^T h5 (orientation, since R5 h5 = h5) and h . e4 o5 = h . G e6^-1 o5.
void parallel_base(const ParallelBaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
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

// ------------------------------------------------------------- SCARA and planar

// SCARA / planar arm: angle sum, height, planar 2R: 2 candidates.
void planar(const PlanarGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
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

// Joints 1-3 carrying the tool point g.c to w = t (position IK; G = T, no M^-1): 4 candidates.
void point(const PointGeometry& g, Vec3 w, double* q, bool* valid, bool* family) {
    const ArmCandidates a = wrist_centre_joints(g, w);
    for (int s = 0; s < 4; ++s) {
        for (int j = 0; j < 3; ++j) q[3 * s + j] = a.q[s][j];
        valid[s] = a.valid[s];
        family[s] = a.valid[s] && a.free[s];
    }
}

}  // namespace

void solve_case(const SphericalGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    spherical(g, R, t, q, valid, family);
}

void solve_case(const ThreeParallelGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    three_parallel(g, R, t, q, valid, family);
}

void solve_case(const ParallelBaseGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    parallel_base(g, R, t, q, valid, family);
}

void solve_case(const PlanarGeometry& g, const Mat3& R, Vec3 t, double* q, bool* valid, bool* family) {
    planar(g, R, t, q, valid, family);
}

void solve_case(const PointGeometry& g, const Mat3&, Vec3 t, double* q, bool* valid, bool* family) {
    point(g, t, q, valid, family);
}

}  // namespace armkit
