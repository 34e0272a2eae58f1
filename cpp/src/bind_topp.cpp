#include <cstddef>
#include <stdexcept>
#include <utility>

#include <nanobind/stl/pair.h>

#include "armkit/polynomial.hpp"
#include "armkit/topp.hpp"
#include "bindings.hpp"

namespace armkit::bindings {

namespace {

// (status, point): see ToppStatus. Writes x (N+1), u (N), k_lo, k_hi (N+1).
std::pair<int, std::size_t> topp(In s, In a, In b, In c, In lo, In hi, In x_max, double x_start, double x_end,
                                 Out x, Out u, Out k_lo, Out k_hi) {
    const std::size_t points = s.size();
    if (points < 2) throw std::invalid_argument("s: expected at least two grid points");
    const std::size_t rows = a.size() / points;
    if (rows > kToppMaxRows || a.size() != points * rows || b.size() != a.size() || c.size() != a.size() ||
        lo.size() != a.size() || hi.size() != a.size())
        throw std::invalid_argument("a, b, c, lo, hi: expected (N+1, m) arrays, m <= kToppMaxRows (64)");
    if (x_max.size() != points || x.size() != points || k_lo.size() != points || k_hi.size() != points ||
        u.size() != points - 1)
        throw std::invalid_argument("x_max, x, k_lo, k_hi: expected (N+1,), u (N,)");
    const ToppProblem problem{points,     rows,      s.data(), a.data(), b.data(), c.data(),
                              lo.data(), hi.data(), x_max.data(), x_start, x_end};
    const ToppResult result = topp_ra(problem, x.data(), u.data(), k_lo.data(), k_hi.data());
    return {static_cast<int>(result.status), result.point};
}

// Per column r of c ((degree + 1, R), ascending powers), the lowest and highest value on [0, 1].
void extremes(In c, Out low, Out high) {
    if (c.ndim() != 2 || c.shape(0) < 1 || c.shape(0) > std::size_t(kMaxPolynomialDegree) + 1 ||
        low.size() != c.shape(1) || high.size() != c.shape(1))
        throw std::invalid_argument("c: expected (degree + 1, R) with degree <= 7, low and high (R,)");
    const int degree = int(c.shape(0)) - 1;
    const std::size_t rows = c.shape(1);
    double column[kMaxPolynomialDegree + 1];
    for (std::size_t r = 0; r < rows; ++r) {
        for (int i = 0; i <= degree; ++i) column[i] = c.data()[std::size_t(i) * rows + r];
        polynomial_extremes(column, degree, low.data()[r], high.data()[r]);
    }
}

}  // namespace

void bind_topp(nb::module_& m) {
    m.def("topp_ra", &topp, nb::arg("s"), nb::arg("a"), nb::arg("b"), nb::arg("c"), nb::arg("lo"),
          nb::arg("hi"), nb::arg("x_max"), nb::arg("x_start"), nb::arg("x_end"), nb::arg("x"), nb::arg("u"),
          nb::arg("k_lo"), nb::arg("k_hi"), nb::call_guard<nb::gil_scoped_release>(),
          "Time-optimal parameterisation (TOPP-RA) on the grid s (N+1) under lo <= a u + b x + c <= hi "
          "(N+1, m) and x <= x_max: writes x = s'^2, u = s'', the controllable sets; returns (status, point).");
    m.def("polynomial_extremes", &extremes, nb::arg("c"), nb::arg("low"), nb::arg("high"),
          nb::call_guard<nb::gil_scoped_release>(),
          "Lowest and highest value on [0, 1] of each column of c ((degree + 1, R), ascending powers) "
          "into low, high (R,): the ends and the real roots of the derivative, no eigenvalues.");
}

}  // namespace armkit::bindings
