// Modbus RTU ADU decoder. Oracles: never out of bounds; a complete frame re-encodes to exactly
// the input; a single flipped bit in a valid frame is always caught.
#include <motionbus/modbus/rtu.hpp>

#include <cstring>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto f = mo::decode_rtu(mb::byte_view(data, size));
  if (!f.is_complete()) {
    MOTIONBUS_FUZZ_CHECK(f.is_failed() && f.consumed() == size);
    return 0;
  }
  std::uint8_t out[mo::max_rtu_size] = {};
  const auto n = mo::encode_rtu(f.value().slave, f.value().pdu, out);
  MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == size && std::memcmp(out, data, size) == 0);
  // CRC-16 catches every single-bit error
  const std::size_t bit = (data[0] * 131U + size) % (size * 8U);
  out[bit / 8U] = static_cast<std::uint8_t>(out[bit / 8U] ^ (1U << (bit % 8U)));
  MOTIONBUS_FUZZ_CHECK(mo::decode_rtu(mb::byte_view(out, size)).is_failed());
  return 0;
}
