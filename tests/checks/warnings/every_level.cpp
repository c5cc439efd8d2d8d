// Compiled at -O0, -O2, -O3 and -Os with the project's warnings as errors (tests/CMakeLists.txt,
// warnings.levels): the public codecs called the way firmware calls them, with exact-size stack
// buffers and run-time lengths, which is where g++'s -O3 vectoriser reported writes past a
// caller's array (-Wstringop-overflow, issue 12 point 8).
#include <motionbus/biss.hpp>
#include <motionbus/devices/absys_emulator.hpp>
#include <motionbus/devices/sm_unit.hpp>
#include <motionbus/devices/sm_unit_emulator.hpp>
#include <motionbus/devices/ts5700n8500.hpp>
#include <motionbus/devices/ts5700n8500_emulator.hpp>
#include <motionbus/modbus.hpp>
#include <motionbus/motionbus.hpp>
#include <motionbus/tformat.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

std::size_t modbus_round(const std::uint16_t* values, std::size_t count) {
  const mb::span<const std::uint16_t> v(values, count);
  std::uint8_t out[32] = {};  // smaller than the largest response: the size check decides
  std::size_t total = mo::encode_read_registers_response(0x03, v, out).value_or(0);
  total += mo::encode_write_multiple_registers(1, v, out).value_or(0);
  total += mo::encode_read_write_multiple_registers(1, 2, 3, v, out).value_or(0);
  total += mo::encode_fifo_response(v, out).value_or(0);
  std::uint8_t adu[mo::max_rtu_size] = {};
  total += mo::encode_rtu(1, mb::byte_view(out, total % 32U + 1U), adu).value_or(0);
  mo::rtu_framer rx(mo::framer_role::server, {1});
  const auto r = rx.feed(mb::byte_view(adu, total % 64U));
  total += r.is_complete() ? r->pdu.size() : 0U;
  return total + out[5] + adu[7];
}

std::size_t tformat_round(std::uint8_t id) {
  std::uint8_t req[mb::tformat::max_request_size] = {};
  const auto n = mb::tformat::encode_request(static_cast<mb::tformat::data_id>(id & 0xFU), id,
                                             static_cast<std::uint8_t>(~id), req);
  motionbus::devices::ts5700n8500::emulator enc;
  const auto rep = enc.respond(mb::byte_view(req, n.value_or(0)), id);
  return rep.size + req[1];
}

}  // namespace

int main(int argc, char**) {
  // values of a length known only at run time, as a host tool has them
  std::vector<std::uint16_t> values(static_cast<std::size_t>(argc) * 15U);
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = static_cast<std::uint16_t>(i * static_cast<std::size_t>(argc));
  }
  std::printf("%zu %zu\n", modbus_round(values.data(), values.size()),
              tformat_round(static_cast<std::uint8_t>(argc)));
  return 0;
}
