#include "common.hpp"
namespace mbpy {
void bind_sm_unit(py::module_&) {}
}  // namespace mbpy
