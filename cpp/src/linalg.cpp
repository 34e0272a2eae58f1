#include "armkit/linalg.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace armkit {

bool cholesky_solve(double* A, double* b, int k) {
    for (int j = 0; j < k; ++j) {
        double d = A[j * k + j];
        for (int p = 0; p < j; ++p) d -= A[j * k + p] * A[j * k + p];
        if (!(d > 0.0)) return false;
        d = std::sqrt(d);
        A[j * k + j] = d;
        for (int i = j + 1; i < k; ++i) {
            double s = A[i * k + j];
            for (int p = 0; p < j; ++p) s -= A[i * k + p] * A[j * k + p];
            A[i * k + j] = s / d;
        }
    }
    for (int i = 0; i < k; ++i) {  // L y = b
        double s = b[i];
        for (int p = 0; p < i; ++p) s -= A[i * k + p] * b[p];
        b[i] = s / A[i * k + i];
    }
    for (int i = k - 1; i >= 0; --i) {  // L^T x = y
        double s = b[i];
        for (int p = i + 1; p < k; ++p) s -= A[p * k + i] * b[p];
        b[i] = s / A[i * k + i];
    }
    return true;
}

namespace {

// x (k) from (Jm Jm^T + damping I) x = em if m <= n (k = m), else from
// (Jm^T Jm + damping I) x = Jm^T em (k = n); Jm is m x n row-major.
bool solve_normal_equations(const double* Jm, int m, int n, const double* em, double damping, double* x) {
    const bool wide = m <= n;
    const int size = wide ? m : n;
    double A[kMaxJoints * kMaxJoints];
    for (int a = 0; a < size; ++a) {
        for (int b = 0; b <= a; ++b) {
            double s = 0.0;
            if (wide)
                for (int i = 0; i < n; ++i) s += Jm[a * n + i] * Jm[b * n + i];
            else
                for (int k = 0; k < m; ++k) s += Jm[k * n + a] * Jm[k * n + b];
            A[a * size + b] = s;
        }
        A[a * size + a] += damping;
        if (wide) {
            x[a] = em[a];
        } else {
            double s = 0.0;
            for (int k = 0; k < m; ++k) s += Jm[k * n + a] * em[k];
            x[a] = s;
        }
    }
    return cholesky_solve(A, x, size);
}

}  // namespace

void damped_step(const double* J, int n, const double* e, const int* rows, int m, const double* sides,
                 double damping, double* dq) {
    double Jm[6 * kMaxJoints] = {}, em[6] = {}, x[kMaxJoints] = {};
    for (int k = 0; k < m; ++k) em[k] = e[rows[k]];
    double trace = 0.0;
    for (int i = 0; i < n; ++i) {
        bool frozen = false;
        if (sides[i] != 0.0) {
            double gradient = 0.0;
            for (int k = 0; k < m; ++k) gradient += em[k] * J[rows[k] * n + i];
            frozen = gradient * sides[i] > 0.0;
        }
        for (int k = 0; k < m; ++k) {
            Jm[k * n + i] = frozen ? 0.0 : J[rows[k] * n + i];
            trace += Jm[k * n + i] * Jm[k * n + i];
        }
    }
    const bool wide = m <= n;
    const int size = wide ? m : n;
    if (!solve_normal_equations(Jm, m, n, em, damping, x) &&
        !solve_normal_equations(Jm, m, n, em, damping + kSingularDamping * trace, x))
        for (int k = 0; k < size; ++k) x[k] = 0.0;  // J is all zeros: no direction lowers the error
    for (int i = 0; i < n; ++i) {
        if (wide) {
            double s = 0.0;
            for (int k = 0; k < m; ++k) s += Jm[k * n + i] * x[k];
            dq[i] = s;
        } else {
            dq[i] = x[i];
        }
    }
}

double rate_damping(double sigma_min, double threshold, double max_damping) {
    if (sigma_min >= threshold) return 0.0;  // also every sigma_min >= 0 when threshold <= 0
    const double ratio = sigma_min / threshold;
    return (1.0 - ratio * ratio) * max_damping * max_damping;
}

double limit_scale(const double* qd, const double* inverse_max_velocity, int n) {
    double ratio = 0.0;
    for (int i = 0; i < n; ++i) ratio = std::max(ratio, std::abs(qd[i]) * inverse_max_velocity[i]);
    return ratio > 1.0 ? 1.0 / ratio : 1.0;
}

namespace {

// Smallest eigenvalue of the Gram matrix of J (6 x n): J J^T (6 x 6, fixed size) for n >= 6.
double smallest_gram_eigenvalue(const double* J, int n) {
    const Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>> A(J, 6, n);
    if (n >= 6) {
        const Eigen::Matrix<double, 6, 6> gram = A * A.transpose();
        return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(gram, Eigen::EigenvaluesOnly).eigenvalues()(0);
    }
    using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
    const Small gram = A.transpose() * A;
    return Eigen::SelfAdjointEigenSolver<Small>(gram, Eigen::EigenvaluesOnly).eigenvalues()(0);
}

}  // namespace

RateStepInfo rate_step(const double* J, int n, const double* twist, double threshold, double max_damping,
                       const double* inverse_max_velocity, double* qd) {
    // The step is solved for Js = J 2^-e, e the exponent of J's largest entry (Js's in [0.5, 1)):
    // scaling by a power of two is exact, so a J of ordinary size gets the very same bits, and a
    // J of 1e-300 (or 1e300), whose Gram matrix would underflow to zero (overflow), its true step
    // rather than 0. With J = 2^e Js and d = lambda^2 4^-e:
    //   sigma_min(J) = 2^e sigma_min(Js),  qd = J^T (J J^T + lambda^2 I)^-1 twist
    //                                         = 2^-e Js^T (Js Js^T + d I)^-1 twist.
    int e = 0;
    double largest = 0.0;
    for (int k = 0; k < 6 * n; ++k) largest = std::max(largest, std::abs(J[k]));
    if (largest > 0.0) std::frexp(largest, &e);
    // 2^-e as two factors, each a double for every e frexp gives (-1073 .. 1024); multiplying
    // by them is exact (but for entries below 2^-1022 of the result, noise beside the largest)
    const double half = std::ldexp(1.0, -e / 2), rest = std::ldexp(1.0, -e - (-e / 2));
    double Js[6 * kMaxJoints];
    for (int k = 0; k < 6 * n; ++k) Js[k] = J[k] * half * rest;
    RateStepInfo info;
    const double smallest = smallest_gram_eigenvalue(Js, n);
    info.sigma_min = std::ldexp(std::sqrt(std::max(smallest, 0.0)), e);
    info.damping = rate_damping(info.sigma_min, threshold, max_damping);
    double damping = std::ldexp(info.damping, -2 * e);
    if (damping == 0.0) {  // no damping asked (or one below Js's rounding): a singular J still gets the least-squares step
        double trace = 0.0;
        for (int k = 0; k < 6 * n; ++k) trace += Js[k] * Js[k];
        if (smallest <= kGramRounding * trace) {
            damping = kSingularDamping * trace;
            info.damping = std::ldexp(damping, 2 * e);
        }
    }
    if (damping > kDampingDominates) {  // qd = 2^-e Js^T twist / d = Js^T twist 2^e / lambda^2
        int e_damping = 0;
        const double mantissa = std::frexp(info.damping, &e_damping);
        for (int i = 0; i < n; ++i) {
            double s = 0.0;
            for (int k = 0; k < 6; ++k) s += Js[k * n + i] * twist[k];
            qd[i] = std::ldexp(s / mantissa, e - e_damping);
        }
    } else {
        static constexpr int kEveryRow[6] = {0, 1, 2, 3, 4, 5};
        double free[kMaxJoints] = {};
        damped_step(Js, n, twist, kEveryRow, 6, free, damping, qd);
        for (int i = 0; i < n; ++i) qd[i] = qd[i] * half * rest;
    }
    info.scale = inverse_max_velocity ? limit_scale(qd, inverse_max_velocity, n) : 1.0;
    if (info.scale != 1.0)
        for (int i = 0; i < n; ++i) qd[i] *= info.scale;
    return info;
}

}  // namespace armkit

