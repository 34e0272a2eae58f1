// The Python module armkit._core: one binding function per concept, called by module.cpp.
#pragma once

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

void bind_kinematics(nb::module_& m);   // Chain, FK, frames, Jacobians, pose errors, checks
void bind_closed_form(nb::module_& m);  // subproblems, case solvers, closed-form candidates
void bind_numeric(nb::module_& m);      // Levenberg-Marquardt
void bind_solve(nb::module_& m);        // the IK pipeline: wrap, verify, rank
void bind_workspace(nb::module_& m);    // reachability: sampling, FK positions, voxel counts in one pass

}  // namespace armkit::bindings
