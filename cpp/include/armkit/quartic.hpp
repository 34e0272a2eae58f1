// The roots of a complex quartic, for the two-angle systems of the case solvers.
#pragma once

#include <cmath>
#include <complex>
#include <limits>

namespace armkit {

using Complex = std::complex<double>;

// a b and a / b without the library's inf / NaN recovery (a function call per operation
// unless built with -fcx-limited-range; the operands here are finite).
inline Complex mul(Complex a, Complex b) {
    return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}
inline Complex divide(Complex a, Complex b) {
    const double inv = 1.0 / (b.real() * b.real() + b.imag() * b.imag());
    return {(a.real() * b.real() + a.imag() * b.imag()) * inv, (a.imag() * b.real() - a.real() * b.imag()) * inv};
}
inline double modulus(Complex a) { return std::sqrt(a.real() * a.real() + a.imag() * a.imag()); }

// p(z) and p'(z) for p(z) = c[0] z^4 + ... + c[4] (Horner).
inline void quartic_value(const Complex* c, Complex z, Complex& p, Complex& dp) {
    p = c[0];
    dp = 0.0;
    for (int i = 1; i < 5; ++i) {
        dp = mul(dp, z) + p;
        p = mul(p, z) + c[i];
    }
}

// The Aberth-Ehrlich correction of root approximation z[i] of c[0] z^4 + ... + c[4]: the
// Newton step p / p' with repulsion from the other approximations. at_rounding: p(z[i]) is
// at the rounding level of the polynomial (eps sum |c_k| |z|^k, Horner's error bound).
inline Complex aberth_step(const Complex* c, const double* abs_c, const Complex* z, int i, bool& at_rounding) {
    Complex p, dp;
    quartic_value(c, z[i], p, dp);
    const double az = modulus(z[i]);
    double bound = abs_c[0];
    for (int k = 1; k < 5; ++k) bound = bound * az + abs_c[k];
    at_rounding = modulus(p) <= 2.0 * std::numeric_limits<double>::epsilon() * bound;
    const Complex newton = divide(p, dp);
    Complex repulsion = 0.0;
    for (int j = 0; j < 4; ++j)
        if (j != i) repulsion += divide(1.0, z[i] - z[j]);
    return divide(newton, 1.0 - mul(newton, repulsion));
}

// The four roots of c[0] z^4 + ... + c[4] (c[0] != 0) by Aberth-Ehrlich iterations: the
// simultaneous Newton iteration with repulsion between the approximations, which converges
// to all roots, cubically for simple ones (a double root to about sqrt(eps), as for any
// method). A root stops moving once its value is at the rounding level of the polynomial
// or its step at that of the root; a last sweep then moves every root once more (an
// approximation that stopped early in a cluster feels its final neighbours).
inline void quartic_roots(const Complex* c, Complex* z) {
    double abs_c[5];
    for (int i = 0; i < 5; ++i) abs_c[i] = std::abs(c[i]);
    // Start on circles whose radii the Newton polygon gives (Bini): the upper convex hull of
    // (k, log |a_k|), a_k = c[4 - k] the coefficient of z^k; an edge from k0 to k1 holds
    // k1 - k0 roots of modulus about (|a_k0| / |a_k1|)^(1 / (k1 - k0)).
    double log_a[5];
    for (int k = 0; k < 5; ++k) log_a[k] = abs_c[4 - k] > 0.0 ? std::log(abs_c[4 - k]) : -1e300;
    int hull[5], m = 0;
    for (int k = 0; k < 5; ++k) {
        while (m >= 2) {  // drop the last vertex while it lies on or below the chord to k
            const int a = hull[m - 2], b = hull[m - 1];
            if ((log_a[b] - log_a[a]) * (k - a) <= (log_a[k] - log_a[a]) * (b - a)) --m;
            else break;
        }
        hull[m++] = k;
    }
    int root = 0;
    for (int e = 0; e + 1 < m; ++e) {
        const int k0 = hull[e], k1 = hull[e + 1];
        const double radius = std::exp((log_a[k0] - log_a[k1]) / (k1 - k0));
        for (int j = 0; j < k1 - k0; ++j, ++root)  // angles no symmetry of the problem maps onto each other
            z[root] = std::polar(radius, 0.4 + 6.283185307179586 * j / (k1 - k0) + 1.3 * e);
    }
    // Every sweep computes all corrections from the same approximations (Jacobi order: the
    // four are independent, so the processor overlaps them), then applies them.
    bool done[4] = {false, false, false, false};
    constexpr double eps2 = std::numeric_limits<double>::epsilon() * std::numeric_limits<double>::epsilon();
    for (int sweep = 0; sweep <= 100; ++sweep) {
        const bool last = sweep == 100 || (done[0] && done[1] && done[2] && done[3]);
        Complex step[4];
        bool at_rounding[4];
        for (int i = 0; i < 4; ++i) step[i] = aberth_step(c, abs_c, z, i, at_rounding[i]);
        for (int i = 0; i < 4; ++i) {
            // NaN input, or an exact multiple root: nothing to improve
            const bool finite = std::isfinite(step[i].real()) && std::isfinite(step[i].imag());
            if (last) {
                if (finite) z[i] -= step[i];
                continue;
            }
            if (done[i]) continue;
            if (finite && !at_rounding[i]) z[i] -= step[i];
            done[i] = !finite || at_rounding[i] || std::norm(step[i]) <= eps2 * std::norm(z[i]);
        }
        if (last) break;
    }
}

}  // namespace armkit
