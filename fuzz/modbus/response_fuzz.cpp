// Modbus response decoder (client side). The input holds a request (length in byte 0) and a
// response. Oracles: never out of bounds; a complete normal response has data consistent with
// the request (byte count = bits/8 rounded up, or 2 per register) and lies inside the input;
// the per-function client decoders agree with decode_response.
#include <motionbus/modbus/pdu_client.hpp>
#include <motionbus/modbus/pdu_server.hpp>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  const std::size_t request_size = 1U + data[0] % 16U;
  if (size < 1U + request_size) {
    return 0;
  }
  const mb::byte_view request(data + 1, request_size);
  const mb::byte_view pdu(data + 1 + request_size, size - 1 - request_size);
  const auto format = (data[0] & 0x80U) != 0 ? mo::report_id_format::two_bytes_no_count
                                             : mo::report_id_format::standard;
  const auto r = mo::decode_response_for(request, pdu, format);
  const auto sent = mo::decode_request(request);
  if (sent.is_complete()) {
    const mo::request& s = sent.value();
    const auto fc = s.function;
    const bool read = s.function <= 0x04U || s.function == 0x17U;
    const bool write =
        s.function == 0x05U || s.function == 0x06U || s.function == 0x0FU || s.function == 0x10U;
    if (read || write) {
      const auto one = read ? mo::decode_read_response(fc, s.quantity, pdu)
                            : mo::decode_write_response(
                                  fc, s.address, s.function <= 0x06U ? s.value : s.quantity, pdu);
      MOTIONBUS_FUZZ_CHECK(one.status() == r.status() && one.error() == r.error() &&
                           one.consumed() == r.consumed() && one.expected() == r.expected() &&
                           one.received() == r.received());
      MOTIONBUS_FUZZ_CHECK(one->data.data() == r->data.data() &&
                           one->data.size() == r->data.size() && one->quantity == r->quantity &&
                           one->address == r->address && one->value == r->value &&
                           one->exception == r->exception);
    }
  }
  if (!r.is_complete()) {
    MOTIONBUS_FUZZ_CHECK(r.is_failed() && r.consumed() == pdu.size());
    return 0;
  }
  const mo::response& v = r.value();
  const auto q = mo::decode_request(request);
  MOTIONBUS_FUZZ_CHECK(q.is_complete() && q.value().function == v.function);
  if (v.exception) {
    MOTIONBUS_FUZZ_CHECK(pdu.size() == 2);
    return 0;
  }
  if (!v.data.empty()) {
    MOTIONBUS_FUZZ_CHECK(v.data.data() >= pdu.data() &&
                         v.data.data() + v.data.size() <= pdu.data() + pdu.size());
  }
  const std::uint8_t f = v.function;
  if (f == 0x01 || f == 0x02) {
    MOTIONBUS_FUZZ_CHECK(v.data.size() == (q.value().quantity + 7U) / 8U);
  } else if (f == 0x03 || f == 0x04 || f == 0x17) {
    MOTIONBUS_FUZZ_CHECK(v.data.size() == 2U * q.value().quantity);
  }
  return 0;
}
