// The library's RTU server against libmodbus's modbus_reply on any request (the differential
// test's two servers: tests/interop/server_differential.hpp). The first byte: slave 1, or the
// broadcast address when its low bit is set; the rest, the request PDU, cut to the length
// libmodbus's modbus_receive would read for its function (function 01-06: 4 data bytes, 0F and
// 10: 5 and the byte count's, 16: 6, 17: 9 and the byte count's, any other: none); an input too
// short for that is skipped, as is FC11 (each server answers its own identity). Both servers
// start each input from the same image, filled once from a fixed seed. Oracle: the two response
// ADUs and the two images after the request are the same, or differ by a class docs/modbus.md §13
// lists.

// fuzz-max-len: 256 (it reads at most 1 + 253 bytes: the slave byte and the longest request PDU)
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "../../tests/interop/server_differential.hpp"
#include "../fuzz_check.hpp"

namespace {

// The request's length after the function code, as modbus_receive reads it (0: unknown).
std::size_t libmodbus_length(const std::uint8_t* pdu, std::size_t size) {
  const std::uint8_t f = pdu[0];
  if (f >= 0x01 && f <= 0x06) {
    return 4;
  }
  if (f == 0x0F || f == 0x10) {
    return size > 5 ? 5U + pdu[5] : 5U;
  }
  if (f == 0x16) {
    return 6;
  }
  if (f == 0x17) {
    return size > 9 ? 9U + pdu[9] : 9U;
  }
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static server_diff::libmodbus_server theirs;
  static const bool ready = theirs.open();
  MOTIONBUS_FUZZ_CHECK(ready);
  if (size < 2 || data[1] == 0x11) {
    return 0;
  }
  const std::uint8_t slave = (data[0] & 1U) != 0 ? 0 : 1;
  const std::uint8_t* pdu = data + 1;
  const std::size_t available = size - 1;
  const std::size_t n = 1U + libmodbus_length(pdu, available);
  if (n > available || n > motionbus::modbus::max_pdu_size) {
    return 0;
  }
  const std::vector<std::uint8_t> request(pdu, pdu + n);
  // the image from the fixed seed, made once; each input starts both servers from a copy
  static const server_diff::image seeded = [] {
    server_diff::image first;
    std::uint64_t state = 0x28D1FF;
    theirs.fill(first, [&state] {
      std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
      z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
      z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
      return z ^ (z >> 31U);
    });
    return first;
  }();
  static server_diff::image dev;
  dev = seeded;  // same sizes: copies, no allocation
  theirs.load(seeded);
  std::uint8_t adu[motionbus::modbus::max_rtu_size];
  const auto a = motionbus::modbus::encode_rtu(
      slave, motionbus::byte_view(request.data(), request.size()), adu);
  MOTIONBUS_FUZZ_CHECK(a.ok());
  std::uint8_t theirs_out[512];
  const std::size_t their_size = theirs.reply(adu, a.value(), theirs_out);
  std::uint8_t ours[motionbus::modbus::max_rtu_size];
  const auto frame = motionbus::modbus::decode_rtu(motionbus::byte_view(adu, a.value()));
  MOTIONBUS_FUZZ_CHECK(frame.is_complete());
  const std::size_t our_size = motionbus::modbus::serve_frame(dev, 1, frame.value(), ours).value();
  const bool same = our_size == their_size && std::memcmp(ours, theirs_out, our_size) == 0 &&
                    server_diff::same_image(dev, theirs.map);
  if (!same) {
    MOTIONBUS_FUZZ_CHECK(
        !server_diff::difference_class(request, slave == 0, ours, our_size, theirs_out, their_size)
             .empty());
  }
  return 0;
}
