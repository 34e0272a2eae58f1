#include "bindings.hpp"

namespace armkit::bindings {

void bind_solve(nb::module_&) {}

}  // namespace armkit::bindings
