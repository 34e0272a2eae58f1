// The Python module armkit._core: one binding function per concept, called by module.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <cstdint>
#include <stdexcept>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

// NumPy's C API for the arrays the core returns (one allocation, no capsule): imported once by
// module.cpp (ARMKIT_IMPORT_NUMPY), shared by every binding source through this symbol.
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL armkit_ARRAY_API
#ifndef ARMKIT_IMPORT_NUMPY
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include "armkit/chain.hpp"
#include "armkit/transform.hpp"

namespace armkit::bindings {

namespace nb = nanobind;

// Read-only and writable C-ordered float64 arrays on the CPU (the Python layer checks shapes).
using In = nb::ndarray<const double, nb::c_contig, nb::device::cpu>;
using Out = nb::ndarray<double, nb::c_contig, nb::device::cpu>;
using InBool = nb::ndarray<const bool, nb::c_contig, nb::device::cpu>;
using OutBool = nb::ndarray<bool, nb::c_contig, nb::device::cpu>;

template <typename T>
constexpr int numpy_type();
template <>
constexpr int numpy_type<double>() { return NPY_DOUBLE; }
template <>
constexpr int numpy_type<std::int64_t>() { return NPY_INT64; }
template <>
constexpr int numpy_type<bool>() { return NPY_BOOL; }

// A new (uninitialised) numpy array of the given shape; data points at its values.
template <typename T>
inline nb::object new_array(int ndim, const npy_intp* shape, T*& data) {
    PyObject* array = PyArray_SimpleNew(ndim, const_cast<npy_intp*>(shape), numpy_type<T>());
    if (!array) throw nb::python_error();
    data = static_cast<T*>(PyArray_DATA(reinterpret_cast<PyArrayObject*>(array)));
    return nb::steal(array);
}

// A new numpy array of the given shape (1 or 2 axes) holding a copy of values.
template <typename T>
inline nb::object owned_array(const T* values, std::size_t rows, std::size_t cols = 0) {
    const npy_intp shape[2] = {npy_intp(rows), npy_intp(cols)};
    T* data;
    nb::object array = new_array<T>(cols ? 2 : 1, shape, data);
    std::copy(values, values + (cols ? rows * cols : rows), data);
    return array;
}

// Whether every one of count values is finite (branch-free: the loop vectorises).
inline bool all_finite(const double* values, std::size_t count) {
    bool finite = true;
    for (std::size_t k = 0; k < count; ++k) finite &= std::isfinite(values[k]);
    return finite;
}

// a as the core reads it, if it already is: a numpy array (not a subclass) of native-order
// float64, C-ordered and aligned; else nullptr. Checked without a conversion or a reference.
inline PyArrayObject* float64_array(nb::handle a) {
    if (!PyArray_CheckExact(a.ptr())) return nullptr;
    PyArrayObject* array = reinterpret_cast<PyArrayObject*>(a.ptr());
    if (PyArray_TYPE(array) != NPY_DOUBLE || !PyArray_IS_C_CONTIGUOUS(array) || !PyArray_ISALIGNED(array) ||
        !PyArray_ISNOTSWAPPED(array))
        return nullptr;
    return array;
}

// The values of q if it is exactly one configuration as the core takes it (float64_array, n
// values, one axis); else nullptr (the caller then takes the Python layer's checking path).
inline const double* one_configuration(nb::handle q, int n) {
    PyArrayObject* a = float64_array(q);
    if (!a || PyArray_NDIM(a) != 1 || PyArray_DIM(a, 0) != n) return nullptr;
    return static_cast<const double*>(PyArray_DATA(a));
}

// The values of an input array the Python layer prepared (float64_array) holding `size` values,
// or of None (nullptr); anything else is a bug of the caller.
inline const double* prepared(nb::handle a, std::size_t size, const char* what) {
    if (a.is_none()) return nullptr;
    PyArrayObject* array = float64_array(a);
    if (!array || std::size_t(PyArray_SIZE(array)) != size) throw std::invalid_argument(what);
    return static_cast<const double*>(PyArray_DATA(array));
}

// The values of T if it is transforms (..., 4, 4) as the core takes them (float64_array) that
// check_transform returns unchanged (finite, rigid to tolerance, rotations off by at most 1e-14);
// else nullptr (the caller then takes the Python layer's checking path).
inline const double* exactly_rigid(nb::handle T, double tolerance) {
    PyArrayObject* a = float64_array(T);
    if (!a || PyArray_NDIM(a) < 2 || PyArray_DIM(a, PyArray_NDIM(a) - 1) != 4 ||
        PyArray_DIM(a, PyArray_NDIM(a) - 2) != 4)
        return nullptr;
    const double* values = static_cast<const double*>(PyArray_DATA(a));
    const Rigidity r = rigidity(values, std::size_t(PyArray_SIZE(a)) / 16);
    return r.finite && r.last_row <= tolerance && r.orthonormal <= tolerance && r.rough == 0 ? values : nullptr;
}

void bind_kinematics(nb::module_& m);   // Chain, FK, frames, Jacobians, pose errors, checks
void bind_closed_form(nb::module_& m);  // subproblems, case solvers, closed-form candidates
void bind_numeric(nb::module_& m);      // Levenberg-Marquardt
void bind_solve(nb::module_& m);        // the IK pipeline: wrap, verify, rank
void bind_workspace(nb::module_& m);    // reachability: sampling, FK positions, voxel counts in one pass
void bind_topp(nb::module_& m);         // time-optimal path parameterisation (TOPP-RA), polynomial peaks
void bind_dynamics(nb::module_& m);     // inverse and forward dynamics, mass matrices

}  // namespace armkit::bindings
