#include "common.hpp"
namespace mbpy {
void bind_ts5700n8500(py::module_&) {}
}  // namespace mbpy
