// The server's framer alone in its translation unit (alone_main.cpp says why): the same calls
// as op_modbus_framer_* in ops.cpp.

#include <motionbus/modbus/framer.hpp>

#include <cstdint>

namespace md = motionbus::modbus;

#define METER_OP extern "C" __attribute__((used, noinline))

extern "C" std::uint32_t meter_out[64];

namespace {
md::rtu_server_framer framer({1});
}  // namespace

METER_OP void op_alone_framer_start() {
  framer = md::rtu_server_framer({1});
}
METER_OP bool op_alone_framer_byte(unsigned byte) {
  return framer.put(static_cast<std::uint8_t>(byte));
}
METER_OP void op_alone_report_framer(unsigned ready) {
  meter_out[0] = 0;
  meter_out[1] = 0;
  if (ready == 0U) {
    return;
  }
  const auto& r = framer.result();
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    meter_out[2] = r->slave;
    meter_out[3] = static_cast<std::uint32_t>(r->pdu.size());
    meter_out[4] = r->pdu[0];
    meter_out[5] = r->crc;
  }
}
