// Extremes of a polynomial on [0, 1], exact to rounding: the trajectory peaks (armkit/trajectory/peaks.py).
//
// The extremes lie at 0, 1 or a real root of p'. Roots come from the derivative cascade: between two
// consecutive roots of p^(k+1) in [0, 1], p^(k) is monotone, so it has at most one root there, found by
// Newton steps kept inside a shrinking bracket (bisection when a step leaves it). Starting from the
// linear p^(d-1), every root of p' in [0, 1] is found, each to full precision; no eigenvalues.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace armkit {

// Most polynomial degree handled (a quintic's position is degree 5).
constexpr int kMaxPolynomialDegree = 7;

namespace detail {

inline double horner(const double* c, int degree, double s) {
    double value = c[degree];
    for (int i = degree - 1; i >= 0; --i) value = value * s + c[i];
    return value;
}

// The root in [lo, hi] of f (degree `degree`, derivative df) monotone there, given f(lo) f(hi) <= 0.
inline double bracketed_root(const double* f, const double* df, int degree, double lo, double hi, double f_lo) {
    double s = 0.5 * (lo + hi);
    for (int iteration = 0; iteration < 200 && hi - lo > 4e-16; ++iteration) {
        const double value = horner(f, degree, s);
        if (value == 0.0) return s;
        if ((value < 0.0) == (f_lo < 0.0)) {
            lo = s;
            f_lo = value;
        } else {
            hi = s;
        }
        const double newton = s - value / horner(df, degree - 1, s);  // a zero slope: inf, outside
        if (std::abs(newton - s) <= 1e-16) return newton;
        s = (newton > lo && newton < hi) ? newton : 0.5 * (lo + hi);
    }
    return s;
}

}  // namespace detail

// Lowest and highest value on [0, 1] of c[0] + c[1] s + ... + c[degree] s^degree (degree <= kMaxPolynomialDegree).
inline void polynomial_extremes(const double* c, int degree, double& low, double& high) {
    double derivatives[kMaxPolynomialDegree + 1][kMaxPolynomialDegree + 1];  // [k]: p^(k), ascending
    for (int i = 0; i <= degree; ++i) derivatives[0][i] = c[i];
    for (int k = 1; k <= degree; ++k)
        for (int i = 0; i <= degree - k; ++i) derivatives[k][i] = derivatives[k - 1][i + 1] * double(i + 1);
    // points: 0, the roots in (0, 1) of the current derivative, 1 (sorted).
    double points[kMaxPolynomialDegree + 2] = {0.0, 1.0};
    int count = 2;
    for (int k = degree - 1; k >= 1; --k) {  // roots of p^(k) from those of p^(k+1)
        const double* f = derivatives[k];
        const int f_degree = degree - k;
        double roots[kMaxPolynomialDegree + 2] = {0.0};
        int found = 1;
        double f_lo = detail::horner(f, f_degree, points[0]);
        for (int j = 0; j + 1 < count; ++j) {
            const double f_hi = detail::horner(f, f_degree, points[j + 1]);
            if (f_lo == 0.0 && j > 0) {
                roots[found++] = points[j];
            } else if ((f_lo < 0.0) != (f_hi < 0.0) && f_hi != 0.0) {
                roots[found++] = detail::bracketed_root(f, derivatives[k + 1], f_degree, points[j], points[j + 1], f_lo);
            }
            f_lo = f_hi;
        }
        roots[found++] = 1.0;
        std::copy(roots, roots + found, points);
        count = found;
    }
    low = high = detail::horner(c, degree, 0.0);
    for (int j = 1; j < count; ++j) {
        const double value = detail::horner(c, degree, points[j]);
        low = std::min(low, value);
        high = std::max(high, value);
    }
}

}  // namespace armkit
