// motionbus Python binding — the extension module motionbus._motionbus: one bind_ function per
// protocol and per device profile, each in its own file.
#include <string>

#include "common.hpp"
#include "motionbus/version.hpp"

PYBIND11_MODULE(_motionbus, m) {
  m.doc() =
      "motionbus codecs (T-format, Modbus, BiSS-C) from the C++ headers; use the motionbus "
      "package, not this module.";
  m.attr("__version__") = std::to_string(MOTIONBUS_VERSION_MAJOR) + "." +
                          std::to_string(MOTIONBUS_VERSION_MINOR) + "." +
                          std::to_string(MOTIONBUS_VERSION_PATCH);
  mbpy::bind_core(m);
  mbpy::bind_tformat(m);
  mbpy::bind_modbus(m);
  mbpy::bind_biss(m);
  mbpy::bind_ts5700n8500(m);
  mbpy::bind_sm_unit(m);
  mbpy::bind_absys(m);
  m.attr("_result_classes") = mbpy::result_classes();
}
