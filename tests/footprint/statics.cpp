// Firmware-style statics: the stream objects as a firmware declares them (default-constructed
// `static`s, configured at start-up), compiled for Cortex-M4. tests/footprint/CMakeLists.txt
// checks with nm that each lands in .bss (zero-initialised, no flash copied to RAM at boot),
// none in .data.
#include <motionbus/biss/control.hpp>
#include <motionbus/devices/ts5700n8500_emulator.hpp>
#include <motionbus/modbus/framer.hpp>
#include <motionbus/tformat/receiver.hpp>

namespace mb = motionbus;

mb::modbus::rtu_framer static_rtu_framer;
mb::tformat::receiver static_receiver;
motionbus::devices::ts5700n8500::emulator static_encoder_model;
mb::biss::control_master static_control_master;

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n) {
  static_rtu_framer = mb::modbus::rtu_framer({mb::modbus::framer_role::server, in[0]});
  const auto f = static_rtu_framer.feed(mb::byte_view(in, n));
  const auto r = static_receiver.feed(mb::byte_view(in, n));
  const auto reply = static_encoder_model.respond(mb::byte_view(in, n), n);
  const bool cdm = static_control_master.step(n > 3U);
  return static_cast<unsigned>(f.status()) + static_cast<unsigned>(r.status()) +
         static_cast<unsigned>(reply.size) + (cdm ? 1U : 0U);
}
