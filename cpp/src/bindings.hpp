// The Python module armkit._core: one binding function per concept, called by module.cpp.
#pragma once

#include <algorithm>
#include <cstddef>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "armkit/chain.hpp"

namespace armkit::bindings {

namespace nb = nanobind;

// Read-only and writable C-ordered float64 arrays on the CPU (the Python layer checks shapes).
using In = nb::ndarray<const double, nb::c_contig, nb::device::cpu>;
using Out = nb::ndarray<double, nb::c_contig, nb::device::cpu>;
using InBool = nb::ndarray<const bool, nb::c_contig, nb::device::cpu>;
using OutBool = nb::ndarray<bool, nb::c_contig, nb::device::cpu>;

// A numpy array of the given shape (1 or 2 axes) owning a copy of values.
template <typename T>
inline nb::object owned_array(const T* values, std::size_t rows, std::size_t cols = 0) {
    const std::size_t size = cols ? rows * cols : rows, shape[2] = {rows, cols};
    T* data = new T[size];
    std::copy(values, values + size, data);
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
    return nb::cast(nb::ndarray<nb::numpy, T>(data, cols ? 2 : 1, shape, owner));
}

void bind_kinematics(nb::module_& m);   // Chain, FK, frames, Jacobians, pose errors, checks
void bind_closed_form(nb::module_& m);  // subproblems, case solvers, closed-form candidates
void bind_numeric(nb::module_& m);      // Levenberg-Marquardt
void bind_solve(nb::module_& m);        // the IK pipeline: wrap, verify, rank
void bind_workspace(nb::module_& m);    // reachability: sampling, FK positions, voxel counts in one pass
void bind_topp(nb::module_& m);         // time-optimal path parameterisation (TOPP-RA), polynomial peaks
void bind_dynamics(nb::module_& m);     // inverse and forward dynamics, mass matrices

}  // namespace armkit::bindings
