// The two-angle system (see two_angle.hpp).
#include "armkit/two_angle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "armkit/quartic.hpp"

namespace armkit {

namespace {

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

}  // namespace

// t2 of the two-angle system for t1: x(t2) = Q^-1 (P x(t1) - r), its direction.
double second_angle(const TwoAngleSystem& g, const Mat2& P, const double* r, double t1) {
    const auto& Qi = g.Q_inv;
    const double c = std::cos(t1), s = std::sin(t1);
    const double v0 = P.m[0][0] * c + P.m[0][1] * s - r[0], v1 = P.m[1][0] * c + P.m[1][1] * s - r[1];
    return std::atan2(Qi[1][0] * v0 + Qi[1][1] * v1, Qi[0][0] * v0 + Qi[0][1] * v1);
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

}  // namespace armkit
