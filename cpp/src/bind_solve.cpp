#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include <nanobind/stl/tuple.h>
#include <nanobind/stl/variant.h>

#include "armkit/batch.hpp"
#include "armkit/closed_form.hpp"
#include "armkit/ik_solve.hpp"
#include "armkit/turn_copies.hpp"
#include "bindings.hpp"

namespace armkit::bindings {

namespace {

using InIndex = nb::ndarray<const std::int64_t, nb::c_contig, nb::device::cpu>;
using OutIndex = nb::ndarray<std::int64_t, nb::c_contig, nb::device::cpu>;

ClosedForm make_closed_form(const Chain& chain, const CaseGeometry& geometry, InIndex index, In sign, In M_inv,
                            bool inverted, int k, bool verify, bool polish, double verify_tolerance) {
    const std::size_t n = std::size_t(chain.n);
    if (case_chain(geometry).n != chain.n || index.size() != n || sign.size() != n || M_inv.size() != 16 || k < 1 ||
        k > kMaxCandidates)
        throw std::invalid_argument("ClosedForm: expected a geometry of the chain's n joints, index and sign "
                                    "(n,), M_inv (4, 4), 1 <= k <= 16");
    ClosedForm cf;
    cf.chain = chain;
    cf.geometry = geometry;
    bool seen[kMaxJoints] = {};
    for (std::size_t j = 0; j < n; ++j) {
        const std::int64_t user = index.data()[j];
        if (user < 0 || user >= std::int64_t(n) || seen[user])
            throw std::invalid_argument("ClosedForm: index must be a permutation of 0 .. n - 1");
        seen[user] = true;
        cf.index[j] = int(user);
        cf.sign[j] = sign.data()[j];
    }
    cf.M_inv = pose_from_matrix(M_inv.data());
    cf.inverted = inverted;
    cf.k = k;
    cf.verify = verify;
    cf.polish = polish;
    if (std::holds_alternative<GeneralGeometry>(geometry)) {
        cf.polish_steps = kGeneralNewtonSteps;
        cf.polish_stop = kPolished * case_chain(geometry).size;
    }
    cf.verify_tolerance = verify_tolerance;
    return cf;
}

std::size_t poses(const In& T) {
    if (T.size() % 16 != 0) throw std::invalid_argument("T: expected poses (N, 4, 4)");
    return T.size() / 16;
}

// The outputs of N poses as a Found (k candidates per pose: from their sizes), after checking them.
Found found_of(const ClosedForm& cf, std::size_t N, Out& q, Out& errors, OutBool& flags, OutIndex& count) {
    const std::size_t n = std::size_t(cf.chain.n), k = N > 0 ? errors.size() / (2 * N) : std::size_t(cf.k);
    if (k > std::size_t(kMaxCandidates) || q.size() != N * k * n || errors.size() != N * k * 2 ||
        flags.size() != N * k * kFlags || count.size() != N)
        throw std::invalid_argument("expected outputs q (N, k, n), errors (N, k, 2), flags (N, k, 4), count (N,)");
    return Found{int(k), cf.chain.n, q.data(), errors.data(), flags.data(), count.data()};
}

// The reference configurations (N, n) or (n,) (stride 0), or zeros; the weights (n,), or ones.
struct References {
    double zeros[kMaxJoints] = {}, ones[kMaxJoints];
    const double* near = zeros;
    std::size_t stride = 0;
    const double* weights = ones;

    References(const ClosedForm& cf, std::size_t N, const In& near_in, const In& weights_in) {
        const std::size_t n = std::size_t(cf.chain.n);
        for (double& one : ones) one = 1.0;
        if (near_in.is_valid()) {
            if (near_in.size() != N * n && near_in.size() != n)
                throw std::invalid_argument("near: expected (N, n) or (n,) joint values");
            near = near_in.data();
            stride = near_in.size() == N * n && N > 1 ? n : 0;
        }
        if (weights_in.is_valid()) {
            if (weights_in.size() != n) throw std::invalid_argument("weights: expected (n,) values");
            weights = weights_in.data();
        }
    }
};

long long solve_batch(const ClosedForm& cf, In T, In near, In weights, bool within_limits, bool nearest,
                      double rigid_tolerance, Out q, Out errors, OutBool flags, OutIndex count, int threads) {
    const std::size_t N = poses(T);
    const Found f = found_of(cf, N, q, errors, flags, count);
    if (f.k != cf.k) throw std::invalid_argument("solve_batch: expected k = closed_form.k candidates per pose");
    const References ref(cf, N, near, weights);
    nb::gil_scoped_release release;
    if (rigid_tolerance >= 0.0) {
        const Rigidity r = rigidity(T.data(), N);
        if (!(r.finite && r.last_row <= rigid_tolerance && r.orthonormal <= rigid_tolerance && r.rough == 0))
            return -1;
    }
    std::atomic<long long> empty{0};
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        empty += solve_poses(cf, T.data(), ref.near, ref.stride, ref.weights, within_limits, nearest, f, begin, end);
    });
    return empty;
}

// One pose, the common case in one call: the usable solutions (count, n), nearest first, or
// with nearest the nearest one (n,); None where the general path must take over (a target
// not exactly rigid, near not finite, weights not positive, no usable candidate: the
// caller's errors and repairs).
nb::object solve_one(const ClosedForm& cf, In T, In near, In weights, bool within_limits, bool nearest,
                     double rigid_tolerance) {
    const std::size_t n = std::size_t(cf.chain.n);
    if (T.size() != 16) throw std::invalid_argument("solve_one: expected one pose (4, 4)");
    if ((near.is_valid() && near.size() != n) || (weights.is_valid() && weights.size() != n))
        throw std::invalid_argument("solve_one: expected near and weights (n,)");
    const References ref(cf, 1, near, weights);
    for (std::size_t j = 0; j < n; ++j)
        if (!std::isfinite(ref.near[j]) || !(std::isfinite(ref.weights[j]) && ref.weights[j] > 0.0)) return nb::none();
    const Rigidity r = rigidity(T.data(), 1);
    if (!(r.finite && r.last_row <= rigid_tolerance && r.orthonormal <= rigid_tolerance && r.rough == 0))
        return nb::none();
    double q[kMaxCandidates * kMaxJoints], errors[kMaxCandidates * 2];
    bool flags[kMaxCandidates * kFlags];
    std::int64_t count = 0;
    const Found f{cf.k, cf.chain.n, q, errors, flags, &count};
    if (solve_poses(cf, T.data(), ref.near, 0, ref.weights, within_limits, nearest, f, 0, 1) > 0) return nb::none();
    return nearest ? owned_array(q, n) : owned_array(q, std::size_t(count), n);
}

#ifdef ARMKIT_TEST_BINDINGS  // the stages of solve_batch, bound for their tests only (CMake's ARMKIT_TEST_BINDINGS)
void rank(const ClosedForm& cf, InIndex which, In near, In weights, bool within_limits, Out q, Out errors,
          OutBool flags, OutIndex count) {
    const std::size_t N = count.size();
    const Found f = found_of(cf, N, q, errors, flags, count);
    const References ref(cf, N, near, weights);
    for (std::size_t a = 0; a < which.size(); ++a) {
        const std::int64_t i = which.data()[a];
        if (i < 0 || std::size_t(i) >= N) throw std::invalid_argument("rank: pose index out of range");
        rank_pose(cf.chain, f, std::size_t(i), ref.near + ref.stride * std::size_t(i), ref.weights, within_limits);
    }
}

// The verification stage of solve_batch on given candidates: each valid one's FK residuals
// into errors, rough ones refined and wrapped towards their own values (for tests of that
// stage; rank the poses after it).
void verify_candidates(const ClosedForm& cf, In T, Out q, Out errors, OutBool flags, OutIndex count) {
    const std::size_t N = poses(T);
    const Found f = found_of(cf, N, q, errors, flags, count);
    for (std::size_t i = 0; i < N; ++i) {
        const Pose target = pose_from_matrix(T.data() + 16 * i);
        for (int s = 0; s < f.k; ++s) {
            if (!f.flags_of(i, s)[kValid]) continue;
            double own[kMaxJoints];
            std::copy(f.q_of(i, s), f.q_of(i, s) + f.n, own);
            verify(cf.chain, target, f, i, s, own);
        }
    }
}
#endif

void candidates(const ClosedForm& cf, In T, Out q, OutBool valid, OutBool family, int threads) {
    const std::size_t N = poses(T), k = std::size_t(cf.k), n = std::size_t(cf.chain.n);
    if (q.size() != N * k * n || valid.size() != N * k || family.size() != N * k)
        throw std::invalid_argument("candidates: expected outputs q (N, k, n), valid and family (N, k)");
    const double* poses_in = T.data();
    double* q_out = q.data();
    bool *valid_out = valid.data(), *family_out = family.data();
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            pose_candidates(cf, pose_from_matrix(poses_in + 16 * i), q_out + i * k * n, valid_out + i * k,
                            family_out + i * k);
    });
}

void residuals(In T_target, In F, Out out) {
    const std::size_t N = poses(T_target);
    if (F.size() != 16 * N || out.size() != 2 * N)
        throw std::invalid_argument("residuals: expected (N, 4, 4), (N, 4, 4) and an output (N, 2)");
    for (std::size_t i = 0; i < N; ++i)
        pose_residual(pose_from_matrix(T_target.data() + 16 * i), pose_from_matrix(F.data() + 16 * i),
                      out.data()[2 * i], out.data()[2 * i + 1]);
}

void duplicates(In q, InBool valid, InBool prismatic, OutBool duplicate) {
    const std::size_t k = valid.size(), n = prismatic.size();
    if (k > std::size_t(kMaxCandidates) || n > std::size_t(kMaxJoints) || q.size() != k * n ||
        duplicate.size() != k)
        throw std::invalid_argument("duplicates: expected q (k, n), valid (k,), prismatic (n,), duplicate (k,)");
    std::uint8_t kinds[kMaxJoints];
    for (std::size_t j = 0; j < n; ++j) kinds[j] = prismatic.data()[j];
    mark_duplicates(q.data(), int(k), int(n), valid.data(), kinds, duplicate.data());
}

nb::tuple list_turn_copies(const Chain& chain, In T, In q, InBool expand, InBool free_joints, In near, In weights,
                           std::size_t limit) {
    const std::size_t n = std::size_t(chain.n), k = expand.size();
    if (T.size() != 16 || q.size() != k * n || free_joints.size() != n || near.size() != n || weights.size() != n)
        throw std::invalid_argument("turn_copies: expected T (4, 4), q (k, n), expand (k,), free_joints, near "
                                    "and weights (n,)");
    TurnCopies c;
    {
        nb::gil_scoped_release release;
        c = turn_copies(chain, pose_from_matrix(T.data()), q.data(), expand.data(), int(k), free_joints.data(),
                        near.data(), weights.data(), limit);
    }
    const std::size_t m = c.source.size();
    return nb::make_tuple(owned_array(c.source.data(), m), owned_array(c.q.data(), m, n),
                          owned_array(c.errors.data(), m, std::size_t(2)), c.total);
}

}  // namespace

void bind_solve(nb::module_& m) {
    m.attr("SOLUTION_TOLERANCE") = kSolutionTolerance;
    nb::class_<ClosedForm>(m, "ClosedForm",
                           "A chain's closed-form IK: its chain, case geometry, joint map and checks.")
        .def(nb::new_(&make_closed_form), nb::arg("chain"), nb::arg("geometry"), nb::arg("index"),
             nb::arg("sign"), nb::arg("M_inv"), nb::arg("inverted"), nb::arg("k"), nb::arg("verify"),
             nb::arg("polish"), nb::arg("verify_tolerance"))
        .def_ro("k", &ClosedForm::k)
        .def_prop_ro("n", [](const ClosedForm& cf) { return cf.chain.n; });
    m.def("solve_batch", &solve_batch, nb::arg("closed_form"), nb::arg("T"), nb::arg("near").none(),
          nb::arg("weights").none(), nb::arg("within_limits"), nb::arg("nearest"), nb::arg("rigid_tolerance"),
          nb::arg("q"), nb::arg("errors"), nb::arg("flags"), nb::arg("count"), nb::arg("threads"),
          "Candidates of poses T (N, 4, 4) wrapped into the limits (reference near (N, n), (n,) or None: "
          "zeros), FK-verified, family representatives moved to the member nearest to near, ranked by "
          "|weights * (q - near)| (None: ones) into q (N, k, n), errors (N, k, 2) [m, rad], flags (N, k, 4) "
          "(valid, keep, inside, family) and count (N,). nearest: verify nearest first, up to the first kept. "
          "rigid_tolerance >= 0: first check that every T is exactly rigid (as check_transform would return "
          "it unchanged); if not, solve nothing and return -1. Rough candidates (FK residual above "
          "kRefineAbove, 1e-13) are refined by a few Levenberg-Marquardt steps that stay on their branch. "
          "Returns the number of poses without a usable candidate.");
    m.def("solve_one", &solve_one, nb::arg("closed_form"), nb::arg("T"), nb::arg("near").none(),
          nb::arg("weights").none(), nb::arg("within_limits"), nb::arg("nearest"), nb::arg("rigid_tolerance"),
          "One pose (4, 4): its usable solutions (count, n) nearest to near first, or with nearest the "
          "nearest one (n,); None if the target is not exactly rigid, near or weights are bad or no candidate "
          "is usable (then solve_batch and the Python layer take over).");
#ifdef ARMKIT_TEST_BINDINGS
    m.def("rank", &rank, nb::arg("closed_form"), nb::arg("poses"), nb::arg("near").none(),
          nb::arg("weights").none(), nb::arg("within_limits"), nb::arg("q"), nb::arg("errors"), nb::arg("flags"),
          nb::arg("count"), "Flag, count and sort again the candidates of the given poses (in place; the "
          "ranking stage of solve_batch, bound for its tests).");
    m.def("verify_candidates", &verify_candidates, nb::arg("closed_form"), nb::arg("T"), nb::arg("q"),
          nb::arg("errors"), nb::arg("flags"), nb::arg("count"),
          "FK residuals of the valid candidates q (N, k, n) of poses T (N, 4, 4) into errors (N, k, 2), rough "
          "ones (above kRefineAbove, 1e-13) refined on their branch (in place; the verification stage of "
          "solve_batch, bound for its tests).");
#endif
    m.def("candidates", &candidates, nb::arg("closed_form"), nb::arg("T"), nb::arg("q"), nb::arg("valid"),
          nb::arg("family"), nb::arg("threads"), nb::call_guard<nb::gil_scoped_release>(),
          "Every closed-form candidate of poses T (N, 4, 4) into q (N, k, n), valid and family (N, k).");
    m.def("residuals", &residuals, nb::arg("T_target"), nb::arg("F"), nb::arg("out"),
          "FK residuals (N, 2) of poses F to T_target (N, 4, 4): position [m], rotation angle [rad].");
    m.def("turn_copies", &list_turn_copies, nb::arg("chain"), nb::arg("T"), nb::arg("q"), nb::arg("expand"),
          nb::arg("free_joints"), nb::arg("near"), nb::arg("weights"), nb::arg("limit"),
          "The whole-turn copies of solutions q (k, n) of pose T (4, 4): of rows with expand every copy "
          "inside the limits of the free_joints (n,) spanning more than a whole turn, of the others the row itself; "
          "nearest to near (n,) first by |weights * (q - near)|, at most limit. Returns (source (m,): the "
          "row of each copy, q (m, n), errors (m, 2) FK residuals [m, rad], total: how many exist).");
    m.def("duplicates", &duplicates, nb::arg("q"), nb::arg("valid"), nb::arg("prismatic"), nb::arg("duplicate"),
          "Mark the candidates of q (k, n) equal (modulo 2 pi, 1e-9) to an earlier valid one.");
}

}  // namespace armkit::bindings
