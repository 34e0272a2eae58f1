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
    RateStepInfo info;
    const double smallest = smallest_gram_eigenvalue(J, n);
    info.sigma_min = std::sqrt(std::max(smallest, 0.0));
    info.damping = rate_damping(info.sigma_min, threshold, max_damping);
    if (info.damping == 0.0) {  // no damping asked: an exactly singular J still gets the least-squares step
        double trace = 0.0;
        for (int k = 0; k < 6 * n; ++k) trace += J[k] * J[k];
        if (smallest <= kGramRounding * trace) info.damping = kSingularDamping * trace;
    }
    static constexpr int kEveryRow[6] = {0, 1, 2, 3, 4, 5};
    double free[kMaxJoints] = {};
    damped_step(J, n, twist, kEveryRow, 6, free, info.damping, qd);
    info.scale = inverse_max_velocity ? limit_scale(qd, inverse_max_velocity, n) : 1.0;
    if (info.scale != 1.0)
        for (int i = 0; i < n; ++i) qd[i] *= info.scale;
    return info;
}

}  // namespace armkit

