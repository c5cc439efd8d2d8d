// T-format request decoder and the encoder model (encoder side). Oracles: a complete request
// re-encodes to exactly the bytes consumed; the model's reply to any input is either silence
// (only for a bad sync code) or a response the master decodes without error.
#include <motionbus/devices/ts5700n8500_emulator.hpp>
#include <motionbus/tformat/codec.hpp>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const mb::byte_view in(data, size);
  const auto q = tf::decode_request(in);
  if (q.is_complete()) {
    MOTIONBUS_FUZZ_CHECK(q.consumed() == tf::request_size(q.value().id) && q.consumed() <= size);
    std::uint8_t out[tf::max_request_size] = {};
    const auto n = tf::encode_request(q.value().id, q.value().address, q.value().edf, out);
    MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == q.consumed());
    for (std::size_t i = 0; i < n.value(); ++i) {
      MOTIONBUS_FUZZ_CHECK(out[i] == data[i]);
    }
  } else if (q.is_failed()) {
    MOTIONBUS_FUZZ_CHECK(q.consumed() <= size);
  }

  // Drive the model with the input as a sequence of frames: byte 0 of each chunk is its length.
  motionbus::devices::ts5700n8500::emulator enc;
  std::uint32_t now = 0;
  std::size_t at = 0;
  while (at < size) {
    const std::size_t len = 1U + data[at] % 5U;
    ++at;
    const std::size_t take = len < size - at ? len : size - at;
    const mb::byte_view frame(data + at, take);
    const bool delimiter_error = take > 0 && (data[at] & 0x40U) != 0 && (data[at] & 0x20U) != 0;
    now += 37U * static_cast<std::uint32_t>(take + 1U) * 100U;
    const motionbus::devices::ts5700n8500::reply r =
        enc.respond(frame, now,
                    delimiter_error ? motionbus::devices::ts5700n8500::request_line::delimiter_error
                                    : motionbus::devices::ts5700n8500::request_line::ok);
    if (take == 0 || !tf::sync_ok(frame[0])) {
      MOTIONBUS_FUZZ_CHECK(r.size == 0);
    } else {
      MOTIONBUS_FUZZ_CHECK(r.size > 0);
      const auto d = tf::decode_response(r.view());
      MOTIONBUS_FUZZ_CHECK(d.is_complete() && d.consumed() == r.size);
    }
    at += take;
  }
  return 0;
}
