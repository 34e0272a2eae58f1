#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include <nanobind/stl/tuple.h>
#include <nanobind/stl/variant.h>

#include "armkit/batch.hpp"
#include "armkit/closed_form.hpp"
#include "armkit/ik_solve.hpp"
#include "armkit/tolerances.hpp"
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
    return Found{int(k), cf.chain.n, q.data(), errors.data(), flags.data(), count.data(), case_chain(cf.geometry).size};
}

// The reference configurations (N, n) or (n,) (stride 0), or zeros; the weights (n,), or ones.
struct References {
    double zeros[kMaxJoints] = {}, ones[kMaxJoints];
    const double* near = zeros;
    std::size_t stride = 0;
    const double* weights = ones;

    // near_in: near_size values (nullptr: none); weights_in: n values (nullptr: none).
    References(std::size_t n, std::size_t N, const double* near_in, std::size_t near_size, const double* weights_in) {
        for (double& one : ones) one = 1.0;
        if (near_in) {
            if (near_size != N * n && near_size != n)
                throw std::invalid_argument("near: expected (N, n) or (n,) joint values");
            near = near_in;
            stride = near_size == N * n && N > 1 ? n : 0;
        }
        if (weights_in) weights = weights_in;
    }

    References(const ClosedForm& cf, std::size_t N, const In& near_in, const In& weights_in)
        : References(std::size_t(cf.chain.n), N, near_in.is_valid() ? near_in.data() : nullptr,
                     near_in.is_valid() ? near_in.size() : 0, nullptr) {
        if (weights_in.is_valid()) {
            if (weights_in.size() != std::size_t(cf.chain.n)) throw std::invalid_argument("weights: expected (n,) values");
            weights = weights_in.data();
        }
    }
};

// Poses T (N, 4, 4) with references near (N, n), (n,) or None and weights (n,) or None, as the
// Python layer prepared them (exactly rigid, C-ordered float64): every candidate of each wrapped,
// verified and ranked (solve_poses) into new arrays q (N, k, n), errors (N, k, 2), flags (N, k, 4)
// and count (N,), and the number of poses without a usable candidate. One call for any N.
nb::tuple solve(const ClosedForm& cf, nb::handle T, nb::handle near, nb::handle weights, bool within_limits,
                bool nearest, int threads) {
    PyArrayObject* targets = float64_array(T);
    if (!targets || PyArray_SIZE(targets) % 16 != 0) throw std::invalid_argument("solve: expected poses (N, 4, 4)");
    const std::size_t N = std::size_t(PyArray_SIZE(targets)) / 16, n = std::size_t(cf.chain.n);
    const std::size_t k = std::size_t(cf.k);
    const double* poses = static_cast<const double*>(PyArray_DATA(targets));
    PyArrayObject* near_in = near.is_none() ? nullptr : float64_array(near);
    if (!near.is_none() && !near_in) throw std::invalid_argument("solve: expected near as C-ordered float64");
    const References ref(n, N, near_in ? static_cast<const double*>(PyArray_DATA(near_in)) : nullptr,
                         near_in ? std::size_t(PyArray_SIZE(near_in)) : 0,
                         prepared(weights, n, "solve: expected weights (n,)"));
    const npy_intp N_ = npy_intp(N), k_ = npy_intp(k);
    const npy_intp q_shape[3] = {N_, k_, npy_intp(n)}, errors_shape[3] = {N_, k_, 2}, flags_shape[3] = {N_, k_, kFlags};
    double *q, *errors;
    bool* flags;
    std::int64_t* count;
    nb::object q_out = new_array(3, q_shape, q), errors_out = new_array(3, errors_shape, errors);
    nb::object flags_out = new_array(3, flags_shape, flags), count_out = new_array(1, &N_, count);
    const Found f{int(k), int(n), q, errors, flags, count, case_chain(cf.geometry).size};
    std::atomic<long long> empty{0};
    {
        std::optional<nb::gil_scoped_release> release;  // for a batch: one pose takes less than a release
        if (N > 1) release.emplace();
        parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
            empty += solve_poses(cf, poses, ref.near, ref.stride, ref.weights, within_limits, nearest, f, begin, end);
        });
    }
    return nb::make_tuple(q_out, errors_out, flags_out, count_out, empty.load());
}

// One pose T (4, 4) as solve takes it (exactly rigid, kRigidTolerance) with near (n,) finite
// values or None: solve's listing of it, without solve's five arrays: the usable solutions
// (count, n), nearest first, or with nearest only the first (n,). None if the inputs are not
// as the core takes them or the pose has no usable candidate: the caller then takes the Python
// layer's path, which checks the inputs and raises or falls back to numeric IK. The one-pose
// path of robot.ik, kept thin: the same solve_poses, one allocation.
nb::object solve_one(const ClosedForm& cf, nb::handle T, nb::handle near, bool within_limits, bool nearest) {
    const int n = cf.chain.n, k = cf.k;
    PyArrayObject* target = float64_array(T);
    if (!target || PyArray_NDIM(target) != 2 || !exactly_rigid(T, kRigidTolerance)) return nb::none();
    const double* reference = nullptr;
    if (!near.is_none()) {
        reference = one_configuration(near, n);
        if (!reference || !all_finite(reference, std::size_t(n))) return nb::none();
    }
    const References ref(std::size_t(n), 1, reference, reference ? std::size_t(n) : 0, nullptr);
    double q[kMaxCandidates * kMaxJoints], errors[kMaxCandidates * 2];
    bool flags[kMaxCandidates * kFlags];
    std::int64_t count = 0;
    const Found f{k, n, q, errors, flags, &count, case_chain(cf.geometry).size};
    solve_poses(cf, static_cast<const double*>(PyArray_DATA(target)), ref.near, 0, ref.weights, within_limits,
                nearest, f, 0, 1);
    if (count <= 0) return nb::none();
    return nearest ? owned_array(q, std::size_t(n)) : owned_array(q, std::size_t(count), std::size_t(n));
}

#ifdef ARMKIT_TEST_BINDINGS  // the stages of solve, bound for their tests only (CMake's ARMKIT_TEST_BINDINGS)
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

// The usable solutions of N poses as solve lists them (q (N, k, n), errors (N, k, 2), flags (N, k, 4),
// count (N,)) with every whole-turn copy inside the limits of those inside (TurnCopyLister; of the
// free_joints (n,), None: all), nearest to near ((N, n), (n,) or None: zeros) first by
// |weights * (q - near)| (None: ones), at most limit per pose, each with its solution's residuals
// and flags: new arrays q (N, K, n), errors (N, K, 2), flags (N, K, 4) padded with NaN and false,
// count (N,), and total (N,): how many copies each pose has. If N K (K at least 1) exceeds
// max_rows, the arrays are None (nothing listed, nothing allocated) and count says how many would be.
nb::tuple list_turn_copies(const Chain& chain, In q, In errors, InBool flags, InIndex count, In near, In weights,
                           InBool free_joints, std::size_t limit, double max_rows, int threads) {
    const std::size_t N = count.size(), n = std::size_t(chain.n);
    const std::size_t k = N ? q.size() / (N * n) : 0;
    if (k > std::size_t(kMaxCandidates) || q.size() != N * k * n || errors.size() != N * k * 2 ||
        flags.size() != N * k * kFlags || (near.is_valid() && near.size() != N * n && near.size() != n) ||
        (weights.is_valid() && weights.size() != n) || (free_joints.is_valid() && free_joints.size() != n))
        throw std::invalid_argument("turn_copies: expected q (N, k, n), errors (N, k, 2), flags (N, k, 4), "
                                    "count (N,), near (N, n) or (n,), weights and free_joints (n,)");
    const References ref(n, N, near.is_valid() ? near.data() : nullptr, near.is_valid() ? near.size() : 0,
                         weights.is_valid() ? weights.data() : nullptr);
    bool all[kMaxJoints];
    std::fill(all, all + kMaxJoints, true);
    const bool* free_joint = free_joints.is_valid() ? free_joints.data() : all;
    const double* q_in = q.data();
    const double* errors_in = errors.data();
    const bool* flags_in = flags.data();
    const std::int64_t* count_in = count.data();
    const npy_intp N_ = npy_intp(N);
    std::int64_t* listed;
    double* total;
    nb::object listed_out = new_array(1, &N_, listed), total_out = new_array(1, &N_, total);
    auto expand_of = [&](std::size_t i, bool* expand) {
        const std::int64_t m = std::min<std::int64_t>(count_in[i], std::int64_t(k));
        for (std::int64_t r = 0; r < m; ++r) expand[r] = flags_in[(i * k + std::size_t(r)) * kFlags + kInside];
        return int(std::max<std::int64_t>(m, 0));
    };
    std::size_t K = 0;
    {
        nb::gil_scoped_release release;
        for (std::size_t i = 0; i < N; ++i) {  // counted, not listed: a product per solution
            bool expand[kMaxCandidates];
            const int m = expand_of(i, expand);
            total[i] = count_turn_copies(chain, q_in + i * k * n, expand, m, free_joint);
            listed[i] = std::int64_t(std::min(total[i], double(limit)));
            K = std::max(K, std::size_t(listed[i]));
        }
    }
    if (double(N) * double(std::max<std::size_t>(K, 1)) > max_rows)
        return nb::make_tuple(nb::none(), nb::none(), nb::none(), listed_out, total_out);
    const npy_intp K_ = npy_intp(K);
    const npy_intp q_shape[3] = {N_, K_, npy_intp(n)}, errors_shape[3] = {N_, K_, 2}, flags_shape[3] = {N_, K_, kFlags};
    double *q_out, *errors_out;
    bool* flags_out;
    nb::object q_array = new_array(3, q_shape, q_out), errors_array = new_array(3, errors_shape, errors_out);
    nb::object flags_array = new_array(3, flags_shape, flags_out);
    {
        nb::gil_scoped_release release;
        constexpr double nan = std::numeric_limits<double>::quiet_NaN();
        parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
            TurnCopyLister lister;  // one per thread: its scratch serves every pose of the block
            std::vector<std::int64_t> source(K);
            for (std::size_t i = begin; i < end; ++i) {
                bool expand[kMaxCandidates];
                const int m = expand_of(i, expand);
                double* rows = q_out + i * K * n;
                const std::size_t written = lister.list(chain, q_in + i * k * n, expand, m, free_joint,
                                                        ref.near + ref.stride * i, ref.weights, std::size_t(listed[i]), rows,
                                                        source.data());
                for (std::size_t c = 0; c < written; ++c) {
                    const std::size_t from = i * k + std::size_t(source[c]), to = i * K + c;
                    std::copy(errors_in + 2 * from, errors_in + 2 * from + 2, errors_out + 2 * to);
                    std::copy(flags_in + kFlags * from, flags_in + kFlags * from + kFlags, flags_out + kFlags * to);
                }
                std::fill(rows + written * n, rows + K * n, nan);
                std::fill(errors_out + 2 * (i * K + written), errors_out + 2 * (i + 1) * K, nan);
                std::fill(flags_out + kFlags * (i * K + written), flags_out + kFlags * (i + 1) * K, false);
            }
        });
    }
    return nb::make_tuple(q_array, errors_array, flags_array, listed_out, total_out);
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
    m.def("solve", &solve, nb::arg("closed_form"), nb::arg("T"), nb::arg("near").none(), nb::arg("weights").none(),
          nb::arg("within_limits"), nb::arg("nearest"), nb::arg("threads"),
          "Candidates of poses T (N, 4, 4) (exactly rigid C-ordered float64) wrapped into the limits (reference "
          "near (N, n), (n,) or None: zeros), FK-verified, family representatives moved to the member nearest "
          "to near, ranked by |weights * (q - near)| (None: ones). Returns new arrays q (N, k, n), errors "
          "(N, k, 2) [m, rad], flags (N, k, 4) (valid, keep, inside, family), count (N,) (usable ones, first) "
          "and the number of poses without a usable candidate. nearest: verify nearest first, up to the first "
          "kept. Rough candidates (FK residual above kRefineAbove, 1e-13) are refined by a few "
          "Levenberg-Marquardt steps that stay on their branch.");
    m.def("solve_one", &solve_one, nb::arg("closed_form"), nb::arg("T"), nb::arg("near").none(),
          nb::arg("within_limits"), nb::arg("nearest"),
          "solve's listing of one pose T (4, 4) with near (n,) or None: the usable solutions (count, n), "
          "nearest first (nearest: the first, (n,)); None if T is not an exactly rigid C-ordered float64 "
          "(4, 4), near not n finite float64 values, or no candidate is usable (the caller's checking path).");
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
    m.def("turn_copies", &list_turn_copies, nb::arg("chain"), nb::arg("q"), nb::arg("errors"), nb::arg("flags"),
          nb::arg("count"), nb::arg("near").none(), nb::arg("weights").none(), nb::arg("free_joints").none(),
          nb::arg("limit"), nb::arg("max_rows"), nb::arg("threads"),
          "The usable solutions of N poses as solve lists them with every whole-turn copy inside the limits of "
          "those inside (joints spanning more than a whole turn, of free_joints (n,); None: all), nearest to "
          "near first by |weights * (q - near)|, at most limit per pose, each with its solution's residuals and "
          "flags. Returns (q (N, K, n), errors (N, K, 2), flags (N, K, 4), padded with NaN and false; count "
          "(N,); total (N,): how many copies exist); the arrays are None if N K would exceed max_rows.");
    m.def("duplicates", &duplicates, nb::arg("q"), nb::arg("valid"), nb::arg("prismatic"), nb::arg("duplicate"),
          "Mark the candidates of q (k, n) equal (modulo 2 pi, 1e-9) to an earlier valid one.");
}

}  // namespace armkit::bindings
