// Firmware-style statics: every stateful type as a firmware declares it (a `static`, configured
// at start-up), compiled for Cortex-M4. tests/footprint/CMakeLists.txt checks with nm that each
// `static_*` object (the stream objects: RTU and ASCII framers, receiver, TS5700N8500 emulator,
// control master) lands in .bss (zero-initialised, no flash copied to RAM at boot), none in .data;
// and that each object's size is the one its header's firmware contract states ("size N bytes").
// The `data_*` objects (the SM unit and ABSYS emulators, whose default state is not all zeros)
// are only sized.
#include <motionbus/biss/control.hpp>
#include <motionbus/devices/absys_emulator.hpp>
#include <motionbus/devices/sm_unit_emulator.hpp>
#include <motionbus/devices/ts5700n8500_emulator.hpp>
#include <motionbus/modbus/ascii.hpp>
#include <motionbus/modbus/framer.hpp>
#include <motionbus/tformat/receiver.hpp>

#include <cstdint>

namespace mb = motionbus;

mb::modbus::rtu_framer static_rtu_framer;
mb::modbus::ascii_framer static_ascii_framer;
mb::tformat::receiver static_receiver;
mb::devices::ts5700n8500::emulator static_ts5700n8500_emulator;
mb::biss::control_master static_control_master;
mb::devices::sm_unit::emulator data_sm_unit_emulator;
mb::devices::absys::emulator data_absys_emulator;

// The smallest register file a control slave can serve: one readable, writable register.
struct one_register {
  std::uint8_t value = 0;
  constexpr bool readable(std::uint8_t a) const noexcept { return a == 0U; }
  constexpr bool writable(std::uint8_t a) const noexcept { return a == 0U; }
  constexpr bool ready() const noexcept { return true; }
  constexpr std::uint8_t read(std::uint8_t) noexcept { return value; }
  constexpr void write(std::uint8_t, std::uint8_t v) noexcept { value = v; }
};
one_register registers;
mb::biss::control_slave<one_register> data_control_slave(registers);

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n) {
  static_rtu_framer = mb::modbus::rtu_framer(mb::modbus::framer_role::server, {in[0]});
  const auto f = static_rtu_framer.feed(mb::byte_view(in, n));
  const auto a = static_ascii_framer.feed(mb::byte_view(in, n));
  const auto r = static_receiver.feed(mb::byte_view(in, n));
  const auto reply = static_ts5700n8500_emulator.respond(mb::byte_view(in, n), n);
  const bool cdm = static_control_master.step(n > 3U);
  data_absys_emulator.control(cdm);
  const bool cds = data_control_slave.step(cdm);
  return static_cast<unsigned>(f.status()) + static_cast<unsigned>(a.status()) +
         static_cast<unsigned>(r.status()) + static_cast<unsigned>(reply.size) + (cdm ? 1U : 0U) +
         (data_sm_unit_emulator.logged_in() ? 1U : 0U) + (data_absys_emulator.cds() ? 1U : 0U) +
         (cds ? 1U : 0U);
}
