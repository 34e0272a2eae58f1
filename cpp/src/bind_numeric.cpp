#include "bindings.hpp"

namespace armkit::bindings {

void bind_numeric(nb::module_&) {}

}  // namespace armkit::bindings
