// Modbus RTU stream framer. Oracles: never holds more than 256 bytes; every frame it delivers
// is CRC-valid, for its address, and re-encodes to bytes that occur in the input; put() byte by
// byte reports what feed() in chunks does (stream_oracle.hpp); after the t3.5 signal a clean
// frame fed in any chunks is delivered exactly once, unchanged.
#include <motionbus/modbus/framer.hpp>

#include <cstring>
#include <tuple>
#include <vector>

#include "../fuzz_check.hpp"
#include "../stream_oracle.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

bool occurs_in(const std::uint8_t* hay, std::size_t n, const std::uint8_t* needle, std::size_t k) {
  for (std::size_t i = 0; i + k <= n; ++i) {
    if (std::memcmp(hay + i, needle, k) == 0) {
      return true;
    }
  }
  return false;
}

// A result as the oracle compares it: status, error, evidence, and the frame's bytes.
auto note(const mb::decode_result<mo::rtu_frame>& r) {
  const mo::rtu_frame& f = r.value();
  return std::make_tuple(r.status(), r.error(), r.expected(), r.received(), f.slave, f.crc,
                         std::vector<std::uint8_t>(f.pdu.begin(), f.pdu.end()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) {
    return 0;
  }
  const bool server = (data[0] & 1U) != 0;
  const std::uint8_t address = static_cast<std::uint8_t>(1U + data[1] % 247U);
  const std::size_t chunk = 1U + data[2] % 32U;
  mo::framer_options options{server ? mo::framer_role::server : mo::framer_role::client, address};
  options.fc11 = (data[0] & 2U) != 0 ? mo::report_id_format::two_bytes_no_count
                                     : mo::report_id_format::standard;
  options.ends = (data[0] & 4U) != 0 ? mo::frame_end::silence : mo::frame_end::length;
  mo::rtu_framer f(options);
  mo::rtu_framer by_byte(options);
  if (!server) {
    f.sent(address, data[0] >> 3U);
    by_byte.sent(address, data[0] >> 3U);
  }
  const std::uint8_t* stream = data + 3;
  const std::size_t n = size - 3;
  const auto put_results = motionbus_fuzz::results_by_put(by_byte, mb::byte_view(stream, n), note);
  std::vector<decltype(note(f.result()))> feed_results;
  for (std::size_t at = 0; at < n; at += chunk) {
    mb::byte_view in(stream + at, chunk < n - at ? chunk : n - at);
    for (int guard = 0;; ++guard) {
      MOTIONBUS_FUZZ_CHECK(guard < 100000);
      const auto r = f.feed(in);
      MOTIONBUS_FUZZ_CHECK(f.pending() <= mo::max_rtu_size);
      if (r.is_incomplete()) {
        break;
      }
      MOTIONBUS_FUZZ_CHECK(r.consumed() <= in.size());
      in = in.subspan(r.consumed());
      feed_results.push_back(note(r));
      if (r.is_complete()) {
        std::uint8_t out[mo::max_rtu_size] = {};
        const auto k = mo::encode_rtu(r.value().slave, r.value().pdu, out);
        MOTIONBUS_FUZZ_CHECK(k.ok() && occurs_in(stream, n, out, k.value()));
        MOTIONBUS_FUZZ_CHECK(r.value().slave == address || (server && r.value().slave == 0));
      }
    }
  }
  MOTIONBUS_FUZZ_CHECK(put_results == feed_results);
  MOTIONBUS_FUZZ_CHECK(by_byte.pending() == f.pending());
  const auto last = f.idle();  // the silence ends what is held: a frame only if it is one
  if (last.is_complete()) {
    std::uint8_t out[mo::max_rtu_size] = {};
    const auto k = mo::encode_rtu(last.value().slave, last.value().pdu, out);
    MOTIONBUS_FUZZ_CHECK(k.ok() && occurs_in(stream, n, out, k.value()));
    MOTIONBUS_FUZZ_CHECK(last.value().slave == address || (server && last.value().slave == 0));
  }
  MOTIONBUS_FUZZ_CHECK(f.pending() == 0);
  // a clean frame after the silence
  std::uint8_t frame[16] = {};
  const std::uint8_t pdu[] = {0x06, 0x00, 0x01, 0x00, 0x03};
  const std::size_t k = mo::encode_rtu(address, pdu, frame).value();
  if (!server) {
    f.sent(address, 0x06);
  }
  std::size_t found = 0;
  for (std::size_t at = 0; at < k; at += chunk) {
    mb::byte_view in(frame + at, chunk < k - at ? chunk : k - at);
    for (;;) {
      const auto r = f.feed(in);
      if (r.is_incomplete()) {
        break;
      }
      in = in.subspan(r.consumed());
      MOTIONBUS_FUZZ_CHECK(r.is_complete() && r.value().pdu.size() == 5);
      ++found;
    }
  }
  MOTIONBUS_FUZZ_CHECK(found == 1);
  return 0;
}
