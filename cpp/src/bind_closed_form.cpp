// Bindings of the subproblems and the case solvers: _core.CaseGeometry (built once per chain
// by armkit/ik/closed_form.py), _core.solve_pose (one pose, for tests) and the subproblems
// themselves (for the chain preparation and tests).
#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include <nanobind/stl/array.h>
#include <nanobind/stl/complex.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>

#include "armkit/ik_cases.hpp"
#include "armkit/quartic.hpp"
#include "armkit/subproblems.hpp"
#include "bindings.hpp"

namespace armkit::bindings {

namespace {

using V3 = std::array<double, 3>;
using Pair = std::pair<double, double>;
using Flags = std::pair<bool, bool>;

Vec3 vec(const V3& v) { return {v[0], v[1], v[2]}; }
std::tuple<double, double, double> tuple3(Vec3 v) { return {v.x, v.y, v.z}; }

// ------------------------------------------------------------------ CaseGeometry

// The values of a keyword argument as float64, flattened; its size must be `size` (or any
// multiple of `per_row` when size is 0).
std::vector<double> doubles(const nb::kwargs& kw, const char* name, std::size_t size, std::size_t per_row = 1) {
    if (!kw.contains(name)) throw nb::type_error(("CaseGeometry: missing field '" + std::string(name) + "'").c_str());
    nb::module_ np = nb::module_::import_("numpy");
    nb::object flat = np.attr("ascontiguousarray")(kw[name], nb::arg("dtype") = "float64").attr("ravel")();
    auto a = nb::cast<nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>(flat);
    const std::size_t got = a.shape(0);
    if ((size != 0 && got != size) || (size == 0 && got % per_row != 0))
        throw nb::value_error(("CaseGeometry: field '" + std::string(name) + "' has " + std::to_string(got) +
                               " values, expected " + (size ? std::to_string(size) : "a multiple of " +
                               std::to_string(per_row)))
                                  .c_str());
    return {a.data(), a.data() + got};
}

Vec3 vec_field(const nb::kwargs& kw, const char* name) {
    const std::vector<double> v = doubles(kw, name, 3);
    return {v[0], v[1], v[2]};
}

double number(const nb::kwargs& kw, const char* name) { return doubles(kw, name, 1)[0]; }

int integer(const nb::kwargs& kw, const char* name) {
    const double v = number(kw, name);
    if (v != double(int(v))) throw nb::value_error(("CaseGeometry: field '" + std::string(name) + "' must be an integer").c_str());
    return int(v);
}

bool flag(const nb::kwargs& kw, const char* name) {
    if (!kw.contains(name)) throw nb::type_error(("CaseGeometry: missing field '" + std::string(name) + "'").c_str());
    const int truth = PyObject_IsTrue(kw[name].ptr());  // Python truth (bool, numpy.bool_, 0 / 1)
    if (truth < 0) throw nb::python_error();
    return truth != 0;
}

void matrix2(const nb::kwargs& kw, const char* name, double (&M)[2][2]) {
    const std::vector<double> v = doubles(kw, name, 4);
    M[0][0] = v[0];
    M[0][1] = v[1];
    M[1][0] = v[2];
    M[1][1] = v[3];
}

void pair_field(const nb::kwargs& kw, const char* name, double (&x)[2]) {
    const std::vector<double> v = doubles(kw, name, 2);
    x[0] = v[0];
    x[1] = v[1];
}

constexpr const char* kFields[] = {"kind", "position_case", "h", "p", "prismatic", "c", "o", "u", "hp", "a1", "a2",
                                   "a3", "Q", "Q_inv", "f", "rank1", "lam", "mu", "snap_t2", "q5_aligned",
                                   "b_aligned", "revolute_joints", "prismatic_joint", "k", "general_shift"};

// A CaseGeometry from the keyword arguments named like the fields of ik_cases.hpp (k
// optional: 2 for planar arms, else 8), checked for sizes and ranges.
CaseGeometry make_geometry(const nb::kwargs& kw) {
    for (auto [key, value] : kw) {
        const std::string name = nb::cast<std::string>(key);
        bool known = false;
        for (const char* f : kFields) known = known || name == f;
        if (!known) throw nb::type_error(("CaseGeometry: unknown field '" + name + "'").c_str());
    }
    CaseGeometry g;
    const int kind = integer(kw, "kind"), position_case = integer(kw, "position_case");
    if (kind < 0 || kind > 5) throw nb::value_error("CaseGeometry: kind must be 0 (spherical) .. 5 (general)");
    if (position_case < -1 || position_case > 5) throw nb::value_error("CaseGeometry: position_case must be -1 .. 5");
    g.kind = CaseKind(kind);
    g.position_case = PositionCase(position_case);
    const std::vector<double> h = doubles(kw, "h", 0, 3), p = doubles(kw, "p", 0, 3);
    g.n = int(h.size() / 3);
    if (p.size() != h.size() || g.n < 1 || g.n > 16)
        throw nb::value_error("CaseGeometry: h and p must both be (n, 3) with 1 <= n <= 16");
    if (g.kind == CaseKind::Point ? g.n != 3 : g.kind != CaseKind::Planar && g.n != 6)
        throw nb::value_error("CaseGeometry: a 6-joint case needs n = 6, a point case n = 3");
    if ((g.kind == CaseKind::Spherical || g.kind == CaseKind::Point) && g.position_case == PositionCase::None)
        throw nb::value_error("CaseGeometry: a spherical wrist or a point case needs a position_case 0 .. 5");
    for (int j = 0; j < g.n; ++j) {
        g.h.push_back({h[3 * j], h[3 * j + 1], h[3 * j + 2]});
        g.p.push_back({p[3 * j], p[3 * j + 1], p[3 * j + 2]});
    }
    for (double v : p) g.size = std::max(g.size, 1.0 + std::abs(v));
    for (double v : doubles(kw, "prismatic", std::size_t(g.n))) g.prismatic.push_back(v != 0.0);
    g.c = vec_field(kw, "c");
    g.o = vec_field(kw, "o");
    g.u = vec_field(kw, "u");
    g.hp = vec_field(kw, "hp");
    g.a1 = vec_field(kw, "a1");
    g.a2 = vec_field(kw, "a2");
    g.a3 = vec_field(kw, "a3");
    matrix2(kw, "Q", g.Q);
    matrix2(kw, "Q_inv", g.Q_inv);
    pair_field(kw, "f", g.f);
    g.rank1 = flag(kw, "rank1");
    pair_field(kw, "lam", g.lam);
    pair_field(kw, "mu", g.mu);
    g.snap_t2 = flag(kw, "snap_t2");
    g.q5_aligned = doubles(kw, "q5_aligned", 0);
    g.b_aligned = number(kw, "b_aligned");
    for (double v : doubles(kw, "revolute_joints", 0)) {
        if (v < 0 || v >= g.n || v != double(int(v)))
            throw nb::value_error("CaseGeometry: revolute_joints must be joint indices 0 .. n - 1");
        g.revolute_joints.push_back(int(v));
    }
    g.prismatic_joint = integer(kw, "prismatic_joint");
    if (g.prismatic_joint < -1 || g.prismatic_joint >= g.n)
        throw nb::value_error("CaseGeometry: prismatic_joint must be -1 or a joint index");
    if (g.kind == CaseKind::Planar && g.revolute_joints.size() != 2 && g.revolute_joints.size() != 3)
        throw nb::value_error("CaseGeometry: a planar arm needs 2 or 3 revolute_joints");
    if (g.kind == CaseKind::General) {
        if (std::any_of(g.prismatic.begin(), g.prismatic.end(), [](std::uint8_t v) { return v != 0; }))
            throw nb::value_error("CaseGeometry: the general 6R case takes revolute joints only");
        const int shift = kw.contains("general_shift") ? integer(kw, "general_shift") : 0;
        if (shift < 0 || shift > 5) throw nb::value_error("CaseGeometry: general_shift must be 0 .. 5");
        prepare_general(g.h.data(), g.p.data(), shift, g.general);
    }
    g.k = g.kind == CaseKind::Planar ? 2 : g.kind == CaseKind::Point ? 4 : g.kind == CaseKind::General ? kGeneralRoots : 8;
    if (kw.contains("k") && integer(kw, "k") != g.k)
        throw nb::value_error(("CaseGeometry: k must be " + std::to_string(g.k) + " for this kind").c_str());
    return g;
}

// Every candidate of one joint motion G = (R, t) as new arrays (q (k, n), valid, family (k,)).
nb::tuple solve_one(const CaseGeometry& g, In R, In t) {
    if (R.size() != 9 || t.size() != 3) throw nb::value_error("solve_pose: expected R (3, 3) and t (3,)");
    const double* r = R.data();
    const Mat3 M{{{r[0], r[1], r[2]}, {r[3], r[4], r[5]}, {r[6], r[7], r[8]}}};
    nb::module_ np = nb::module_::import_("numpy");
    nb::object q = np.attr("empty")(nb::make_tuple(g.k, g.n));
    nb::object valid = np.attr("empty")(g.k, nb::arg("dtype") = "bool");
    nb::object family = np.attr("empty")(g.k, nb::arg("dtype") = "bool");
    solve_pose(g, M, vec3(t.data()), nb::cast<Out>(q).data(), nb::cast<OutBool>(valid).data(),
               nb::cast<OutBool>(family).data());
    return nb::make_tuple(q, valid, family);
}

// ------------------------------------------------------------------- subproblems

std::pair<Pair, Flags> angles(const Angles2& s) { return {{s.t[0], s.t[1]}, {s.ok[0], s.ok[1]}}; }

}  // namespace

void bind_closed_form(nb::module_& m) {
    m.attr("OUT_TOLERANCE") = kOutTolerance;
    m.attr("TANGENT_TOLERANCE") = kTangentTolerance;
    m.attr("FREE_TOLERANCE") = kFreeTolerance;
    m.attr("DUPLICATE_TOLERANCE") = kDuplicateTolerance;
    m.attr("RANK_ONE_TOLERANCE") = kRankOne;

    m.def("rotate", [](V3 k, double t, V3 v) { return tuple3(rotate(vec(k), t, vec(v))); }, nb::arg("k"),
          nb::arg("theta"), nb::arg("v"), "R(k, theta) v by Rodrigues' formula (k a unit vector).");
    m.def("trig_coeffs", [](V3 h, V3 k, V3 v) {
            const TrigCoeffs c = trig_coeffs(vec(h), vec(k), vec(v));
            return std::make_tuple(c.constant, c.cos_coeff, c.sin_coeff);
        }, nb::arg("h"), nb::arg("k"), nb::arg("v"),
        "(constant, cos_coeff, sin_coeff) with h . R(k, t) v = constant + cos_coeff cos t + sin_coeff sin t.");
    m.def("sp1", [](V3 p, V3 q, V3 k) {
            const Angle1 s = sp1(vec(p), vec(q), vec(k));
            return std::make_pair(s.t, s.free);
        }, nb::arg("p"), nb::arg("q"), nb::arg("k"),
        "SP1: (theta, free), the angle with R(k, theta) p = q (least squares); free: p on the axis.");
    m.def("solve_trig_linear", [](double a, double b, double c, double size, bool snap) {
            const Angles2 s = solve_trig_linear(a, b, c, size, snap);
            auto [t, ok] = angles(s);
            return std::make_tuple(t, ok, s.free);
        }, nb::arg("a"), nb::arg("b"), nb::arg("c"), nb::arg("size"), nb::arg("snap") = true,
        "((theta0, theta1), (valid0, valid1), free): all t with a cos t + b sin t = c.");
    m.def("sp3", [](V3 p1, V3 p2, V3 k, double d) {
            const Angles2 s = sp3(vec(p1), vec(p2), vec(k), d);
            auto [t, ok] = angles(s);
            return std::make_tuple(t, ok, s.free);
        }, nb::arg("p1"), nb::arg("p2"), nb::arg("k"), nb::arg("d"),
        "SP3: ((theta0, theta1), (valid0, valid1), free), all t with |R(k, t) p1 - p2| = d.");
    m.def("sp4", [](V3 h, V3 p, V3 k, double d) {
            const Angles2 s = sp4(vec(h), vec(p), vec(k), d);
            auto [t, ok] = angles(s);
            return std::make_tuple(t, ok, s.free);
        }, nb::arg("h"), nb::arg("p"), nb::arg("k"), nb::arg("d"),
        "SP4: ((theta0, theta1), (valid0, valid1), free), all t with h . R(k, t) p = d.");
    m.def("sp2", [](V3 p1, V3 p2, V3 k1, V3 k2) {
            const AnglePairs2 s = sp2(vec(p1), vec(p2), vec(k1), vec(k2));
            return std::make_tuple(Pair{s.t1[0], s.t1[1]}, Pair{s.t2[0], s.t2[1]}, Flags{s.ok[0], s.ok[1]},
                                   s.free1, s.free2);
        }, nb::arg("p1"), nb::arg("p2"), nb::arg("k1"), nb::arg("k2"),
        "SP2: (theta1 pair, theta2 pair, valid pair, free1, free2), all (t1, t2) with "
        "R(k1, t1) p1 = R(k2, t2) p2.");
    m.def("planar_2r", [](V3 h, V3 a, V3 b, V3 v) {
            const Planar2 s = planar_2r(vec(h), vec(a), vec(b), vec(v));
            return std::make_tuple(Pair{s.ta[0], s.ta[1]}, Pair{s.tb[0], s.tb[1]}, Flags{s.ok[0], s.ok[1]}, s.free);
        }, nb::arg("h"), nb::arg("a"), nb::arg("b"), nb::arg("v"),
        "(ta pair, tb pair, valid pair, free): all (ta, tb) with R(h, ta) (a + R(h, tb) b) = v in the plane "
        "normal to h.");

    m.def("quartic_roots", [](std::array<Complex, 5> c) {
            if (c[0] == 0.0) throw nb::value_error("quartic_roots: the leading coefficient must not be 0");
            std::array<Complex, 4> z;
            quartic_roots(c.data(), z.data());
            return z;
        }, nb::arg("coeffs"), "The 4 roots of coeffs[0] z^4 + ... + coeffs[4] (complex).");

    nb::class_<CaseGeometry>(m, "CaseGeometry",
                             "Everything a closed-form case solver needs from a chain (built once per chain).")
        .def("__init__", [](CaseGeometry* self, nb::kwargs kw) { new (self) CaseGeometry(make_geometry(kw)); })
        .def_ro("n", &CaseGeometry::n)
        .def_ro("k", &CaseGeometry::k)
        .def_ro("rank1", &CaseGeometry::rank1)
        .def_prop_ro("kind", [](const CaseGeometry& g) { return int(g.kind); })
        .def_prop_ro("position_case", [](const CaseGeometry& g) { return int(g.position_case); });
    m.def("solve_pose", &solve_one, nb::arg("geometry"), nb::arg("R"), nb::arg("t"),
          "Every candidate (q (k, n), valid (k,), family (k,)) for the joint motion G = (R, t).");
}

}  // namespace armkit::bindings
