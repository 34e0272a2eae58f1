#include "armkit/double_root.hpp"

#include <algorithm>
#include <cmath>

#include "armkit/closed_form.hpp"
#include "armkit/fk.hpp"
#include "armkit/ik_family.hpp"
#include "armkit/tolerances.hpp"

namespace armkit {

namespace {

//: The second difference's step along v [rad or m]: its truncation error (h^2 relative) and
//: its rounding (eps / (g2 h^2), g2 ~ 0.1 .. 1) both ~1e-8; the steps that follow correct it.
constexpr double kCurvatureStep = 1e-4;
//: Steps from each zero of the first model: a root found to ~1e-8 relative reaches rounding in
//: two or three (quadratic convergence); a few more for a slow start.
constexpr int kDoubleRootSteps = 6;

// The weak-direction model at x (6 joints): the strong directions' Gauss-Newton step, the weak
// direction v and g(t) = u . e(x + strong + t v) ~ g0 + g1 t + g2 t^2.
struct WeakModel {
    double strong[6], v[6];
    double g0 = 0.0, g1 = 0.0, g2 = 0.0;
    double ratio = 1.0;  // smallest singular value of J over its largest
    double error = 0.0;  // max |e| at x [m, rad]
};

WeakModel weak_model(const Chain& chain, const Pose& T, const double* x) {
    WeakModel m;
    Vec3 axes[6], points[6];
    double J[36], e[6], s[6], V[36], A[36];
    const Pose F = joint_axes(chain, x, axes, points);
    jacobian_from_axes(F, axes, points, chain.prismatic.data(), 6, J);
    pose_error(T, F, e);
    jacobi_svd(J, 6, s, V);
    int w = 0;
    double largest = 0.0;
    for (int i = 0; i < 6; ++i) {
        if (s[i] < s[w]) w = i;
        largest = std::max(largest, s[i]);
        m.error = std::max(m.error, std::fabs(e[i]));
    }
    m.ratio = largest > 0.0 ? s[w] / largest : 0.0;
    for (int r = 0; r < 6; ++r)  // A = J V: column i is s_i u_i
        for (int i = 0; i < 6; ++i) {
            double sum = 0.0;
            for (int k = 0; k < 6; ++k) sum += J[r * 6 + k] * V[k * 6 + i];
            A[r * 6 + i] = sum;
        }
    std::fill(m.strong, m.strong + 6, 0.0);
    double u[6] = {}, best = -1.0;
    for (int c = 0; c < 6; ++c) {  // u: the unit vector orthogonal to every strong u_i (Gram-Schmidt)
        double r[6] = {};
        r[c] = 1.0;
        for (int i = 0; i < 6; ++i) {
            if (i == w) continue;
            const double along = A[c * 6 + i] / (s[i] * s[i]);  // u_i[c] / s_i
            for (int k = 0; k < 6; ++k) r[k] -= along * A[k * 6 + i];
        }
        double length = 0.0;
        for (double v : r) length += v * v;
        if (length > best) best = length, std::copy(r, r + 6, u);
    }
    const double scale = 1.0 / std::sqrt(best);
    for (double& v : u) v *= scale;
    for (int i = 0; i < 6; ++i) {
        if (i == w) continue;
        double along = 0.0;  // (u_i . e) / s_i, over s_i again for the step
        for (int k = 0; k < 6; ++k) along += A[k * 6 + i] * e[k];
        along /= s[i] * s[i];
        for (int k = 0; k < 6; ++k) m.strong[k] += along * V[k * 6 + i];
    }
    double Jv_u = 0.0;
    for (int k = 0; k < 6; ++k) {
        m.v[k] = V[k * 6 + w];
        m.g0 += u[k] * e[k];
        Jv_u += u[k] * A[k * 6 + w];
    }
    m.g1 = -Jv_u;  // e = target - fk: de/dt = -J v
    double ahead[6], behind[6], e_ahead[6], e_behind[6];
    for (int k = 0; k < 6; ++k) ahead[k] = x[k] + kCurvatureStep * m.v[k], behind[k] = x[k] - kCurvatureStep * m.v[k];
    pose_error(T, tool_pose(chain, ahead), e_ahead);
    pose_error(T, tool_pose(chain, behind), e_behind);
    double second = 0.0;
    for (int k = 0; k < 6; ++k) second += u[k] * (e_ahead[k] + e_behind[k] - 2.0 * e[k]);
    m.g2 = second / (2.0 * kCurvatureStep * kCurvatureStep);
    return m;
}

// The real zeros of g0 + g1 t + g2 t^2 into t (the vertex where they are complex: the nearest
// the pair comes to a root); returns their number, the one nearest 0 first.
int model_zeros(const WeakModel& m, double* t) {
    if (m.g2 == 0.0) {
        if (m.g1 == 0.0) return 0;
        t[0] = -m.g0 / m.g1;
        return 1;
    }
    const double discriminant = m.g1 * m.g1 - 4.0 * m.g2 * m.g0;
    if (!(discriminant > 0.0)) {
        t[0] = -m.g1 / (2.0 * m.g2);
        return std::isfinite(t[0]) ? 1 : 0;
    }
    const double half = -0.5 * (m.g1 + std::copysign(std::sqrt(discriminant), m.g1));  // no cancellation
    t[0] = half / m.g2;
    t[1] = half != 0.0 ? m.g0 / half : t[0];
    if (std::fabs(t[1]) < std::fabs(t[0])) std::swap(t[0], t[1]);
    return std::isfinite(t[0]) && std::isfinite(t[1]) ? 2 : 0;
}

void step(const WeakModel& m, double t, double* x) {
    for (int k = 0; k < 6; ++k) x[k] += m.strong[k] + t * m.v[k];
}

}  // namespace

int near_double_roots(const Chain& chain, const Pose& T, const double* q, double size, double* roots) {
    if (chain.n != 6) return 0;
    const WeakModel first = weak_model(chain, T, q);
    if (!(first.ratio <= kNearDoubleRoot)) return 0;
    double zeros[2];
    const int count = model_zeros(first, zeros);
    int found = 0;
    for (int z = 0; z < count; ++z) {
        double x[6];
        std::copy(q, q + 6, x);
        step(first, zeros[z], x);
        for (int k = 0; k < kDoubleRootSteps; ++k) {
            const WeakModel m = weak_model(chain, T, x);
            if (m.error <= kPolished * size) break;
            double t[2];
            if (model_zeros(m, t) == 0) break;
            step(m, t[0], x);
        }
        if (!(fk_difference(chain, T, x) <= kDoubleRootExact * size)) continue;
        bool twin = false;
        for (int r = 0; r < found && !twin; ++r) twin = within(chain, x, roots + 6 * r, kDuplicateTolerance);
        if (!twin) std::copy(x, x + 6, roots + 6 * found++);
    }
    return found;
}

}  // namespace armkit
