// Modbus PDU: every refusal of every encoder, and the client decoder on the functions other
// than reads and writes (exception, mismatch, each length rule). Each expectation follows the
// rule quoted next to it (Modbus Application Protocol V1.1b3 §6, §7).
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/pdu_server.hpp"
#include "motionbus/modbus/tcp.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

namespace {

using bytes = std::vector<std::uint8_t>;

byte_view view(const bytes& b) {
  return byte_view(b.data(), b.size());
}

errc decode_error(const bytes& response, const bytes& request) {
  return decode_response(view(response), view(request)).error();
}

}  // namespace

TEST_CASE("encoders: each bad argument has its own error, and a short buffer is refused") {
  std::uint8_t out[260] = {};
  std::uint8_t tiny[3] = {};
  const mutable_byte_view big(out, sizeof out);
  const mutable_byte_view small(tiny, sizeof tiny);
  const std::uint16_t regs[3] = {1, 2, 3};
  const span<const std::uint16_t> three(regs, 3);
  const std::uint8_t packed[2] = {0xFF, 0x03};
  const byte_view two_bytes(packed, 2);

  // FC0F: 1..1968 coils, packed bytes for all of them, no address wrap, room for 6 + n bytes
  CHECK(encode_write_multiple_coils(0, 0, two_bytes, big).error() == errc::modbus_quantity);
  CHECK(encode_write_multiple_coils(0, 17, two_bytes, big).error() == errc::modbus_byte_count);
  CHECK(encode_write_multiple_coils(0xFFFF, 10, two_bytes, big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_write_multiple_coils(0, 10, two_bytes, small).error() == errc::buffer_too_small);
  // FC10: no address wrap, room for 6 + 2n bytes
  CHECK(encode_write_multiple_registers(0xFFFE, three, big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_write_multiple_registers(0, three, small).error() == errc::buffer_too_small);
  // FC16: 7 bytes
  CHECK(encode_mask_write_register(0, 0xFFFF, 0, small).error() == errc::buffer_too_small);
  // FC17: no wrap of either range, room for 10 + 2n bytes
  CHECK(encode_read_write_multiple_registers(0xFFFF, 2, 0, three, big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_read_write_multiple_registers(0, 2, 0xFFFF, three, big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_read_write_multiple_registers(0, 2, 0, three, small).error() ==
        errc::buffer_too_small);
  // raw: function and data copied; room for 1 + n bytes
  const auto raw = encode_raw(0x41, two_bytes, big);
  REQUIRE(raw.ok());
  CHECK(raw.value() == 3);
  CHECK((out[0] == 0x41 && out[1] == 0xFF && out[2] == 0x03));
  CHECK(encode_raw(0x41, two_bytes, mutable_byte_view(tiny, 2)).error() == errc::buffer_too_small);
  // FC08: at most 253 bytes in all; room for 3 + n bytes
  const std::vector<std::uint8_t> long_data(252, 0);
  CHECK(encode_diagnostics(diagnostic::return_query_data, byte_view(long_data.data(), 252), big)
            .error() == errc::modbus_pdu_length);
  CHECK(encode_diagnostics(diagnostic::return_query_data, two_bytes, small).error() ==
        errc::buffer_too_small);
  // FC18 and FC2B/0E requests
  CHECK(encode_read_fifo_queue(0, mutable_byte_view(tiny, 2)).error() == errc::buffer_too_small);
  CHECK(encode_read_device_identification(1, 0, small).error() == errc::buffer_too_small);
  // responses
  CHECK(encode_exception(0x03, 0x02, mutable_byte_view(tiny, 1)).error() == errc::buffer_too_small);
  CHECK(encode_read_bits_response(0x03, 8, two_bytes, big).error() == errc::invalid_argument);
  CHECK(encode_read_bits_response(0x01, 0, two_bytes, big).error() == errc::modbus_quantity);
  CHECK(encode_read_bits_response(0x01, 17, two_bytes, big).error() == errc::modbus_byte_count);
  CHECK(encode_read_bits_response(0x01, 10, two_bytes, mutable_byte_view(tiny, 2)).error() ==
        errc::buffer_too_small);
  CHECK(encode_read_registers_response(0x01, three, big).error() == errc::invalid_argument);
  CHECK(encode_read_registers_response(0x03, span<const std::uint16_t>(), big).error() ==
        errc::modbus_quantity);
  CHECK(encode_read_registers_response(0x03, three, small).error() == errc::buffer_too_small);
  request q;
  q.function = 0x03;
  CHECK(encode_write_response(q, big).error() == errc::invalid_argument);
  q.function = 0x16;
  CHECK(encode_write_response(q, small).error() == errc::buffer_too_small);
  CHECK(encode_exception_status_response(0, mutable_byte_view(tiny, 1)).error() ==
        errc::buffer_too_small);
  const std::vector<std::uint8_t> events(65, 0);  // §6.9: at most 64 event bytes
  CHECK(encode_comm_event_log_response(0, 0, 0, byte_view(events.data(), 65), big).error() ==
        errc::modbus_byte_count);
  CHECK(encode_comm_event_log_response(0, 0, 0, two_bytes, small).error() ==
        errc::buffer_too_small);
  CHECK(encode_fifo_response(three, small).error() == errc::buffer_too_small);
  // FC2B/0E: objects must parse to exactly the count, fit a PDU, fit the buffer
  const bytes one_object = {0x00, 0x02, 'A', 'B'};
  CHECK(
      encode_device_identification_response(1, 0x81, false, 0, 2, view(one_object), big).error() ==
      errc::modbus_byte_count);  // count says 2, one object given
  CHECK(
      encode_device_identification_response(1, 0x81, false, 0, 0, view(one_object), big).error() ==
      errc::modbus_byte_count);  // bytes left over
  const bytes huge_object = [] {
    bytes b = {0x00, 250};
    b.resize(252, 'x');
    return b;
  }();
  CHECK(
      encode_device_identification_response(1, 0x81, false, 0, 1, view(huge_object), big).error() ==
      errc::modbus_pdu_length);
  CHECK(encode_device_identification_response(1, 0x81, false, 0, 1, view(one_object), small)
            .error() == errc::buffer_too_small);
}

TEST_CASE("server: FC2B with another MEI type is passed on; a lone 0x2B is truncated") {
  const bytes other_mei = {0x2B, 0x0D, 0x01, 0x02};
  const auto q = decode_request(view(other_mei));
  REQUIRE(q.is_complete());
  CHECK(q->mei_type == 0x0D);
  CHECK(q->data.size() == 2);
  CHECK(decode_request(view({0x2B})).error() == errc::truncated);
}

TEST_CASE("client: functions other than reads and writes, each length and echo rule") {
  // Exception response and a response to another function, for a non-read/write request.
  const bytes fc07 = {0x07};
  auto r = decode_response(view({0x87, 0x01}), view(fc07));
  REQUIRE(r.is_complete());
  CHECK(r->exception);
  CHECK(r->exception_code == 0x01);
  r = decode_response(view({0x0B, 0x00, 0x00, 0x00, 0x00}), view(fc07));
  CHECK(r.error() == errc::modbus_mismatch);
  CHECK(r.expected() == 0x07);
  CHECK(r.received() == 0x0B);
  // FC07: function and one status byte
  CHECK(decode_error({0x07}, fc07) == errc::truncated);
  CHECK(decode_error({0x07, 0x6D, 0x00}, fc07) == errc::modbus_byte_count);
  // FC16: the request echoed, 7 bytes
  const bytes fc16 = {0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25};
  CHECK(decode_error({0x16, 0x00, 0x04}, fc16) == errc::truncated);
  CHECK(decode_error({0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25, 0x00}, fc16) ==
        errc::modbus_byte_count);
  CHECK(decode_error({0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x26}, fc16) == errc::modbus_mismatch);
  // FC08: sub-function echoed; return query data echoed exactly; others two data bytes
  const bytes echo = {0x08, 0x00, 0x00, 0xA5, 0x37};
  CHECK(decode_error({0x08, 0x00}, echo) == errc::truncated);
  CHECK(decode_error({0x08, 0x00, 0x01, 0xA5, 0x37}, echo) == errc::modbus_mismatch);
  CHECK(decode_error({0x08, 0x00, 0x00, 0xA5}, echo) == errc::modbus_byte_count);
  CHECK(decode_error({0x08, 0x00, 0x00, 0xA5, 0x38}, echo) == errc::modbus_mismatch);
  const bytes counter = {0x08, 0x00, 0x0B, 0x00, 0x00};
  CHECK(decode_error({0x08, 0x00, 0x0B, 0x00}, counter) == errc::modbus_byte_count);
  CHECK(decode_response(view({0x08, 0x00, 0x0B, 0x00, 0x07}), view(counter)).is_complete());
  // FC0B: status and event count, 5 bytes
  const bytes fc0b = {0x0B};
  CHECK(decode_error({0x0B, 0xFF, 0xFF}, fc0b) == errc::truncated);
  CHECK(decode_error({0x0B, 0xFF, 0xFF, 0x01, 0x08, 0x00}, fc0b) == errc::modbus_byte_count);
  // FC0C: byte count = bytes after it, 6..70
  const bytes fc0c = {0x0C};
  CHECK(decode_error({0x0C, 0x06, 0x00, 0x00}, fc0c) == errc::truncated);
  CHECK(decode_error({0x0C, 0x07, 0x00, 0x00, 0x01, 0x08, 0x01, 0x21}, fc0c) ==
        errc::modbus_byte_count);
  // FC18: byte count = 2 + 2 * FIFO count, at most 31 registers
  const bytes fc18 = {0x18, 0x04, 0xDE};
  CHECK(decode_error({0x18, 0x00, 0x06}, fc18) == errc::truncated);
  CHECK(decode_error({0x18, 0x00, 0x42, 0x00, 0x20}, fc18) == errc::modbus_quantity);
  CHECK(decode_error({0x18, 0x00, 0x06, 0x00, 0x02, 0x01, 0xB8}, fc18) == errc::modbus_byte_count);
  // FC2B/0E: 7 bytes of header; MEI type and read code echoed; objects inside the PDU
  const bytes fc2b = {0x2B, 0x0E, 0x01, 0x00};
  CHECK(decode_error({0x2B, 0x0E, 0x01, 0x81}, fc2b) == errc::truncated);
  CHECK(decode_error({0x2B, 0x0E, 0x02, 0x81, 0x00, 0x00, 0x00}, fc2b) == errc::modbus_mismatch);
  CHECK(decode_error({0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 0x01, 0x00, 0x05, 'A'}, fc2b) ==
        errc::modbus_byte_count);
  CHECK(decode_error({0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 0x00, 0x00}, fc2b) ==
        errc::modbus_byte_count);  // a byte after the last object
  // object_at refuses an object running past the data
  response bad;
  const bytes objects = {0x00, 0x09, 'A'};
  bad.function = 0x2B;
  bad.object_count = 1;
  bad.data = view(objects);
  CHECK(object_at(bad, 0).error() == errc::modbus_byte_count);
  // FC11 standard form: byte count, then that many bytes
  CHECK(decode_error({0x11}, {0x11}) == errc::truncated);
  // any other function: the data, raw
  const bytes user = {0x41, 0x01};
  r = decode_response(view({0x41, 0x09, 0x08}), view(user));
  REQUIRE(r.is_complete());
  CHECK(r->data.size() == 2);
}

TEST_CASE("frame size prediction: each length rule, and when it cannot tell yet") {
  // §6: fixed sizes per function; a byte count where the response has one.
  CHECK(predict_request_size(view({0x11})) == 0);  // the function is not in yet
  CHECK(predict_response_size(view({0x11}), 0x03) == 0);
  CHECK(predict_response_size(view({0x11, 0x04}), 0x03) == unknown_length);  // not the one asked
  CHECK(predict_response_size(view({0x11, 0x07}), 0x07) == 5);  // address, FC, status, CRC
  CHECK(predict_response_size(view({0x11, 0x16}), 0x16) == 10);
  CHECK(predict_response_size(view({0x11, 0x18, 0x00}), 0x18) == 0);
  CHECK(predict_response_size(view({0x11, 0x18, 0x00, 0x06}), 0x18) == 12);
  CHECK(predict_response_size(view({0x11, 0x41}), 0x41) == unknown_length);
  // FC2B/0E objects walked as they arrive; a frame past the largest ADU has its size (the
  // framer then rejects it as modbus_pdu_length), at most 255 objects are walked
  bytes walk = {0x11, 0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 0x03};
  for (int k = 0; k < 3; ++k) {
    walk.push_back(0x00);
    walk.push_back(200);
    walk.resize(walk.size() + 200, 'x');
  }
  const std::size_t predicted = predict_response_size(view(walk), 0x2B);
  CHECK(predicted > max_rtu_size);
  CHECK(predicted == walk.size() + 2U);  // the objects, then the CRC
  walk.resize(walk.size() - 1U);         // the last object is not all there: its end is known
  CHECK(predict_response_size(view(walk), 0x2B) == walk.size() + 1U);
  walk.resize(8U + 202U + 1U);  // the second object's header is cut: wait for it
  CHECK(predict_response_size(view(walk), 0x2B) == 0);
}

TEST_CASE("framer framing by silence: a full buffer with no frame end resynchronises") {
  // frame_end::silence: a function without a length rule waits for idle(), but never
  // beyond the largest ADU: then the oldest byte is dropped and the scan goes on.
  rtu_framer f({framer_role::server, 0x11});
  bytes noise = {0x11, 0x41};
  noise.resize(max_rtu_size + 10, 0x55);
  std::size_t used = 0;
  bool completed = false;
  while (used < noise.size()) {
    const auto r = f.feed(byte_view(noise.data() + used, noise.size() - used));
    completed = completed || r.is_complete();
    used += r.consumed() == 0 ? noise.size() - used : r.consumed();
  }
  CHECK(!completed);
  CHECK(f.dropped() > 0);
  CHECK(f.pending() <= max_rtu_size);
}

TEST_CASE("MBAP header: a buffer shorter than header and PDU is refused") {
  std::uint8_t out[8] = {};
  const bytes pdu = {0x03, 0x00, 0x00, 0x00, 0x01};
  CHECK(encode_tcp(1, 1, view(pdu), mutable_byte_view(out, sizeof out)).error() ==
        errc::buffer_too_small);
}
