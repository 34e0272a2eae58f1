// armkit._core's dynamics: the model (a chain and its bodies) and the batch algorithms.
#include <atomic>
#include <cmath>
#include <cstddef>
#include <stdexcept>

#include "armkit/batch.hpp"
#include "armkit/dynamics.hpp"
#include "armkit/linalg.hpp"
#include "bindings.hpp"

namespace armkit::bindings {

namespace {

Vec3 gravity_vector(const In& gravity) {
    if (gravity.size() != 3) throw std::invalid_argument("gravity: expected (3,)");
    return vec3(gravity.data());
}

Dynamics make_dynamics(const Chain& chain, In mass, In moment, In inertia, In gravity) {
    const std::size_t n = std::size_t(chain.n);
    if (mass.size() != n || moment.size() != 3 * n || inertia.size() != 9 * n)
        throw std::invalid_argument("Dynamics: expected mass (n,), moment (n, 3), inertia (n, 3, 3)");
    Dynamics model{chain, {}, {}, {}, gravity_vector(gravity)};
    for (std::size_t i = 0; i < n; ++i) {
        model.mass.push_back(mass.data()[i]);
        model.moment.push_back(vec3(moment.data() + 3 * i));
        const double* I = inertia.data() + 9 * i;
        model.inertia.push_back(Mat3{{vec3(I), vec3(I + 3), vec3(I + 6)}});
    }
    return model;
}

// The number of states N of an (N, n) array, checked against the other (N, n) arrays given.
std::size_t states(const Dynamics& model, const In& q, std::initializer_list<const In*> others) {
    const std::size_t n = std::size_t(model.chain.n);
    if (q.size() % n != 0) throw std::invalid_argument("q: expected (N, n) joint values");
    for (const In* other : others)
        if (other->is_valid() && other->size() != q.size())
            throw std::invalid_argument("expected arrays of the shape of q, (N, n)");
    return q.size() / n;
}

const double* data_or_null(const In& a) { return a.is_valid() ? a.data() : nullptr; }

void inverse_dynamics_batch(const Dynamics& model, In q, In qd, In qdd, In gravity, Out tau, int threads) {
    const std::size_t N = states(model, q, {&qd, &qdd}), n = std::size_t(model.chain.n);
    if (tau.size() != q.size()) throw std::invalid_argument("inverse_dynamics: expected an output (N, n)");
    const Vec3 g = gravity_vector(gravity);
    const double *qs = q.data(), *qds = data_or_null(qd), *qdds = data_or_null(qdd);
    double* out = tau.data();
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            inverse_dynamics(model, qs + n * i, qds ? qds + n * i : nullptr, qdds ? qdds + n * i : nullptr, g,
                             out + n * i);
    });
}

// One state, the common single call: the values of each array of a state as one_configuration
// takes them (None for qd or qdd where `optional`: zero, nullptr), finite. False for anything else
// (a batch, a list, a value not finite): the caller's checked path then answers or names it.
bool one_state(int n, std::initializer_list<std::pair<nb::handle, const double**>> arrays, bool optional) {
    for (const auto& [value, data] : arrays) {
        if (optional && value.is_none()) {
            *data = nullptr;
            continue;
        }
        *data = one_configuration(value, n);
        if (!*data || !all_finite(*data, std::size_t(n))) return false;
    }
    return true;
}

// tau (n,) as a new array, or None (see one_state).
nb::object inverse_dynamics_one(const Dynamics& model, nb::handle q, nb::handle qd, nb::handle qdd) {
    const int n = model.chain.n;
    const double *qs, *qds, *qdds;
    if (!one_state(n, {{q, &qs}}, false) || !one_state(n, {{qd, &qds}, {qdd, &qdds}}, true)) return nb::none();
    double tau[kMaxJoints];
    inverse_dynamics(model, qs, qds, qdds, model.gravity, tau);
    return owned_array(tau, std::size_t(n));
}

// M (n, n) as a new array, or None (see one_state).
nb::object mass_matrix_one(const Dynamics& model, nb::handle q) {
    const int n = model.chain.n;
    const double* qs;
    if (!one_state(n, {{q, &qs}}, false)) return nb::none();
    double M[kMaxJoints * kMaxJoints];
    mass_matrix(model, qs, M);
    return owned_array(M, std::size_t(n), std::size_t(n));
}

// qdd (n,) as a new array, or None (see one_state; also when the mass matrix is singular).
nb::object forward_dynamics_one(const Dynamics& model, nb::handle q, nb::handle qd, nb::handle tau) {
    const int n = model.chain.n;
    const double *qs, *qds, *taus;
    if (!one_state(n, {{q, &qs}, {qd, &qds}, {tau, &taus}}, false)) return nb::none();
    double qdd[kMaxJoints];
    if (!forward_dynamics(model, qs, qds, taus, model.gravity, qdd)) return nb::none();
    return owned_array(qdd, std::size_t(n));
}

void mass_matrix_batch(const Dynamics& model, In q, Out M, int threads) {
    const std::size_t N = states(model, q, {}), n = std::size_t(model.chain.n);
    if (M.size() != N * n * n) throw std::invalid_argument("mass_matrix: expected an output (N, n, n)");
    const double* qs = q.data();
    double* out = M.data();
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) mass_matrix(model, qs + n * i, out + n * n * i);
    });
}

// qdd (N, n); the index of the first state whose mass matrix is not positive definite, or -1.
long long forward_dynamics_batch(const Dynamics& model, In q, In qd, In tau, In gravity, Out qdd, int threads) {
    const std::size_t N = states(model, q, {&qd, &tau}), n = std::size_t(model.chain.n);
    if (!qd.is_valid() || !tau.is_valid() || qdd.size() != q.size())
        throw std::invalid_argument("forward_dynamics: expected q, qd, tau and the output (N, n)");
    const Vec3 g = gravity_vector(gravity);
    const double *qs = q.data(), *qds = qd.data(), *taus = tau.data();
    double* out = qdd.data();
    std::atomic<long long> first_bad{-1};
    parallel_for(N, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            if (forward_dynamics(model, qs + n * i, qds + n * i, taus + n * i, g, out + n * i)) continue;
            long long seen = first_bad.load();  // keep the lowest failing state across threads
            while ((seen < 0 || (long long)i < seen) && !first_bad.compare_exchange_weak(seen, (long long)i)) {
            }
            return;
        }
    });
    return first_bad.load();
}

}  // namespace

void bind_dynamics(nb::module_& m) {
    nb::class_<Dynamics>(m, "Dynamics", "A chain and the mass, first moment and inertia about the origin of "
                                        "each body, in its joint frame; the one-state calls' gravity.")
        .def(nb::new_(&make_dynamics), nb::arg("chain"), nb::arg("mass"), nb::arg("moment"), nb::arg("inertia"),
             nb::arg("gravity"));
    const auto release = nb::call_guard<nb::gil_scoped_release>();
    m.def("inverse_dynamics", &inverse_dynamics_batch, nb::arg("model"), nb::arg("q"), nb::arg("qd").none(),
          nb::arg("qdd").none(), nb::arg("gravity"), nb::arg("tau"), nb::arg("threads"), release,
          "Joint torques of the states (q, qd, qdd) (N, n) into tau (N, n); qd or qdd None: zero.");
    m.def("inverse_dynamics_one", &inverse_dynamics_one, nb::arg("model"), nb::arg("q").none(),
          nb::arg("qd").none(),
          nb::arg("qdd").none(),
          "Joint torques (n,) of one state (n,) each, qd or qdd None: zero, the model's gravity; None if a "
          "value is not finite.");
    m.def("mass_matrix_one", &mass_matrix_one, nb::arg("model"), nb::arg("q").none(),
          "The mass matrix (n, n) of one configuration (n,); None if a value is not finite.");
    m.def("forward_dynamics_one", &forward_dynamics_one, nb::arg("model"), nb::arg("q").none(),
          nb::arg("qd").none(), nb::arg("tau").none(),
          "Joint accelerations (n,) of one state, the model's gravity; None if a value is not finite or M is "
          "singular.");
    m.def("mass_matrix", &mass_matrix_batch, nb::arg("model"), nb::arg("q"), nb::arg("M"), nb::arg("threads"),
          release, "Mass matrices of q (N, n) into M (N, n, n).");
    m.def("forward_dynamics", &forward_dynamics_batch, nb::arg("model"), nb::arg("q"), nb::arg("qd"),
          nb::arg("tau"), nb::arg("gravity"), nb::arg("qdd"), nb::arg("threads"), release,
          "Joint accelerations into qdd (N, n); the first state whose mass matrix is not positive definite, "
          "or -1.");
}

}  // namespace armkit::bindings
