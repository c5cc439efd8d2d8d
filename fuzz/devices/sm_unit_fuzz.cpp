// The SM unit emulator behind the server dispatch, fed a sequence of request PDUs (each framed
// as an RTU ADU for slave 1 or 0). Oracles: no out-of-bounds access; every reply is a valid RTU
// frame from slave 1 that a client decodes against its request (exceptions only with the SM
// unit's codes 01..04); broadcasts are never answered.
#include <motionbus/devices/sm_unit_emulator.hpp>
#include <motionbus/modbus.hpp>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;
namespace sm = motionbus::devices::sm_unit;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sm::emulator unit;
  std::size_t at = 0;
  std::uint32_t now = 0;
  while (at < size) {
    const std::size_t length = 1U + data[at] % 40U;
    const bool broadcast = (data[at] & 0x80U) != 0;
    ++at;
    const std::size_t take = length < size - at ? length : size - at;
    if (take == 0) {
      break;
    }
    const mb::byte_view pdu(data + at, take);
    at += take;
    std::uint8_t adu[mo::max_rtu_size] = {};
    const auto n = mo::encode_rtu(broadcast ? 0 : 1, pdu, adu);
    if (!n) {
      continue;
    }
    now += 250;
    unit.set_time_ms(now);
    std::uint8_t out[mo::max_rtu_size] = {};
    const auto r = mo::serve_rtu(unit, 1, mb::byte_view(adu, n.value()), out);
    MOTIONBUS_FUZZ_CHECK(r.ok());
    if (broadcast) {
      MOTIONBUS_FUZZ_CHECK(r.value() == 0);
      continue;
    }
    MOTIONBUS_FUZZ_CHECK(r.value() > 0);  // the emulator answers every request for it
    const auto f = mo::decode_rtu(mb::byte_view(out, r.value()));
    MOTIONBUS_FUZZ_CHECK(f.is_complete() && f.value().slave == 1);
    const mb::byte_view reply = f.value().pdu;
    if ((reply[0] & mo::exception_flag) != 0U) {
      MOTIONBUS_FUZZ_CHECK(reply.size() == 2 && reply[1] >= 1 && reply[1] <= 4);
      MOTIONBUS_FUZZ_CHECK((reply[0] & 0x7FU) == (pdu[0] & 0x7FU));
      continue;
    }
    const auto d = mo::decode_response_for(pdu, reply, mo::report_id_format::two_bytes_no_count);
    MOTIONBUS_FUZZ_CHECK(d.is_complete());
  }
  return 0;
}
