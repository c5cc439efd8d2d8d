#include "common.hpp"
namespace mbpy {
void bind_modbus(py::module_&) {}
}  // namespace mbpy
