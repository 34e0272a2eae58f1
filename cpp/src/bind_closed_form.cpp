#include "bindings.hpp"

namespace armkit::bindings {

void bind_closed_form(nb::module_&) {}

}  // namespace armkit::bindings
