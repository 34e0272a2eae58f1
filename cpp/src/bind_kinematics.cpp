#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include <nanobind/stl/tuple.h>

#include "armkit/batch.hpp"
#include "armkit/fk.hpp"
#include "armkit/linalg.hpp"
#include "armkit/tolerances.hpp"
#include "armkit/transform.hpp"
#include "armkit/turn_copies.hpp"
#include "bindings.hpp"

namespace armkit::bindings {

namespace {

Chain make_chain(In T_between, InBool prismatic, In lower, In upper) {
    const std::size_t n = prismatic.shape(0);
    if (n == 0 || n > std::size_t(kMaxJoints) || T_between.size() != 16 * (n + 1) || lower.size() != n ||
        upper.size() != n)
        throw std::invalid_argument("Chain: expected T_between (n + 1, 4, 4), prismatic, lower, upper (n,), "
                                    "1 <= n <= 16");
    Chain chain;
    chain.n = int(n);
    for (std::size_t i = 0; i <= n; ++i) chain.between.push_back(pose_from_matrix(T_between.data() + 16 * i));
    chain.prismatic.assign(prismatic.data(), prismatic.data() + n);
    chain.lower.assign(lower.data(), lower.data() + n);
    chain.upper.assign(upper.data(), upper.data() + n);
    return chain;
}

// first <- bad if it is the first bad index seen so far (-1: none yet), across threads.
void keep_first(std::atomic<long long>& first, long long bad) {
    long long seen = first.load();
    while ((seen < 0 || bad < seen) && !first.compare_exchange_weak(seen, bad)) {
    }
}

// Runs item(i) for every configuration of q (N x n) whose values are all finite, in
// parallel; returns the flat index of the first non-finite value, or -1 (then the
// outputs of the configurations after it may be unset).
template <class Item>
long long for_each_configuration(const Chain& chain, const double* q, std::size_t N, int threads, Item&& item) {
    const std::size_t n = std::size_t(chain.n);
    std::atomic<long long> first_bad{-1};
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const double* qi = q + n * i;
            for (std::size_t j = 0; j < n; ++j) {
                if (!std::isfinite(qi[j])) {
                    keep_first(first_bad, (long long)(n * i + j));
                    return;
                }
            }
            item(i, qi);
        }
    });
    return first_bad.load();
}

std::size_t configurations(const Chain& chain, const In& q) {
    if (q.size() % std::size_t(chain.n) != 0)
        throw std::invalid_argument("q: expected (N, n) joint values");
    return q.size() / std::size_t(chain.n);
}

// Tool poses of the N configurations qs (N x n) into out (N x 4 x 4); the flat index of the
// first non-finite value, or -1.
long long fk_into(const Chain& chain, const double* qs, std::size_t N, double* out, int threads) {
    const std::size_t n = std::size_t(chain.n);
    if (N < std::size_t(kFkBlock))  // one configuration (or a few): no block
        return for_each_configuration(chain, qs, N, threads, [&](std::size_t i, const double* qi) {
            pose_to_matrix(tool_pose(chain, qi), out + 16 * i);
        });
    // Blocks of kFkBlock configurations; a block holding a non-finite value (and the tail)
    // goes one configuration at a time, which finds the first bad value.
    std::atomic<long long> first_bad{-1};
    const std::size_t blocks = N / kFkBlock;
    parallel_for(blocks + 1, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t start = k * kFkBlock, count = std::min<std::size_t>(kFkBlock, N - start);
            if (count == std::size_t(kFkBlock) && all_finite(qs + n * start, n * count)) {
                tool_poses_blocks(chain, qs + n * start, out + 16 * start, 1);
                continue;
            }
            for (std::size_t i = start; i < start + count; ++i) {
                const double* qi = qs + n * i;
                if (!all_finite(qi, n)) {
                    std::size_t j = 0;
                    while (std::isfinite(qi[j])) ++j;
                    keep_first(first_bad, (long long)(n * i + j));
                    return;
                }
                pose_to_matrix(tool_pose(chain, qi), out + 16 * i);
            }
        }
    });
    return first_bad.load();
}

// Base-frame (or with tool, tool-frame) geometric Jacobians (N x 6 x n, rows [v; w]) of qs (N x n)
// into out, and their tool poses into poses (N x 4 x 4) unless nullptr; as fk_into for bad values.
long long jacobians_into(const Chain& chain, const double* qs, std::size_t N, bool tool, double* out, double* poses,
                        int threads) {
    const std::size_t n = std::size_t(chain.n);
    return for_each_configuration(chain, qs, N, threads, [&](std::size_t i, const double* qi) {
        Vec3 axes[kMaxJoints], points[kMaxJoints];
        const Pose T = joint_axes(chain, qi, axes, points);
        double* J = out + 6 * n * i;
        jacobian_from_axes(T, axes, points, chain.prismatic.data(), chain.n, J);
        if (tool)  // the same twist in tool coordinates: R^T v and R^T w
            for (std::size_t c = 0; c < n; ++c)
                for (std::size_t half = 0; half < 6; half += 3) {
                    const Vec3 x{J[(half + 0) * n + c], J[(half + 1) * n + c], J[(half + 2) * n + c]};
                    for (int r = 0; r < 3; ++r)
                        J[(half + std::size_t(r)) * n + c] = T(0, r) * x.x + T(1, r) * x.y + T(2, r) * x.z;
                }
        if (poses) pose_to_matrix(T, poses + 16 * i);
    });
}

// q as the core reads it, with its last axis n joint values: q itself if it already is a
// float64_array, else converted as numpy.asarray(q, dtype=float) would (numbers only: text,
// bools and complex numbers are not joint values); an invalid object if it cannot be (the
// caller's checks then say why).
nb::object joint_values(nb::handle q, int n) {
    nb::object values;
    if (float64_array(q)) {
        values = nb::borrow(q);
    } else {
        PyObject* raw = PyArray_FromAny(q.ptr(), nullptr, 0, 0, NPY_ARRAY_ENSUREARRAY, nullptr);
        if (!raw) {
            PyErr_Clear();
            return nb::object();
        }
        const nb::object as_given = nb::steal(raw);
        const char kind = PyArray_DESCR(reinterpret_cast<PyArrayObject*>(raw))->kind;
        if (kind != 'i' && kind != 'u' && kind != 'f' && kind != 'O') return nb::object();
        PyObject* converted = PyArray_FromAny(raw, PyArray_DescrFromType(NPY_DOUBLE), 0, 0,
                                              NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED | NPY_ARRAY_ENSUREARRAY |
                                                  NPY_ARRAY_FORCECAST,
                                              nullptr);
        if (!converted) {
            PyErr_Clear();
            return nb::object();
        }
        values = nb::steal(converted);
    }
    PyArrayObject* a = reinterpret_cast<PyArrayObject*>(values.ptr());
    if (PyArray_NDIM(a) < 1 || PyArray_DIM(a, PyArray_NDIM(a) - 1) != n) return nb::object();
    return values;
}

// Joint values the core cannot take, raised as armkit._core.RefusedJointValues: what() is the flat
// index of the first non-finite value, or -1 for values that are not (..., n) numbers (the Python
// layer's checks then say why, in its words).
struct RefusedJointValues : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A new array of q's batch shape followed by rows x cols, for the results of q (..., n).
template <class Fill>
nb::object per_configuration(const Chain& chain, nb::handle q_in, npy_intp rows, npy_intp cols, Fill&& fill) {
    const nb::object q = joint_values(q_in, chain.n);
    PyArrayObject* a = q.is_valid() ? reinterpret_cast<PyArrayObject*>(q.ptr()) : nullptr;
    const int axes = a ? PyArray_NDIM(a) + 1 : 0;
    if (!a || axes > NPY_MAXDIMS) throw RefusedJointValues("-1");
    npy_intp shape[NPY_MAXDIMS];
    std::copy(PyArray_DIMS(a), PyArray_DIMS(a) + axes - 2, shape);
    shape[axes - 2] = rows;
    shape[axes - 1] = cols;
    double* out;
    nb::object array = new_array(axes, shape, out);
    const std::size_t N = std::size_t(PyArray_SIZE(a)) / std::size_t(chain.n);
    const double* values = static_cast<const double*>(PyArray_DATA(a));
    long long bad;
    if (N > 1) {
        nb::gil_scoped_release release;
        bad = fill(values, N, out);
    } else {  // one configuration: releasing the GIL would cost more than the arithmetic
        bad = fill(values, N, out);
    }
    if (bad >= 0) throw RefusedJointValues(std::to_string(bad));
    return array;
}

// The one call behind fk and Robot.fk for any batch shape: the tool poses (..., 4, 4) of q
// (..., n) in a new array (RefusedJointValues for values it cannot take).
nb::object fk(const Chain& chain, nb::handle q, int threads) {
    return per_configuration(chain, q, 4, 4, [&](const double* values, std::size_t N, double* T) {
        return fk_into(chain, values, N, T, threads);
    });
}

// As fk, for the geometric Jacobians (..., 6, n), in the base frame or (tool) the tool frame.
nb::object jacobian(const Chain& chain, nb::handle q, bool tool, int threads) {
    return per_configuration(chain, q, 6, chain.n, [&](const double* values, std::size_t N, double* J) {
        return jacobians_into(chain, values, N, tool, J, nullptr, threads);
    });
}

long long joint_frames(const Chain& chain, In q, Out frames, Out tool, int threads) {
    const std::size_t N = configurations(chain, q), n = std::size_t(chain.n);
    if (frames.size() != 16 * n * N || tool.size() != 16 * N)
        throw std::invalid_argument("joint_frames: expected outputs (N, n, 4, 4) and (N, 4, 4)");
    double *F = frames.data(), *P = tool.data();
    return for_each_configuration(chain, q.data(), N, threads, [&](std::size_t i, const double* qi) {
        const JointTrig trig(qi, chain.n);
        Pose T = chain.between[0];
        for (std::size_t j = 0; j < n; ++j) {
            move(T, qi, trig, int(j), chain.prismatic[j]);
            pose_to_matrix(T, F + 16 * (n * i + j));
            T = compose(T, chain.between[j + 1]);
        }
        pose_to_matrix(T, P + 16 * i);
    });
}

long long pose_jacobian(const Chain& chain, In q, Out J, Out T, int threads) {
    const std::size_t N = configurations(chain, q), n = std::size_t(chain.n);
    if (J.size() != 6 * n * N || T.size() != 16 * N)
        throw std::invalid_argument("pose_jacobian: expected outputs (N, 6, n) and (N, 4, 4)");
    return jacobians_into(chain, q.data(), N, false, J.data(), T.data(), threads);
}

void joint_axes_points(const Chain& chain, In q, Out axes, Out points) {
    if (q.size() != std::size_t(chain.n) || axes.size() != 3 * q.size() || points.size() != 3 * q.size())
        throw std::invalid_argument("joint_axes: expected q (n,), outputs (n, 3)");
    Vec3 a[kMaxJoints], p[kMaxJoints];
    joint_axes(chain, q.data(), a, p);
    for (int j = 0; j < chain.n; ++j) {
        axes.data()[3 * j] = a[j].x, axes.data()[3 * j + 1] = a[j].y, axes.data()[3 * j + 2] = a[j].z;
        points.data()[3 * j] = p[j].x, points.data()[3 * j + 1] = p[j].y, points.data()[3 * j + 2] = p[j].z;
    }
}

void pose_errors(In T_target, In T, Out e, int threads) {
    const std::size_t N = T.size() / 16;
    if (T_target.size() != 16 * N || e.size() != 6 * N)
        throw std::invalid_argument("pose_error: expected (N, 4, 4), (N, 4, 4) and an output (N, 6)");
    const double *A = T_target.data(), *B = T.data();
    double* out = e.data();
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            pose_error(pose_from_matrix(A + 16 * i), pose_from_matrix(B + 16 * i), out + 6 * i);
    });
}

void wrap_into_limits(const Chain& chain, In q, In reference, Out out) {
    const std::size_t n = std::size_t(chain.n), N = configurations(chain, q);
    if (reference.size() != n * N || out.size() != n * N)
        throw std::invalid_argument("wrap_into_limits: expected q, reference and the output (N, n)");
    for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            const double v = q.data()[n * i + j];
            out.data()[n * i + j] = chain.prismatic[j] ? v
                : wrap_angle_into_limits(v, chain.lower[j], chain.upper[j], reference.data()[n * i + j]);
        }
}

}  // namespace

void bind_kinematics(nb::module_& m) {
    nb::class_<Chain>(m, "Chain", "A chain's fixed transforms between joint motions, joint kinds and limits.")
        .def(nb::new_(&make_chain), nb::arg("T_between"), nb::arg("prismatic"), nb::arg("lower"),
             nb::arg("upper"))
        .def_ro("n", &Chain::n)
        .def_prop_ro("spans_turns", [](const Chain& chain) {
            nb::list joints;
            for (int j = 0; j < chain.n; ++j)
                if (spans_turns(chain, j)) joints.append(j);
            return joints;
        }, "The revolute joints whose finite limits span more than a whole turn (their angles have "
           "several whole-turn copies inside the limits).");
    m.attr("LIMIT_TOLERANCE") = kLimitTolerance;
    m.attr("MAX_JOINTS") = kMaxJoints;
    const auto release = nb::call_guard<nb::gil_scoped_release>();
    nb::exception<RefusedJointValues>(m, "RefusedJointValues");
    m.def("fk", &fk, nb::arg("chain"), nb::arg("q").none(), nb::arg("threads"),
          "Tool poses (..., 4, 4) of joint values q (..., n) (anything numpy.asarray(q, dtype=float) takes) in "
          "a new array. Raises RefusedJointValues(index of the first non-finite value, or -1 if q is not "
          "(..., n) numbers).");
    m.def("jacobian", &jacobian, nb::arg("chain"), nb::arg("q").none(), nb::arg("tool"), nb::arg("threads"),
          "Geometric Jacobians (..., 6, n), rows [v; w], of q (..., n), in the base frame or (tool) the tool "
          "frame, in a new array; RefusedJointValues as fk.");
    m.def("joint_frames", &joint_frames, nb::arg("chain"), nb::arg("q"), nb::arg("frames"), nb::arg("tool"),
          nb::arg("threads"), release,
          "Joint frames after each motion (N, n, 4, 4) and tool poses (N, 4, 4); as fk for bad q.");
    m.def("pose_jacobian", &pose_jacobian, nb::arg("chain"), nb::arg("q"), nb::arg("J"), nb::arg("T"),
          nb::arg("threads"), release,
          "Base-frame geometric Jacobians (N, 6, n), rows [v; w], and tool poses of q (N, n) into J and tool; "
          "the flat index of the first non-finite q, or -1.");
    m.def("joint_axes", &joint_axes_points, nb::arg("chain"), nb::arg("q"), nb::arg("axes"), nb::arg("points"),
          "Joint axes and points on them (n, 3), base frame, of one configuration.");
    m.def("pose_error", &pose_errors, nb::arg("T_target"), nb::arg("T"), nb::arg("e"), nb::arg("threads"),
          release, "Pose errors (N, 6): p_target - p and the rotation vector of R_target R^T.");
    m.def("wrap_into_limits", &wrap_into_limits, nb::arg("chain"), nb::arg("q"), nb::arg("reference"),
          nb::arg("out"), "Revolute angles of q (N, n) shifted by whole turns into the limits.");
    m.def("rigidity", [](In T) {
        const Rigidity r = rigidity(T.data(), T.size() / 16);
        return nb::make_tuple(r.finite, r.last_row, r.orthonormal, r.rough);
    }, nb::arg("T"), "For transforms (N, 4, 4): all finite, worst last row, worst |R^T R - I| or |det - 1|, "
                     "how many are off by more than 1e-14.");
    m.attr("RIGID_TOLERANCE") = kRigidTolerance;
    m.def("exactly_rigid", [](nb::handle T, double tolerance) { return exactly_rigid(T, tolerance) != nullptr; },
       nb::arg("T"), nb::arg("tolerance"),
       "Whether T is transforms (..., 4, 4) as the core takes them (C-ordered native float64) that "
       "check_transform would return unchanged (finite, rigid to tolerance, off by at most 1e-14).");
}

}  // namespace armkit::bindings
