// The Python module armkit._core: one binding function per concept, called by module.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <cstdint>

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

// A new numpy array of the given shape (1 or 2 axes) holding a copy of values.
template <typename T>
inline nb::object owned_array(const T* values, std::size_t rows, std::size_t cols = 0) {
    npy_intp shape[2] = {npy_intp(rows), npy_intp(cols)};
    PyObject* array = PyArray_SimpleNew(cols ? 2 : 1, shape, numpy_type<T>());
    if (!array) throw nb::python_error();
    std::copy(values, values + (cols ? rows * cols : rows), static_cast<T*>(PyArray_DATA((PyArrayObject*)array)));
    return nb::steal(array);
}

// Whether every one of count values is finite (branch-free: the loop vectorises).
inline bool all_finite(const double* values, std::size_t count) {
    bool finite = true;
    for (std::size_t k = 0; k < count; ++k) finite &= std::isfinite(values[k]);
    return finite;
}

// The values of q if it is exactly one configuration as the core takes it: a numpy array (not
// a subclass) of n native-order float64, C-ordered and aligned; else nullptr (the caller then
// takes the Python layer's checking path). The fast single-configuration calls start here.
inline const double* one_configuration(nb::handle q, int n) {
    if (!PyArray_CheckExact(q.ptr())) return nullptr;
    PyArrayObject* a = reinterpret_cast<PyArrayObject*>(q.ptr());
    if (PyArray_TYPE(a) != NPY_DOUBLE || PyArray_NDIM(a) != 1 || PyArray_DIM(a, 0) != n ||
        !PyArray_IS_C_CONTIGUOUS(a) || !PyArray_ISALIGNED(a) || !PyArray_ISNOTSWAPPED(a))
        return nullptr;
    return static_cast<const double*>(PyArray_DATA(a));
}

void bind_kinematics(nb::module_& m);   // Chain, FK, frames, Jacobians, pose errors, checks
void bind_closed_form(nb::module_& m);  // subproblems, case solvers, closed-form candidates
void bind_numeric(nb::module_& m);      // Levenberg-Marquardt
void bind_solve(nb::module_& m);        // the IK pipeline: wrap, verify, rank
void bind_workspace(nb::module_& m);    // reachability: sampling, FK positions, voxel counts in one pass
void bind_topp(nb::module_& m);         // time-optimal path parameterisation (TOPP-RA), polynomial peaks
void bind_dynamics(nb::module_& m);     // inverse and forward dynamics, mass matrices

}  // namespace armkit::bindings
