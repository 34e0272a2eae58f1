#include "armkit/topp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace armkit {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A bound p + q x on u, linear in x.
struct Bound {
    double p;
    double q;
};

struct Interval {
    double lo;
    double hi;
    bool empty;
};

// Whether lo > hi by more than rounding (slack relative to max(1, |hi|)).
bool beyond_slack(double lo, double hi) { return lo - hi > kToppSlack * std::max(1.0, std::abs(hi)); }

// The rows of grid point i as bounds on u (rows with a = 0 bound x directly, into [xlo, xhi]);
// returns false if a row with a = 0 and b = 0 cannot hold.
bool row_bounds(const ToppProblem& pr, std::size_t i, Bound* lower, Bound* upper, std::size_t& count,
                double& xlo, double& xhi) {
    count = 0;
    for (std::size_t j = 0; j < pr.rows; ++j) {
        const std::size_t k = i * pr.rows + j;
        const double a = pr.a[k], b = pr.b[k], l = pr.lo[k] - pr.c[k], h = pr.hi[k] - pr.c[k];
        if (a == 0.0) {
            if (b > 0.0) {
                xlo = std::max(xlo, l / b);
                xhi = std::min(xhi, h / b);
            } else if (b < 0.0) {
                xlo = std::max(xlo, h / b);
                xhi = std::min(xhi, l / b);
            } else if (beyond_slack(l, 0.0) || beyond_slack(0.0, h)) {
                return false;
            }
        } else if (a > 0.0) {
            lower[count] = {l / a, -b / a};
            upper[count++] = {h / a, -b / a};
        } else {
            lower[count] = {h / a, -b / a};
            upper[count++] = {l / a, -b / a};
        }
    }
    return true;
}

// The x in [0, x_max_i] for which some u meets the rows of grid point i and, with `next`, takes
// x + 2 d u into [next_lo, next_hi]: u eliminated by pairing every lower bound with every upper one.
Interval project(const ToppProblem& pr, std::size_t i, bool next, double d, double next_lo, double next_hi) {
    Bound lower[kToppMaxRows + 1], upper[kToppMaxRows + 1];
    std::size_t count = 0;
    double xlo = 0.0, xhi = pr.x_max[i];
    if (!row_bounds(pr, i, lower, upper, count, xlo, xhi)) return {0.0, 0.0, true};
    if (next) {
        lower[count] = {next_lo / (2.0 * d), -1.0 / (2.0 * d)};
        upper[count++] = {next_hi / (2.0 * d), -1.0 / (2.0 * d)};
    }
    for (std::size_t l = 0; l < count; ++l) {
        for (std::size_t h = 0; h < count; ++h) {
            const double slope = lower[l].q - upper[h].q, room = upper[h].p - lower[l].p;
            if (slope > 0.0) {
                xhi = std::min(xhi, room / slope);
            } else if (slope < 0.0) {
                xlo = std::max(xlo, room / slope);
            } else if (beyond_slack(0.0, room)) {
                return {0.0, 0.0, true};
            }
        }
    }
    if (beyond_slack(xlo, xhi)) return {xlo, xhi, true};
    if (xlo > xhi) xlo = xhi = std::max(xhi, 0.0);  // empty by rounding only: the single point
    return {xlo, xhi, false};
}

}  // namespace

ToppResult topp_ra(const ToppProblem& pr, double* x, double* u, double* k_lo, double* k_hi) {
    const std::size_t last = pr.points - 1;
    const Interval end = project(pr, last, false, 0.0, 0.0, 0.0);
    if (end.empty || beyond_slack(end.lo, pr.x_end) || beyond_slack(pr.x_end, end.hi))
        return {ToppStatus::infeasible, last};
    k_lo[last] = k_hi[last] = pr.x_end;
    for (std::size_t i = last; i-- > 0;) {
        const Interval set = project(pr, i, true, pr.s[i + 1] - pr.s[i], k_lo[i + 1], k_hi[i + 1]);
        if (set.empty) return {ToppStatus::infeasible, i};
        k_lo[i] = set.lo;
        k_hi[i] = set.hi;
    }
    if (beyond_slack(k_lo[0], pr.x_start) || beyond_slack(pr.x_start, k_hi[0]))
        return {ToppStatus::start_unreachable, 0};
    x[0] = std::clamp(pr.x_start, k_lo[0], k_hi[0]);
    Bound lower[kToppMaxRows], upper[kToppMaxRows];
    for (std::size_t i = 0; i < last; ++i) {
        const double d = pr.s[i + 1] - pr.s[i];
        std::size_t count = 0;
        double xlo = 0.0, xhi = kInf;  // rows with a = 0 were met by the backward pass
        row_bounds(pr, i, lower, upper, count, xlo, xhi);
        double most = (k_hi[i + 1] - x[i]) / (2.0 * d);
        for (std::size_t r = 0; r < count; ++r) most = std::min(most, upper[r].p + upper[r].q * x[i]);
        // The greedy step, kept inside K_{i+1} against rounding.
        x[i + 1] = std::clamp(x[i] + 2.0 * d * most, k_lo[i + 1], k_hi[i + 1]);
        u[i] = (x[i + 1] - x[i]) / (2.0 * d);
    }
    return {ToppStatus::success, 0};
}

}  // namespace armkit
