#include "common.hpp"
namespace mbpy {
void bind_biss(py::module_&) {}
}  // namespace mbpy
