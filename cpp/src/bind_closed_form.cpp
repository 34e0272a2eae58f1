// Bindings of the subproblems and the case solvers: the registry (_core.CASE_NAMES), one
// class per case geometry (plain structs with typed keyword constructors, built once per
// chain by armkit/ik/closed_form.py), _core.solve_pose (one pose, for tests) and the
// subproblems themselves (for the chain preparation and tests).
#include <algorithm>
#include <array>
#include <memory>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <nanobind/stl/array.h>
#include <nanobind/stl/complex.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/variant.h>
#include <nanobind/stl/vector.h>

#include "armkit/ik_cases.hpp"
#include "armkit/ik_classify.hpp"
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

// ------------------------------------------------------------------ case geometries

using V2 = std::array<double, 2>;
using M2 = std::array<V2, 2>;
using Lines = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Kinds = nb::ndarray<const bool, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// The joint lines of a case's chain: axes h and points p (n, 3), prismatic (n,), 1 <= n <= 6.
CaseChain make_case_chain(Lines h, Lines p, Kinds prismatic) {
    const std::size_t n = h.shape(0);
    if (h.shape(1) != 3 || p.shape(0) != n || p.shape(1) != 3 || prismatic.shape(0) != n || n < 1 ||
        n > std::size_t(kMaxCaseJoints))
        throw nb::value_error(("CaseChain: h and p must both be (n, 3) and prismatic (n,), 1 <= n <= " +
                               std::to_string(kMaxCaseJoints)).c_str());
    CaseChain c;
    c.n = int(n);
    for (std::size_t j = 0; j < n; ++j) {
        c.h[j] = vec3(h.data() + 3 * j);
        c.p[j] = vec3(p.data() + 3 * j);
        c.prismatic[j] = prismatic.data()[j];
        for (int i = 0; i < 3; ++i) c.size = std::max(c.size, 1.0 + std::abs(p.data()[3 * j + i]));
    }
    return c;
}

void copy2(const M2& from, double (&to)[2][2]) {
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) to[i][j] = from[i][j];
}

// position_case: an index of kPositionCaseNames.
void check_position_case(int position_case) {
    if (position_case < 0 || position_case >= kPositionCaseCount)
        throw nb::value_error(("position_case must be 0 .. " + std::to_string(kPositionCaseCount - 1) +
                               " (armkit.ik.cases.POSITION_CASES)").c_str());
}

// The chain of a case with `n` joints (`what` names the case in the error).
void check_joints(const CaseChain& c, int n, const char* what) {
    if (c.n != n)
        throw nb::value_error((std::string(what) + ": needs a chain of " + std::to_string(n) + " joints, got " +
                               std::to_string(c.n)).c_str());
}

// A geometry G constructed in place over `chain` (and a two-angle system), after checking
// that the chain has n joints (0: any).
template <class G>
G& construct(G* g, const CaseChain& chain, int n, const char* what) {
    if (n > 0) check_joints(chain, n, what);
    new (g) G();
    static_cast<CaseChain&>(*g) = chain;
    return *g;
}

template <class G>
G& construct(G* g, const CaseChain& chain, const TwoAngleSystem& system, int n, const char* what) {
    G& out = construct(g, chain, n, what);
    static_cast<TwoAngleSystem&>(out) = system;
    return out;
}

// The fields of the point case (the wrist centre's of a spherical wrist).
void set_point(PointGeometry& g, int position_case, V3 c, V3 o, V3 o2, V3 o3) {
    g.position_case = PositionCase(position_case);
    g.c = vec(c);
    g.o = vec(o);
    g.o2 = vec(o2);
    g.o3 = vec(o3);
}

// The properties every case's Python class has: n, k (candidates per pose) and its registry name.
template <class G, class... Base>
void case_properties(nb::class_<G, Base...>& cls) {
    cls.def_prop_ro("n", [](const G& g) { return g.n; })
        .def_prop_ro("k", [](const G& g) { return case_entry(CaseGeometry(g)).candidates; })
        .def_prop_ro("case", [](const G& g) { return std::string(case_entry(CaseGeometry(g)).name); });
    if constexpr (std::is_base_of_v<TwoAngleSystem, G>)
        cls.def_prop_ro("rank1", [](const G& g) { return g.rank1; }, "Its two-angle system's Q has rank 1.");
}

// Every candidate of one joint motion G = (R, t) as new arrays (q (k, n), valid, family (k,)).
nb::tuple solve_one(const CaseGeometry& g, In R, In t) {
    if (R.size() != 9 || t.size() != 3) throw nb::value_error("solve_pose: expected R (3, 3) and t (3,)");
    const int k = case_entry(g).candidates, n = case_chain(g).n;
    const double* r = R.data();
    const Mat3 M{{{r[0], r[1], r[2]}, {r[3], r[4], r[5]}, {r[6], r[7], r[8]}}};
    nb::module_ np = nb::module_::import_("numpy");
    nb::object q = np.attr("empty")(nb::make_tuple(k, n));
    nb::object valid = np.attr("empty")(k, nb::arg("dtype") = "bool");
    nb::object family = np.attr("empty")(k, nb::arg("dtype") = "bool");
    solve_pose(g, M, vec3(t.data()), nb::cast<Out>(q).data(), nb::cast<OutBool>(valid).data(),
               nb::cast<OutBool>(family).data());
    return nb::make_tuple(q, valid, family);
}

// ------------------------------------------------------------------- detection

// The lines a case works on, as a dict of arrays (axes, points (n, 3), prismatic, index, sign
// (n,), M (4, 4), inverted): armkit.ik.structure.PoeChain's fields.
nb::dict lines_dict(const ArmLines& a) {
    double axes[3 * kMaxCaseJoints], points[3 * kMaxCaseJoints], sign[kMaxCaseJoints], M[16];
    std::int64_t index[kMaxCaseJoints];
    nb::list prismatic;
    for (int j = 0; j < a.n; ++j) {
        const Vec3 h = a.h[j], p = a.p[j];
        axes[3 * j] = h.x, axes[3 * j + 1] = h.y, axes[3 * j + 2] = h.z;
        points[3 * j] = p.x, points[3 * j + 1] = p.y, points[3 * j + 2] = p.z;
        sign[j] = a.sign[j];
        index[j] = a.index[j];
        prismatic.append(bool(a.prismatic[j]));
    }
    pose_to_matrix(a.M, M);
    nb::dict d;
    d["axes"] = owned_array(axes, std::size_t(a.n), 3);
    d["points"] = owned_array(points, std::size_t(a.n), 3);
    d["prismatic"] = prismatic;
    d["index"] = owned_array(index, std::size_t(a.n));
    d["sign"] = owned_array(sign, std::size_t(a.n));
    d["M"] = owned_array(M, 4, 4);
    d["inverted"] = a.inverted;
    return d;
}

// Why each registered case does not apply: (case name, fit name, text) per case.
nb::list reasons(const CaseReason* why) {
    nb::list out;
    for (int c = 0; c < kCaseCount; ++c)
        out.append(nb::make_tuple(kCases[c].name, kCaseFitNames[int(why[c].fit)], why[c].text));
    return out;
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

#ifdef ARMKIT_TEST_BINDINGS  // the quartic solver, bound for its test only
    m.def("quartic_roots", [](std::array<Complex, 5> c) {
            if (c[0] == 0.0) throw nb::value_error("quartic_roots: the leading coefficient must not be 0");
            std::array<Complex, 4> z;
            quartic_roots(c.data(), z.data());
            return z;
        }, nb::arg("coeffs"), "The 4 roots of coeffs[0] z^4 + ... + coeffs[4] (complex).");
#endif

    nb::list names, candidates, position_cases;
    for (const CaseEntry& entry : kCases) names.append(entry.name), candidates.append(entry.candidates);
    for (const char* name : kPositionCaseNames) position_cases.append(name);
    m.attr("CASE_NAMES") = nb::tuple(names);
    m.attr("CASE_CANDIDATES") = nb::tuple(candidates);
    m.attr("POSITION_CASES") = nb::tuple(position_cases);
    m.attr("MAX_CANDIDATES") = kMaxCandidates;

    nb::class_<CaseChain>(m, "CaseChain", "The joint lines a case starts from: axes h, points p (n, 3), prismatic (n,).")
        .def(nb::new_(&make_case_chain), nb::arg("h"), nb::arg("p"), nb::arg("prismatic"))
        .def_ro("n", &CaseChain::n)
        .def_ro("size", &CaseChain::size);
    nb::class_<TwoAngleSystem>(m, "TwoAngleSystem",
                               "The constant part of a two-angle system P x(t1) - Q x(t2) = r (ik_cases.hpp).")
        .def("__init__", [](TwoAngleSystem* s, M2 Q, M2 Q_inv, V2 f, bool rank1, V2 lam, V2 mu, bool snap_t2) {
                 new (s) TwoAngleSystem();
                 copy2(Q, s->Q);
                 copy2(Q_inv, s->Q_inv);
                 s->f[0] = f[0], s->f[1] = f[1];
                 s->rank1 = rank1;
                 s->lam[0] = lam[0], s->lam[1] = lam[1];
                 s->mu[0] = mu[0], s->mu[1] = mu[1];
                 s->snap_t2 = snap_t2;
             }, nb::arg("Q"), nb::arg("Q_inv"), nb::arg("f"), nb::arg("rank1"), nb::arg("lam"), nb::arg("mu"),
             nb::arg("snap_t2") = true)
        .def(nb::init<>())
        .def_ro("rank1", &TwoAngleSystem::rank1);

    nb::class_<PointGeometry> point(m, "PointGeometry",
                                    "Joints 1-3 carry the point c to a target (position IK): 4 candidates.");
    point.def("__init__", [](PointGeometry* g, const CaseChain& chain, const TwoAngleSystem& system, int position_case,
                             V3 c, V3 o, V3 o2, V3 o3) {
                  check_position_case(position_case);
                  set_point(construct(g, chain, system, 3, "PointGeometry"), position_case, c, o, o2, o3);
              }, nb::arg("chain"), nb::arg("system"), nb::arg("position_case"), nb::arg("c"), nb::arg("o"),
              nb::arg("o2"), nb::arg("o3"));
    case_properties(point);
    point.def_prop_ro("c", [](const PointGeometry& g) { return tuple3(g.c); },
                      "The point joints 1-3 carry (a spherical wrist's centre) [m], at q = 0.");
    nb::class_<SphericalGeometry, PointGeometry> spherical(
        m, "SphericalGeometry", "A spherical wrist at c: joints 1-3 place it, then the wrist (u: a normal of h6).");
    spherical.def("__init__", [](SphericalGeometry* g, const CaseChain& chain, const TwoAngleSystem& system,
                                 int position_case, V3 c, V3 o, V3 o2, V3 o3, V3 u) {
                      check_position_case(position_case);
                      set_point(construct(g, chain, system, 6, "SphericalGeometry"), position_case, c, o, o2, o3);
                      g->u = vec(u);
                  }, nb::arg("chain"), nb::arg("system"), nb::arg("position_case"), nb::arg("c"), nb::arg("o"),
                  nb::arg("o2"), nb::arg("o3"), nb::arg("u"));
    case_properties(spherical);
    nb::class_<ThreeParallelGeometry> three(m, "ThreeParallelGeometry",
                                            "Axes 2-4 parallel to hp: (q1, q5), then q6, the angle sum and a 2R.");
    three.def("__init__", [](ThreeParallelGeometry* g, const CaseChain& chain, const TwoAngleSystem& system, V3 hp,
                             V3 u, V3 p5, V3 p6, std::vector<double> q5_aligned, double b_aligned) {
                  if (q5_aligned.size() > 4) throw nb::value_error("ThreeParallelGeometry: at most 4 q5_aligned");
                  construct(g, chain, system, 6, "ThreeParallelGeometry");
                  g->hp = vec(hp), g->u = vec(u), g->p5 = vec(p5), g->p6 = vec(p6);
                  g->aligned = int(q5_aligned.size());
                  std::copy(q5_aligned.begin(), q5_aligned.end(), g->q5_aligned);
                  g->b_aligned = b_aligned;
              }, nb::arg("chain"), nb::arg("system"), nb::arg("hp"), nb::arg("u"), nb::arg("p5"), nb::arg("p6"),
              nb::arg("q5_aligned"), nb::arg("b_aligned"));
    case_properties(three);
    nb::class_<ParallelBaseGeometry> base(m, "ParallelBaseGeometry",
                                          "Axes 1-3 parallel to hp: (q6, q4), then q5, the angle sum and a 2R.");
    base.def("__init__", [](ParallelBaseGeometry* g, const CaseChain& chain, const TwoAngleSystem& system, V3 hp,
                            V3 u, V3 o4, V3 o5, V3 o6) {
                 construct(g, chain, system, 6, "ParallelBaseGeometry");
                 g->hp = vec(hp), g->u = vec(u), g->o4 = vec(o4), g->o5 = vec(o5), g->o6 = vec(o6);
             }, nb::arg("chain"), nb::arg("system"), nb::arg("hp"), nb::arg("u"), nb::arg("o4"), nb::arg("o5"),
             nb::arg("o6"));
    case_properties(base);
    nb::class_<PlanarGeometry> planar(m, "PlanarGeometry",
                                      "SCARA / planar 2R or 3R about hp: angle sum, height, planar 2R.");
    planar.def("__init__", [](PlanarGeometry* g, const CaseChain& chain, V3 hp, V3 u, V3 y, std::vector<int> revolute,
                              int prismatic_joint) {
                   if (revolute.size() != 2 && revolute.size() != 3)
                       throw nb::value_error("PlanarGeometry: a planar arm needs 2 or 3 revolute joints");
                   for (int j : revolute)
                       if (j < 0 || j >= chain.n || chain.prismatic[j])
                           throw nb::value_error("PlanarGeometry: revolute must be revolute joint indices 0 .. n - 1");
                   if (prismatic_joint < -1 || prismatic_joint >= chain.n ||
                       (prismatic_joint >= 0 && !chain.prismatic[prismatic_joint]))
                       throw nb::value_error("PlanarGeometry: prismatic_joint must be -1 or a prismatic joint's index");
                   construct(g, chain, 0, "PlanarGeometry");
                   g->hp = vec(hp), g->u = vec(u), g->y = vec(y);
                   g->revolute_count = int(revolute.size());
                   std::copy(revolute.begin(), revolute.end(), g->revolute);
                   g->prismatic_joint = prismatic_joint;
               }, nb::arg("chain"), nb::arg("hp"), nb::arg("u"), nb::arg("y"), nb::arg("revolute"),
               nb::arg("prismatic_joint"));
    case_properties(planar);
    nb::class_<GeneralGeometry> general(m, "GeneralGeometry",
                                        "Any 6R or 5R1P arm: Raghavan-Roth elimination, the loop starting at joint shift + 1.");
    general.def("__init__", [](GeneralGeometry* g, const CaseChain& chain, int shift) {
                    check_joints(chain, 6, "GeneralGeometry");
                    if (shift < 0 || shift > 5) throw nb::value_error("GeneralGeometry: shift must be 0 .. 5");
                    if (!loop_takes(chain, shift))
                        throw nb::value_error("GeneralGeometry: the general case takes revolute joints and at most "
                                              "one prismatic joint, as the loop's joint 1 or 2 (joint shift + 1 or "
                                              "shift + 2)");
                    auto arm = std::make_shared<GeneralSixR>();
                    prepare_general(chain, shift, *arm);
                    construct(g, chain, 6, "GeneralGeometry");
                    g->arm = std::move(arm);
                }, nb::arg("chain"), nb::arg("shift") = 0);
    case_properties(general);
    m.attr("CLASS_TOLERANCE") = kClassTolerance;
    m.attr("RANK_TOLERANCE") = kRankTolerance;
    m.attr("CANDIDATE_TOLERANCE") = kCandidateTolerance;
    nb::class_<ArmCase>(m, "ArmCase",
                        "The case chosen for a chain by the registry's detect functions, and why the others do "
                        "not apply.")
        .def_ro("chosen", &ArmCase::chosen, "Index of the chosen case in CASE_NAMES, -1 for none.")
        .def_prop_ro("case", [](const ArmCase& a) -> nb::object {
                if (a.chosen < 0) return nb::none();
                return nb::str(kCases[a.chosen].name);
            }, "The chosen case's registry name, or None.")
        .def_ro("kind", &ArmCase::kind)
        .def_ro("description", &ArmCase::description)
        .def_ro("max_solutions", &ArmCase::max_solutions)
        .def_ro("polish", &ArmCase::polish)
        .def_prop_ro("geometry", [](const ArmCase& a) -> nb::object {
                if (a.chosen < 0) return nb::none();
                return nb::cast(a.geometry);
            }, "The chosen case's geometry (None for none).")
        .def_prop_ro("lines", [](const ArmCase& a) { return lines_dict(a.lines); },
                     "The lines the case works on (possibly reversed, axes flipped), as a dict.")
        .def_prop_ro("why_not", [](const ArmCase& a) { return reasons(a.why_not); },
                     "(case, fit, text) for every registered case: fit 'applies' for the chosen one.");
    m.attr("CASE_FITS") = nb::make_tuple(kCaseFitNames[0], kCaseFitNames[1], kCaseFitNames[2], kCaseFitNames[3],
                                         kCaseFitNames[4], kCaseFitNames[5], kCaseFitNames[6], kCaseFitNames[7]);
    m.def("classify", &classify, nb::arg("chain"),
          "The case that solves the chain (the registry's detect functions in order), and why the others do not.");
    m.def("generic_rank", &generic_rank, nb::arg("chain"), nb::arg("tol") = kRankTolerance, nb::arg("joints") = -1,
          nb::arg("position_only") = false,
          "The largest rank of the chain's Jacobian over a few seeded random configurations inside its limits "
          "(only the first `joints` joints moving, the others at 0, if joints >= 0; only the tool point's rows "
          "if position_only).");
    m.def("closed_form_of", [](const Chain& chain, const ArmCase& arm) {
            if (arm.chosen < 0) throw nb::value_error(("closed_form_of: no case applies: " + arm.description).c_str());
            return closed_form_of(chain, arm);
        }, nb::arg("chain"), nb::arg("arm"), "The per-pose loop's constants for the chosen case.");
    m.def("detect_point", [](const Chain& chain, V3 c) -> nb::tuple {
            if (chain.n < 3) throw nb::value_error("detect_point: needs a chain of at least 3 joints");
            Chain three = chain;  // joints 1-3 alone (their lines do not depend on the rest)
            three.n = 3;
            three.between.resize(4);
            const ArmLines lines = first_lines(arm_lines(three), 3, vec(c));
            Detection<PointGeometry> found = detect_point(lines);
            if (auto* why = std::get_if<CaseReason>(&found))
                return nb::make_tuple(nb::none(), kCaseFitNames[int(why->fit)], why->text);
            const CaseMatch<PointGeometry>& m = std::get<CaseMatch<PointGeometry>>(found);
            return nb::make_tuple(nb::cast(m.geometry), lines_dict(m.lines), m.description);
        }, nb::arg("chain"), nb::arg("c"),
        "Joints 1-3 carrying the point c (base frame at q = 0): (PointGeometry, lines, clause), or (None, fit, "
        "reason).");
    m.def("solve_pose", &solve_one, nb::arg("geometry"), nb::arg("R"), nb::arg("t"),
          "Every candidate (q (k, n), valid (k,), family (k,)) of a case geometry for the joint motion G = (R, t).");
}

}  // namespace armkit::bindings
