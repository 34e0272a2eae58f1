#define ARMKIT_IMPORT_NUMPY
#include "bindings.hpp"

NB_MODULE(_core, m) {
    if (_import_array() < 0) throw nanobind::python_error();
    m.doc() = "armkit's compiled core: kinematics, IK and dynamics kernels (C++17). Internal: use armkit's Python API.";
    armkit::bindings::bind_kinematics(m);
    armkit::bindings::bind_closed_form(m);
    armkit::bindings::bind_numeric(m);
    armkit::bindings::bind_solve(m);
    armkit::bindings::bind_workspace(m);
    armkit::bindings::bind_topp(m);
    armkit::bindings::bind_dynamics(m);
#ifdef ARMKIT_TEST_BINDINGS
    m.attr("TEST_BINDINGS") = true;  // rank, verify_candidates, project, damped_step, quartic_roots
#else
    m.attr("TEST_BINDINGS") = false;
#endif
}
