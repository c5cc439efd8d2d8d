#include "common.hpp"
namespace mbpy {
void bind_absys(py::module_&) {}
}  // namespace mbpy
