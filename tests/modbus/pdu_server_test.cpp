// Modbus server PDUs: the worked examples of the Modbus Application Protocol V1.1b3 §6 decoded
// as requests and answered with the spec's response bytes; the response encoders' refusals.
#include "motionbus/modbus/pdu_server.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/modbus.hpp"
#include "../support/modbus_examples.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

TEST_CASE("server: every spec example request decodes, and its response encodes to the spec") {
  for (const auto& ex : spec_examples()) {
    CAPTURE(ex.name);
    const auto q = decode_request(view(ex.request));
    REQUIRE(q.is_complete());
    CHECK(q.consumed() == ex.request.size());
    std::uint8_t out[32] = {};
    result<std::size_t> n = errc::invalid_argument;
    const std::uint8_t f = q->function;
    if (f == 0x01 || f == 0x02) {
      n = encode_read_bits_response(f, q->quantity,
                                    byte_view(ex.response.data() + 2, ex.response.size() - 2), out);
    } else if (f == 0x03 || f == 0x04 || f == 0x17) {
      std::vector<std::uint16_t> values;
      for (std::size_t i = 2; i + 1 < ex.response.size(); i += 2) {
        values.push_back(static_cast<std::uint16_t>((ex.response[i] << 8) | ex.response[i + 1]));
      }
      CHECK(values.size() == q->quantity);
      n = encode_read_registers_response(f, span<const std::uint16_t>(values.data(), values.size()),
                                         out);
    } else {
      n = encode_write_response(q.value(), out);
    }
    CHECK(output(n, out) == ex.response);
  }
  const auto examples = spec_examples();  // decoded views refer to these bytes: keep them alive
  const auto fc01 = decode_request(view(examples[0].request)).value();
  CHECK(fc01.address == 19);
  CHECK(fc01.quantity == 19);
  const auto fc0f = decode_request(view(examples[6].request)).value();
  CHECK(fc0f.quantity == 10);
  CHECK(bit_at(fc0f.data, 0));
  CHECK(!bit_at(fc0f.data, 1));
  CHECK(bit_at(fc0f.data, 8));
  const auto fc17 = decode_request(view(examples[9].request)).value();
  CHECK(fc17.address == 3);
  CHECK(fc17.quantity == 6);
  CHECK(fc17.write_address == 14);
  CHECK(fc17.write_quantity == 3);
  CHECK(register_at(fc17.data, 2) == 0x00FF);
}

TEST_CASE("server encoders: each bad argument has its own error, and a short buffer is refused") {
  encoder_args a;

  // responses
  CHECK(encode_exception(0x03, 0x02, a.out).value() == 2);
  CHECK(a.out[0] == 0x83);
  CHECK(a.out[1] == 0x02);
  CHECK(encode_exception(0x03, 0x02, mutable_byte_view(a.tiny, 1)).error() ==
        errc::buffer_too_small);
  CHECK(encode_read_bits_response(0x03, 8, a.two_bytes, a.big).error() == errc::invalid_argument);
  CHECK(encode_read_bits_response(0x01, 0, a.two_bytes, a.big).error() == errc::modbus_quantity);
  CHECK(encode_read_bits_response(0x01, 17, a.two_bytes, a.big).error() == errc::modbus_byte_count);
  CHECK(encode_read_bits_response(0x01, 10, a.two_bytes, mutable_byte_view(a.tiny, 2)).error() ==
        errc::buffer_too_small);
  CHECK(encode_read_registers_response(0x01, a.three, a.big).error() == errc::invalid_argument);
  CHECK(encode_read_registers_response(0x03, span<const std::uint16_t>(), a.big).error() ==
        errc::modbus_quantity);
  CHECK(encode_read_registers_response(0x03, a.three, a.small).error() == errc::buffer_too_small);
  request q;
  q.function = 0x03;
  CHECK(encode_write_response(q, a.big).error() == errc::invalid_argument);
  q.function = 0x16;
  CHECK(encode_write_response(q, a.small).error() == errc::buffer_too_small);
  CHECK(encode_exception_status_response(0, mutable_byte_view(a.tiny, 1)).error() ==
        errc::buffer_too_small);
  const std::vector<std::uint8_t> events(65, 0);  // §6.9: at most 64 event bytes
  CHECK(encode_comm_event_log_response(0, 0, 0, byte_view(events.data(), 65), a.big).error() ==
        errc::modbus_byte_count);
  CHECK(encode_comm_event_log_response(0, 0, 0, a.two_bytes, a.small).error() ==
        errc::buffer_too_small);
  CHECK(encode_fifo_response(a.three, a.small).error() == errc::buffer_too_small);
  // FC2B/0E: objects must parse to exactly the count, fit a PDU, fit the buffer
  const bytes one_object = {0x00, 0x02, 'A', 'B'};
  CHECK(encode_device_identification_response(1, 0x81, false, 0, 2, view(one_object), a.big)
            .error() == errc::modbus_byte_count);  // count says 2, one object given
  CHECK(encode_device_identification_response(1, 0x81, false, 0, 0, view(one_object), a.big)
            .error() == errc::modbus_byte_count);  // bytes left over
  const bytes huge_object = [] {
    bytes b = {0x00, 250};
    b.resize(252, 'x');
    return b;
  }();
  CHECK(encode_device_identification_response(1, 0x81, false, 0, 1, view(huge_object), a.big)
            .error() == errc::modbus_pdu_length);
  CHECK(encode_device_identification_response(1, 0x81, false, 0, 1, view(one_object), a.small)
            .error() == errc::buffer_too_small);
}

TEST_CASE("server responses: the bounds of each count, and FC2B's more-follows flag") {
  std::uint8_t out[256] = {};
  const std::uint8_t packed[251] = {};
  CHECK(encode_read_bits_response(0x01, 2000, byte_view(packed, 250), out).ok());
  CHECK(encode_read_bits_response(0x01, 2001, byte_view(packed, 251), out).error() ==
        errc::modbus_quantity);
  CHECK(encode_read_bits_response(0x01, 0, byte_view(), out).error() == errc::modbus_quantity);
  const std::vector<std::uint16_t> values(126, 0);
  CHECK(encode_read_registers_response(0x03, span<const std::uint16_t>(values.data(), 125), out)
            .ok());
  CHECK(encode_read_registers_response(0x03, span<const std::uint16_t>(values.data(), 126), out)
            .error() == errc::modbus_quantity);
  CHECK(encode_read_registers_response(0x03, span<const std::uint16_t>(), out).error() ==
        errc::modbus_quantity);
  const std::uint8_t object[] = {0x00, 0x01, 'A'};
  const auto more =
      encode_device_identification_response(1, 0x01, true, 0x01, 1, byte_view(object, 3), out);
  REQUIRE(more.ok());
  CHECK(out[4] == 0xFF);
  REQUIRE(encode_device_identification_response(1, 0x01, false, 0x00, 1, byte_view(object, 3), out)
              .ok());
  CHECK(out[4] == 0x00);
}

namespace {

// `encode` into a buffer of 0xA5s: it writes `expected` and not a byte past it; into a buffer
// of exactly that size it writes the same; one byte less is buffer_too_small.
void check_encoder(const std::function<result<std::size_t>(mutable_byte_view)>& encode,
                   const bytes& expected) {
  bytes big(300, 0xA5);
  const auto n = encode(mutable_byte_view(big.data(), big.size()));
  REQUIRE(n.ok());
  CHECK(bytes(big.begin(), big.begin() + static_cast<std::ptrdiff_t>(n.value())) == expected);
  CHECK(std::count(big.begin() + static_cast<std::ptrdiff_t>(n.value()), big.end(), 0xA5) ==
        static_cast<std::ptrdiff_t>(big.size() - n.value()));
  bytes exact(expected.size(), 0xA5);
  CHECK(output(encode(mutable_byte_view(exact.data(), exact.size())), exact.data()) == expected);
  bytes short_by_one(expected.size() - 1U, 0xA5);
  CHECK(encode(mutable_byte_view(short_by_one.data(), short_by_one.size())).error() ==
        errc::buffer_too_small);
}

}  // namespace

TEST_CASE("server encoders: their bytes, exact buffers, nothing past the PDU, the largest counts") {
  // each encoder's input is the first bytes of a longer array (0xEE after them): a copy one
  // byte too long would show past the PDU
  check_encoder([](mutable_byte_view out) { return encode_exception_status_response(0x6D, out); },
                {0x07, 0x6D});
  const std::uint8_t events[4] = {0x20, 0x00, 0x40, 0xEE};
  check_encoder(
      [&](mutable_byte_view out) {
        return encode_comm_event_log_response(0x0000, 0x0108, 0x0121, byte_view(events, 3), out);
      },
      {0x0C, 0x09, 0x00, 0x00, 0x01, 0x08, 0x01, 0x21, 0x20, 0x00, 0x40});
  const std::uint16_t fifo[3] = {0x01B8, 0x1284, 0xEEEE};
  check_encoder(
      [&](mutable_byte_view out) {
        return encode_fifo_response(span<const std::uint16_t>(fifo, 2), out);
      },
      {0x18, 0x00, 0x06, 0x00, 0x02, 0x01, 0xB8, 0x12, 0x84});
  const std::uint8_t objects[6] = {0x00, 0x03, 'a', 'b', 'c', 0xEE};
  check_encoder(
      [&](mutable_byte_view out) {
        return encode_device_identification_response(0x01, 0x81, true, 0x02, 1,
                                                     byte_view(objects, 5), out);
      },
      {0x2B, 0x0E, 0x01, 0x81, 0xFF, 0x02, 0x01, 0x00, 0x03, 'a', 'b', 'c'});
  const std::uint8_t regs[5] = {0x0D, 0xFE, 0x00, 0x20, 0xEE};
  const file_record read[] = {{byte_view(regs, 4), 4, 1, 2}, {byte_view(regs, 2), 3, 9, 1}};
  check_encoder([&](mutable_byte_view out) { return encode_read_file_record_response(read, out); },
                {0x14, 0x0A, 0x05, 0x06, 0x0D, 0xFE, 0x00, 0x20, 0x03, 0x06, 0x0D, 0xFE});
  const std::uint8_t write_request[16] = {0x15, 0x0D, 0x06, 0x00, 0x04, 0x00, 0x07, 0x00,
                                          0x03, 0x06, 0xAF, 0x04, 0xBE, 0x10, 0x0D, 0xEE};
  const auto q = decode_file_record_request(byte_view(write_request, 15));
  REQUIRE(q.is_complete());
  check_encoder(
      [&](mutable_byte_view out) { return encode_write_file_record_response(q.value(), out); },
      bytes(write_request, write_request + 15));
  // the largest: 64 events (65 a byte count error), 31 FIFO registers (32 a quantity error),
  // FC2B/0E objects to 253 bytes (one more a PDU length error)
  std::uint8_t out[260] = {};
  const bytes many(65, 0x20);
  CHECK(encode_comm_event_log_response(0, 0, 0, byte_view(many.data(), 64), out).value() == 72U);
  CHECK(encode_comm_event_log_response(0, 0, 0, byte_view(many.data(), 65), out).error() ==
        errc::modbus_byte_count);
  const std::vector<std::uint16_t> queue(32, 0x1234);
  CHECK(encode_fifo_response(span<const std::uint16_t>(queue.data(), 31), out).value() == 67U);
  CHECK(encode_fifo_response(span<const std::uint16_t>(queue.data(), 32), out).error() ==
        errc::modbus_quantity);
  bytes object(246, 'x');
  object[0] = 0x00;
  object[1] = 244;
  CHECK(encode_device_identification_response(1, 1, false, 0, 1, view(object), out).value() ==
        253U);
  object.push_back('x');
  object[1] = 245;
  CHECK(encode_device_identification_response(1, 1, false, 0, 1, view(object), out).error() ==
        errc::modbus_pdu_length);
}
