// Modbus client PDUs: requests encoded to the worked examples of the Modbus Application
// Protocol V1.1b3 §6, responses decoded and checked against their request.
#include "motionbus/modbus/pdu_client.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/modbus.hpp"
#include "../support/modbus_examples.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

TEST_CASE("client: requests encode to the spec's example bytes") {
  std::uint8_t out[32] = {};
  CHECK(output(encode_read(function_code::read_coils, 19, 19, out), out) ==
        spec_examples()[0].request);
  CHECK(output(encode_read(function_code::read_discrete_inputs, 196, 22, out), out) ==
        spec_examples()[1].request);
  CHECK(output(encode_read(function_code::read_holding_registers, 107, 3, out), out) ==
        spec_examples()[2].request);
  CHECK(output(encode_read(function_code::read_input_registers, 8, 1, out), out) ==
        spec_examples()[3].request);
  CHECK(output(encode_write_single_coil(172, true, out), out) == spec_examples()[4].request);
  CHECK(output(encode_write_single_register(1, 3, out), out) == spec_examples()[5].request);
  const std::uint8_t coils[] = {0xCD, 0x01};
  CHECK(output(encode_write_multiple_coils(19, 10, coils, out), out) == spec_examples()[6].request);
  const std::uint16_t regs[] = {0x000A, 0x0102};
  CHECK(output(encode_write_multiple_registers(1, regs, out), out) == spec_examples()[7].request);
  CHECK(output(encode_mask_write_register(4, 0x00F2, 0x0025, out), out) ==
        spec_examples()[8].request);
  const std::uint16_t w[] = {0x00FF, 0x00FF, 0x00FF};
  CHECK(output(encode_read_write_multiple_registers(3, 6, 14, w, out), out) ==
        spec_examples()[9].request);
  const std::uint8_t none[1] = {};
  CHECK(output(encode_raw(0x11, byte_view(none, 0), out), out) == bytes{0x11});
}

TEST_CASE("client: every spec example response decodes against its request") {
  for (const auto& ex : spec_examples()) {
    CAPTURE(ex.name);
    const auto r = decode_response_for(view(ex.request), view(ex.response));
    REQUIRE(r.is_complete());
    CHECK(!r->exception);
    CHECK(r->function == ex.request[0]);
  }
  const auto examples = spec_examples();  // decoded views refer to these bytes: keep them alive
  const auto fc03 = decode_response_for(view(examples[2].request), view(examples[2].response));
  CHECK(register_at(fc03->data, 0) == 0x022B);
  CHECK(register_at(fc03->data, 2) == 0x0064);
  const auto fc01 = decode_response_for(view(examples[0].request), view(examples[0].response));
  CHECK(fc01->data.size() == 3);
  CHECK(bit_at(fc01->data, 0));   // coil 20 on (0xCD bit 0)
  CHECK(!bit_at(fc01->data, 1));  // coil 21 off
}

TEST_CASE("client: exceptions pass through, mismatches and counts are errors") {
  const bytes req = spec_examples()[2].request;  // FC03 read 3 registers
  auto r = decode_response_for(view(req), view({0x83, 0x02}));
  REQUIRE(r.is_complete());
  CHECK(r->exception);
  CHECK(r->exception_code == 0x02);
  r = decode_response_for(view(req), view({0x83, 0x42}));  // unknown code: unchanged
  CHECK(r->exception_code == 0x42);
  CHECK(decode_response_for(view(req), view({0x83})).error() == errc::truncated);
  CHECK(decode_response_for(view(req), view({0x84, 0x02})).error() == errc::modbus_mismatch);
  CHECK(decode_response_for(view(req), view({0x04, 0x06, 0, 0, 0, 0, 0, 0})).error() ==
        errc::modbus_mismatch);
  CHECK(decode_response_for(view(req), view({0x03, 0x04, 0, 0, 0, 0})).error() ==
        errc::modbus_byte_count);
  CHECK(decode_response_for(view(req), view({0x03, 0x06, 0, 0, 0, 0})).error() == errc::truncated);
  CHECK(decode_response_for(view(req), view({0x03, 0x06, 0, 0, 0, 0, 0, 0, 0})).error() ==
        errc::modbus_byte_count);
  // FC01 for 19 coils: 3 bytes, the top 5 bits of the last must be 0
  const bytes fc01 = spec_examples()[0].request;
  CHECK(decode_response_for(view(fc01), view({0x01, 0x03, 0xCD, 0x6B, 0x0D})).error() ==
        errc::reserved_bits);
  // echoes
  const bytes fc06 = spec_examples()[5].request;
  CHECK(decode_response_for(view(fc06), view({0x06, 0x00, 0x01, 0x00, 0x04})).error() ==
        errc::modbus_mismatch);
  const bytes fc10 = spec_examples()[7].request;
  CHECK(decode_response_for(view(fc10), view({0x10, 0x00, 0x01, 0x00, 0x03})).error() ==
        errc::modbus_mismatch);
  // FC11: standard (byte count) and the SM unit's two bytes without a count
  const bytes fc11 = {0x11};
  const bytes standard = {0x11, 0x03, 0xAA, 0xBB, 0xFF};
  r = decode_response_for(view(fc11), view(standard));
  REQUIRE(r.is_complete());
  CHECK(r->data.size() == 3);
  CHECK(decode_response_for(view(fc11), view({0x11, 0x05, 0xAA})).error() ==
        errc::modbus_byte_count);
  const bytes sm_unit = {0x11, 0x01, 0x00};  // Ver.1.0.0
  r = decode_response_for(view(fc11), view(sm_unit), report_id_format::two_bytes_no_count);
  REQUIRE(r.is_complete());
  CHECK(r->data[0] == 0x01);
  CHECK(r->data[1] == 0x00);
  CHECK(decode_response_for(view(fc11), view({0x11, 0x01}), report_id_format::two_bytes_no_count)
            .error() == errc::truncated);
  // an invalid request cannot be matched
  CHECK(decode_response_for(view({0x03, 0x00}), view({0x03, 0x02, 0, 0})).error() ==
        errc::invalid_argument);
}

TEST_CASE("client, one function: read and write decoders agree with decode_response") {
  // decode_read_response / decode_write_response take what the client asked as values (no
  // request bytes to decode); on every spec example, and on each damaged form of it, they
  // must give what decode_response gives from the request bytes.
  int compared = 0;
  for (const auto& ex : spec_examples()) {
    const auto sent = decode_request(view(ex.request));
    REQUIRE(sent.is_complete());
    const request& q = sent.value();
    const std::uint8_t f = q.function;
    const bool read = f <= 0x04U || f == 0x17U;
    const bool write = f == 0x05U || f == 0x06U || f == 0x0FU || f == 0x10U;
    if (!read && !write) {
      continue;
    }
    std::vector<bytes> answers = {ex.response,
                                  {static_cast<std::uint8_t>(f | 0x80U), 0x04},
                                  {static_cast<std::uint8_t>(f | 0x80U)},
                                  {}};
    for (std::size_t cut = 1; cut < ex.response.size(); ++cut) {
      answers.emplace_back(ex.response.begin(), ex.response.begin() + static_cast<long>(cut));
    }
    for (std::size_t at = 0; at < ex.response.size(); ++at) {
      for (unsigned bit = 0; bit < 8U; ++bit) {
        bytes flipped = ex.response;
        flipped[at] = static_cast<std::uint8_t>(flipped[at] ^ (1U << bit));
        answers.push_back(flipped);
      }
    }
    bytes longer = ex.response;
    longer.push_back(0);
    answers.push_back(longer);
    for (const bytes& a : answers) {
      CAPTURE(ex.name);
      CAPTURE(a.size());
      const auto generic = decode_response_for(view(ex.request), view(a));
      const auto one =
          read ? decode_read_response(f, q.quantity, view(a))
               : decode_write_response(f, q.address, f <= 0x06U ? q.value : q.quantity, view(a));
      REQUIRE(one.status() == generic.status());
      CHECK(one.error() == generic.error());
      CHECK(one.consumed() == generic.consumed());
      CHECK(one.expected() == generic.expected());
      CHECK(one.received() == generic.received());
      CHECK(one->exception == generic->exception);
      CHECK(one->exception_code == generic->exception_code);
      CHECK(one->address == generic->address);
      CHECK(one->quantity == generic->quantity);
      CHECK(one->value == generic->value);
      CHECK(one->data.size() == generic->data.size());
      ++compared;
    }
  }
  CHECK(compared > 500);
  // The values themselves, and what only these decoders can be asked.
  const bytes fc03 = spec_examples()[2].response;
  const auto r = decode_read_response(function_code::read_holding_registers, 3, view(fc03));
  REQUIRE(r.is_complete());
  CHECK(register_at(r->data, 1) == 0x0000);
  CHECK(register_at(r->data, 2) == 0x0064);
  // asked for 4 registers, the byte count says 3
  CHECK(decode_read_response(function_code::read_holding_registers, 4, view(fc03)).error() ==
        errc::modbus_byte_count);
  CHECK(decode_read_response(function_code::write_single_register, 3, view(fc03)).error() ==
        errc::invalid_argument);
  const auto other = decode_read_response(function_code::read_input_registers, 3, view(fc03));
  CHECK(other.error() == errc::modbus_mismatch);
  CHECK(other.expected() == 0x04);
  CHECK(other.received() == 0x03);
  CHECK(decode_write_response(function_code::read_coils, 1, 2, view({0x10, 0x00, 0x01, 0x00, 0x02}))
            .error() == errc::invalid_argument);
  const auto w = decode_write_response(function_code::write_multiple_registers, 1, 2,
                                       view({0x10, 0x00, 0x01, 0x00, 0x02}));
  REQUIRE(w.is_complete());
  CHECK(w->address == 1);
  CHECK(w->quantity == 2);
  const auto echo = decode_write_response(function_code::write_single_register, 1, 4,
                                          view({0x06, 0x00, 0x01, 0x00, 0x03}));
  CHECK(echo.error() == errc::modbus_mismatch);
  CHECK(echo.expected() == 0);  // an echo mismatch has no function evidence
}

TEST_CASE("client encoders refuse what a server would refuse") {
  std::uint8_t out[300] = {};
  CHECK(encode_read(function_code::read_coils, 0, 0, out).error() == errc::modbus_quantity);
  CHECK(encode_read(function_code::read_holding_registers, 0, 126, out).error() ==
        errc::modbus_quantity);
  CHECK(encode_read(function_code::read_holding_registers, 0xFFFF, 2, out).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_read(function_code::write_single_coil, 0, 1, out).error() == errc::invalid_argument);
  CHECK(encode_read(function_code::read_coils, 0, 1, mutable_byte_view(out, 4)).error() ==
        errc::buffer_too_small);
  const std::uint8_t one[] = {0xFF};
  CHECK(encode_write_multiple_coils(0, 9, one, out).error() == errc::modbus_byte_count);
  REQUIRE(encode_write_multiple_coils(0, 3, one, out).value() == 7);
  CHECK(out[6] == 0x07);  // unused high bits cleared
  std::uint16_t many[124] = {};
  CHECK(encode_write_multiple_registers(0, span<const std::uint16_t>(many, 124), out).error() ==
        errc::modbus_quantity);
  CHECK(encode_write_multiple_registers(0, span<const std::uint16_t>(many, 0), out).error() ==
        errc::modbus_quantity);
  CHECK(encode_read_write_multiple_registers(0, 1, 0, span<const std::uint16_t>(many, 122), out)
            .error() == errc::modbus_quantity);
  std::uint8_t big[253] = {};
  CHECK(encode_raw(0x41, byte_view(big, 253), out).error() == errc::modbus_pdu_length);
  CHECK(encode_raw(0x81, byte_view(big, 1), out).error() == errc::invalid_argument);
}

TEST_CASE("client: a response without its request, every check it carries itself") {
  auto ok = [](const bytes& pdu, report_id_format fc11 = report_id_format::standard) {
    const auto r = decode_response_unpaired(view(pdu), fc11);
    REQUIRE(r.is_complete());
    CHECK(r.consumed() == pdu.size());
    return r.value();
  };
  auto error = [](const bytes& pdu, report_id_format fc11 = report_id_format::standard) {
    const auto r = decode_response_unpaired(view(pdu), fc11);
    REQUIRE(r.is_failed());
    return r.error();
  };
  // reads: the byte count against the bytes present; registers in pairs
  auto r = ok({0x03, 0x04, 0x00, 0x01, 0x00, 0x02});
  CHECK(r.quantity == 2);
  CHECK(r.byte_count == 4);
  CHECK(ok({0x01, 0x01, 0x05}).quantity == 8);
  CHECK(error({0x03, 0x05, 0x00, 0x01, 0x00, 0x02}) == errc::modbus_byte_count);
  CHECK(error({0x04, 0x03, 0x00, 0x01, 0x00}) == errc::modbus_byte_count);
  CHECK(error({0x03}) == errc::truncated);
  // writes: five bytes, the echo as it came
  r = ok({0x06, 0x00, 0x24, 0x03, 0x20});
  CHECK(r.address == 0x24);
  CHECK(r.value == 0x320);
  CHECK(ok({0x10, 0x00, 0x01, 0x00, 0x02}).quantity == 2);
  CHECK(error({0x05, 0x00, 0x01, 0xFF}) == errc::truncated);
  CHECK(error({0x0F, 0x00, 0x01, 0x00, 0x02, 0x00}) == errc::modbus_byte_count);
  CHECK(ok({0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25}).or_mask == 0x25);
  CHECK(ok({0x07, 0x6D}).status == 0x6D);
  CHECK(ok({0x0B, 0xFF, 0xFF, 0x01, 0x08}).event_count == 0x108);
  // FC08: sub-function 00 echoes an even number of bytes; the others carry two
  CHECK(ok({0x08, 0x00, 0x00, 0xA5, 0x37, 0x12, 0x34}).data.size() == 4);
  CHECK(error({0x08, 0x00, 0x00, 0xA5, 0x37, 0x12}) == errc::modbus_byte_count);
  CHECK(ok({0x08, 0x00, 0x0B, 0x00, 0x07}).sub_function == 0x0B);
  CHECK(error({0x08, 0x00, 0x0B, 0x00}) == errc::modbus_byte_count);
  // FC11: the standard layout's count; the SM unit's two bytes
  CHECK(error({0x11, 0xFA, 0xB4, 0xFF}) == errc::modbus_byte_count);
  CHECK(ok({0x11, 0x02, 0x01, 0xFF}).data.size() == 2);
  CHECK(ok({0x11, 0x02, 0x03}, report_id_format::two_bytes_no_count).data.size() == 2);
  CHECK(error({0x11, 0x02, 0x03, 0x04}, report_id_format::two_bytes_no_count) ==
        errc::modbus_byte_count);
  // FC18, FC0C, FC2B/0E: counts and objects inside the PDU
  CHECK(ok({0x18, 0x00, 0x06, 0x00, 0x02, 0x01, 0xB8, 0x12, 0x84}).fifo_count == 2);
  CHECK(error({0x18, 0x00, 0x08, 0x00, 0x02, 0x01, 0xB8, 0x12, 0x84}) == errc::modbus_byte_count);
  CHECK(ok({0x0C, 0x08, 0x00, 0x00, 0x01, 0x08, 0x01, 0x21, 0x20, 0x00}).message_count == 0x121);
  CHECK(ok({0x2B, 0x0E, 0x01, 0x01, 0x00, 0x00, 0x01, 0x00, 0x02, 'A', 'm'}).object_count == 1);
  CHECK(error({0x2B, 0x0E, 0x01, 0x01, 0x00, 0x00, 0x01, 0x00, 0x09, 'A', 'm'}) ==
        errc::modbus_byte_count);
  // exceptions, an empty PDU, a function without a layout (raw data)
  r = ok({0x83, 0x02});
  CHECK(r.exception);
  CHECK(r.function == 0x03);
  CHECK(r.exception_code == 0x02);
  CHECK(error({0x83, 0x02, 0x00}) == errc::modbus_byte_count);
  CHECK(error({}) == errc::modbus_pdu_length);
  CHECK(ok({0x41, 0x01, 0x02}).data.size() == 2);
}

namespace {

errc decode_error(const bytes& response, const bytes& request) {
  return decode_response_for(view(request), view(response)).error();
}

}  // namespace

TEST_CASE("client encoders: each bad argument has its own error, and a short buffer is refused") {
  encoder_args a;

  // FC0F: 1..1968 coils, a.packed bytes for all of them, no address wrap, room for 6 + n bytes
  CHECK(encode_write_multiple_coils(0, 0, a.two_bytes, a.big).error() == errc::modbus_quantity);
  CHECK(encode_write_multiple_coils(0, 17, a.two_bytes, a.big).error() == errc::modbus_byte_count);
  CHECK(encode_write_multiple_coils(0xFFFF, 10, a.two_bytes, a.big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_write_multiple_coils(0, 10, a.two_bytes, a.small).error() == errc::buffer_too_small);
  // FC10: no address wrap, room for 6 + 2n bytes
  CHECK(encode_write_multiple_registers(0xFFFE, a.three, a.big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_write_multiple_registers(0, a.three, a.small).error() == errc::buffer_too_small);
  // FC16: 7 bytes
  CHECK(encode_mask_write_register(0, 0xFFFF, 0, a.small).error() == errc::buffer_too_small);
  // FC17: no wrap of either range, room for 10 + 2n bytes
  CHECK(encode_read_write_multiple_registers(0xFFFF, 2, 0, a.three, a.big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_read_write_multiple_registers(0, 2, 0xFFFF, a.three, a.big).error() ==
        errc::modbus_address_overflow);
  CHECK(encode_read_write_multiple_registers(0, 2, 0, a.three, a.small).error() ==
        errc::buffer_too_small);
  // raw: function and data copied; room for 1 + n bytes
  const auto raw = encode_raw(0x41, a.two_bytes, a.big);
  REQUIRE(raw.ok());
  CHECK(raw.value() == 3);
  CHECK((a.out[0] == 0x41 && a.out[1] == 0xFF && a.out[2] == 0x03));
  // (a view of known size: with a.two_bytes, g++ -O3 warns of a write past `tiny` that the
  // size check above the copy rules out)
  CHECK(encode_raw(0x41, byte_view(a.packed, 2), mutable_byte_view(a.tiny, 2)).error() ==
        errc::buffer_too_small);
  // FC08: at most 253 bytes in all; room for 3 + n bytes
  const std::vector<std::uint8_t> long_data(252, 0);
  CHECK(encode_diagnostics(diagnostic::return_query_data, byte_view(long_data.data(), 252), a.big)
            .error() == errc::modbus_pdu_length);
  CHECK(encode_diagnostics(diagnostic::return_query_data, a.two_bytes, a.small).error() ==
        errc::buffer_too_small);
  // FC18 and FC2B/0E requests
  CHECK(encode_read_fifo_queue(0, mutable_byte_view(a.tiny, 2)).error() == errc::buffer_too_small);
  CHECK(encode_read_device_identification(1, 0, a.small).error() == errc::buffer_too_small);
}

TEST_CASE("client: functions other than reads and writes, each length and echo rule") {
  // Exception response and a response to another function, for a non-read/write request.
  const bytes fc07 = {0x07};
  auto r = decode_response_for(view(fc07), view({0x87, 0x01}));
  REQUIRE(r.is_complete());
  CHECK(r->exception);
  CHECK(r->exception_code == 0x01);
  r = decode_response_for(view(fc07), view({0x0B, 0x00, 0x00, 0x00, 0x00}));
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
  CHECK(decode_response_for(view(counter), view({0x08, 0x00, 0x0B, 0x00, 0x07})).is_complete());
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
  // ...and an index past the last object of such data: the bad data is told, not the index
  CHECK(object_at(bad, 1).error() == errc::modbus_byte_count);
  const bytes one = {0x00, 0x01, 'A'};
  bad.data = view(one);
  CHECK(object_at(bad, 1).error() == errc::out_of_range);
  // FC11 standard form: byte count, then that many bytes
  CHECK(decode_error({0x11}, {0x11}) == errc::truncated);
  // any other function: the data, raw
  const bytes user = {0x41, 0x01};
  r = decode_response_for(view(user), view({0x41, 0x09, 0x08}));
  REQUIRE(r.is_complete());
  CHECK(r->data.size() == 2);
}

TEST_CASE("client encoders: each bound of each argument alone, at run time") {
  std::uint8_t out[256] = {};
  const std::uint8_t packed[250] = {};
  // FC0F: 1..1968 coils
  CHECK(encode_write_multiple_coils(0, 1968, byte_view(packed, 246), out).ok());
  CHECK(encode_write_multiple_coils(0, 1969, byte_view(packed, 247), out).error() ==
        errc::modbus_quantity);
  CHECK(encode_write_multiple_coils(0, 0, byte_view(packed, 0), out).error() ==
        errc::modbus_quantity);
  // FC17: read 1..125, write 1..121
  const std::vector<std::uint16_t> values(122, 0);
  const span<const std::uint16_t> one(values.data(), 1);
  CHECK(encode_read_write_multiple_registers(0, 125, 0, one, out).ok());
  CHECK(encode_read_write_multiple_registers(0, 0, 0, one, out).error() == errc::modbus_quantity);
  CHECK(encode_read_write_multiple_registers(0, 126, 0, one, out).error() == errc::modbus_quantity);
  CHECK(encode_read_write_multiple_registers(0, 1, 0, span<const std::uint16_t>(), out).error() ==
        errc::modbus_quantity);
  CHECK(encode_read_write_multiple_registers(0, 1, 0, span<const std::uint16_t>(values.data(), 121),
                                             out)
            .ok());
  CHECK(encode_read_write_multiple_registers(0, 1, 0, span<const std::uint16_t>(values.data(), 122),
                                             out)
            .error() == errc::modbus_quantity);
  // a raw request: function 0 and exception responses are no requests
  CHECK(encode_raw(0x41, byte_view(), out).ok());
  CHECK(encode_raw(0x00, byte_view(), out).error() == errc::invalid_argument);
  CHECK(encode_raw(0xC1, byte_view(), out).error() == errc::invalid_argument);
  // FC2B/0E: read device ID codes 1..4
  CHECK(encode_read_device_identification(4, 0, out).ok());
  CHECK(encode_read_device_identification(0, 0, out).error() == errc::modbus_quantity);
  CHECK(encode_read_device_identification(5, 0, out).error() == errc::modbus_quantity);
}

TEST_CASE("client decoders: the remaining checks, each alone") {
  // a bit read of a whole number of bytes has no spare bits to check
  const auto eight = decode_read_response(0x01, 8, view({0x01, 0x01, 0xFF}));
  REQUIRE(eight.is_complete());
  CHECK(eight->quantity == 8);
  CHECK(decode_read_response(0x01, 7, view({0x01, 0x01, 0xFF})).error() == errc::reserved_bits);
  // unpaired: FC04, FC17 and FC05 responses as they come
  CHECK(decode_response_unpaired(view({0x04, 0x02, 0x00, 0x07})).value().quantity == 1);
  CHECK(decode_response_unpaired(view({0x17, 0x02, 0x00, 0x07})).value().quantity == 1);
  const auto coil = decode_response_unpaired(view({0x05, 0x00, 0xAC, 0xFF, 0x00}));
  REQUIRE(coil.is_complete());
  CHECK(coil->address == 0xAC);
  CHECK(coil->value == 0xFF00);
  // FC16: the echo checked field by field against the request
  std::uint8_t req[8] = {};
  const std::size_t n = encode_mask_write_register(0x0004, 0x00F2, 0x0025, req).value();
  const byte_view sent(req, n);
  CHECK(decode_response_for(sent, view({0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25})).is_complete());
  CHECK(decode_response_for(sent, view({0x16, 0x00, 0x05, 0x00, 0xF2, 0x00, 0x25})).error() ==
        errc::modbus_mismatch);
  CHECK(decode_response_for(sent, view({0x16, 0x00, 0x04, 0x00, 0xF3, 0x00, 0x25})).error() ==
        errc::modbus_mismatch);
  CHECK(decode_response_for(sent, view({0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x26})).error() ==
        errc::modbus_mismatch);
  // FC0C: a byte count above 6 + 64 bytes of events, though it matches the bytes present
  bytes log(73, 0);
  log[0] = 0x0C;
  log[1] = 71;
  CHECK(decode_response_unpaired(view(log)).error() == errc::modbus_byte_count);
  // FC2B: another MEI type, unpaired, is raw data; another MEI type's response to an 0E
  // request is a mismatch
  const auto other = decode_response_unpaired(view({0x2B, 0x0D, 0x01, 0x02}));
  REQUIRE(other.is_complete());
  CHECK(other->function == 0x2B);
  const auto bare = decode_response_unpaired(view({0x2B}));  // no MEI type: raw too
  REQUIRE(bare.is_complete());
  CHECK(bare->function == 0x2B);
  CHECK(bare->data.empty());
  std::uint8_t id_req[8] = {};
  const std::size_t m = encode_read_device_identification(1, 0, id_req).value();
  const bytes id_ok = {0x2B, 0x0E, 0x01, 0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 'A'};
  CHECK(decode_response_for(byte_view(id_req, m), view(id_ok)).is_complete());
  bytes id_other = id_ok;
  id_other[1] = 0x0D;
  CHECK(decode_response_for(byte_view(id_req, m), view(id_other)).error() == errc::modbus_mismatch);
  // the request's MEI type decides: to another MEI type's request the response is raw data
  const bytes mei_0d = {0x2B, 0x0D, 0x01};
  const auto raw = decode_response_for(view(mei_0d), view(id_ok));
  REQUIRE(raw.is_complete());
  CHECK(raw->object_count == 0);
  CHECK(raw->data.size() == id_ok.size() - 1U);
}

TEST_CASE("encode_write_file_record writes the request and not a byte past it") {
  // the record's data a view of the first four bytes of six: the two behind it are not its own
  const std::uint8_t memory[6] = {0x06, 0xAF, 0x04, 0xBE, 0x5A, 0x5A};
  const file_record rec{byte_view(memory, 4), 4, 7, 2};
  std::uint8_t out[32];
  for (std::uint8_t& b : out) {
    b = 0xEE;
  }
  const auto n = encode_write_file_record(span<const file_record>(&rec, 1), out);
  REQUIRE(n.ok());
  REQUIRE(n.value() == 13U);  // 15, byte count 11, one sub-request of 7 + 4 bytes
  CHECK(bytes(out, out + 13) ==
        bytes{0x15, 0x0B, 0x06, 0x00, 0x04, 0x00, 0x07, 0x00, 0x02, 0x06, 0xAF, 0x04, 0xBE});
  for (std::size_t i = 13; i < sizeof out; ++i) {
    CAPTURE(i);
    CHECK(out[i] == 0xEE);
  }
}

TEST_CASE("client encoders at their limits: the largest PDUs, quantity 1, the bytes written") {
  std::uint8_t out[260] = {};
  // FC0F with one coil, FC10 with 123 registers (§6.11, §6.12: the largest quantities)
  const std::uint8_t one_coil[1] = {0x01};
  CHECK(output(encode_write_multiple_coils(7, 1, byte_view(one_coil, 1), out), out) ==
        bytes{0x0F, 0x00, 0x07, 0x00, 0x01, 0x01, 0x01});
  std::uint16_t regs[123] = {};
  for (std::size_t i = 0; i < 123; ++i) {
    regs[i] = static_cast<std::uint16_t>(0x0100U + i);
  }
  const auto fc10 = encode_write_multiple_registers(0, span<const std::uint16_t>(regs, 123), out);
  REQUIRE(fc10.ok());
  CHECK(fc10.value() == 6U + 246U);
  CHECK(out[5] == 246);
  CHECK(out[250] == 0x01);
  CHECK(out[251] == 0x7A);
  CHECK(encode_write_multiple_registers(0, span<const std::uint16_t>(regs, 124 - 1), out).ok());
  // a raw PDU and an FC08 PDU of 253 bytes, the largest (§4.1), and one byte more
  std::uint8_t data[253] = {};
  for (std::size_t i = 0; i < sizeof data; ++i) {
    data[i] = static_cast<std::uint8_t>(i);
  }
  CHECK(encode_raw(0x41, byte_view(data, 252), out).value() == 253U);
  CHECK(out[252] == 251);
  CHECK(encode_raw(0x41, byte_view(data, 253), out).error() == errc::modbus_pdu_length);
  CHECK(encode_diagnostics(diagnostic::return_query_data, byte_view(data, 250), out).value() ==
        253U);
  CHECK(out[252] == 249);
  CHECK(encode_diagnostics(diagnostic::return_query_data, byte_view(data, 252), out).error() ==
        errc::modbus_pdu_length);
  // the bytes of FC08, FC18 and FC2B requests, each into a buffer of exactly its size, and
  // nothing written past it (the data are the first bytes of a longer array)
  std::uint8_t exact[7] = {};
  const std::uint8_t query[6] = {0x12, 0x34, 0x56, 0x78, 0xEE, 0xEE};
  std::fill(std::begin(exact), std::end(exact), std::uint8_t{0xA5});
  CHECK(output(encode_diagnostics(diagnostic::return_query_data, byte_view(query, 4),
                                  mutable_byte_view(exact, 7)),
               exact) == bytes{0x08, 0x00, 0x00, 0x12, 0x34, 0x56, 0x78});
  std::uint8_t room[9] = {0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5};
  CHECK(output(encode_diagnostics(diagnostic::clear_counters, byte_view(query, 2),
                                  mutable_byte_view(room, 9)),
               room) == bytes{0x08, 0x00, 0x0A, 0x12, 0x34});
  CHECK(bytes(room + 5, room + 9) == bytes{0xA5, 0xA5, 0xA5, 0xA5});
  CHECK(encode_diagnostics(diagnostic::return_query_data, byte_view(query, 4),
                           mutable_byte_view(exact, 6))
            .error() == errc::buffer_too_small);
  CHECK(output(encode_raw(0x41, byte_view(query, 2), mutable_byte_view(exact, 3)), exact) ==
        bytes{0x41, 0x12, 0x34});
  CHECK(encode_raw(0x41, byte_view(query, 2), mutable_byte_view(exact, 2)).error() ==
        errc::buffer_too_small);
  CHECK(output(encode_read_fifo_queue(0x04DE, mutable_byte_view(exact, 3)), exact) ==
        bytes{0x18, 0x04, 0xDE});
  CHECK(encode_read_fifo_queue(0x04DE, mutable_byte_view(exact, 2)).error() ==
        errc::buffer_too_small);
  CHECK(output(encode_read_device_identification(4, 0x05, mutable_byte_view(exact, 4)), exact) ==
        bytes{0x2B, 0x0E, 0x04, 0x05});
  CHECK(encode_read_device_identification(4, 0x05, mutable_byte_view(exact, 3)).error() ==
        errc::buffer_too_small);
  // a device object made by hand starts from id 0 and no value
  CHECK(device_object{}.id == 0);
  CHECK(device_object{}.value.empty());
}

TEST_CASE("client decoders: the edges of read, write, FC08 and FC0C responses") {
  // decode_read_response: a byte count other than the one asked, in a PDU of two bytes, is a
  // byte count error (not truncated); a read of quantity 0, which no encoder sends, decodes an
  // empty answer without reading outside it
  CHECK(decode_read_response(0x03, 1, view({0x03, 0x04})).error() == errc::modbus_byte_count);
  CHECK(decode_read_response(0x03, 2, view({0x03, 0x04})).error() == errc::truncated);
  const auto empty_bits = decode_read_response(0x01, 0, view({0x01, 0x00}));
  REQUIRE(empty_bits.is_complete());
  CHECK(empty_bits->data.empty());
  // decode_write_response: fewer than 5 bytes truncated, more a byte count error
  CHECK(decode_write_response(0x06, 1, 3, view({0x06, 0x00, 0x01, 0x00})).error() ==
        errc::truncated);
  CHECK(decode_write_response(0x06, 1, 3, view({0x06, 0x00, 0x01, 0x00, 0x03, 0x00})).error() ==
        errc::modbus_byte_count);
  // unpaired reads: the data are the bytes after the count; a count of 0 is an empty read
  const bytes regs_pdu = {0x03, 0x04, 0x12, 0x34, 0x56, 0x78};  // the data are views into it
  const auto regs = decode_response_unpaired(view(regs_pdu));
  REQUIRE(regs.is_complete());
  CHECK(bytes(regs->data.begin(), regs->data.end()) == bytes{0x12, 0x34, 0x56, 0x78});
  CHECK(regs->quantity == 2);
  const auto none = decode_response_unpaired(view({0x03, 0x00}));
  REQUIRE(none.is_complete());
  CHECK(none->data.empty());
  CHECK(none->quantity == 0);
  // FC08: Return Query Data with no data echoed is three bytes, complete
  const bytes q0 = {0x08, 0x00, 0x00};
  CHECK(decode_response_for(view(q0), view(q0)).is_complete());
  CHECK(decode_response_unpaired(view(q0)).is_complete());
  // the echo must be exact from its first byte to its last, and no further: the request's and
  // the response's data are followed by different bytes in their arrays
  const std::uint8_t sent[6] = {0x08, 0x00, 0x00, 0xA1, 0xB2, 0x11};
  const std::uint8_t echo[6] = {0x08, 0x00, 0x00, 0xA1, 0xB2, 0x22};
  const std::uint8_t first_wrong[5] = {0x08, 0x00, 0x00, 0xA0, 0xB2};
  CHECK(decode_response_for(byte_view(sent, 5), byte_view(echo, 5)).is_complete());
  CHECK(decode_response_for(byte_view(sent, 5), byte_view(first_wrong, 5)).error() ==
        errc::modbus_mismatch);
  // FC0C (§6.10): status, event count, message count and up to 64 events; byte count 70 is
  // the largest
  bytes log = {0x0C, 70, 0x12, 0x34, 0x01, 0x08, 0x01, 0x21};
  for (unsigned i = 0; i < 64U; ++i) {
    log.push_back(static_cast<std::uint8_t>(i));
  }
  const auto full = decode_response_unpaired(view(log));
  REQUIRE(full.is_complete());
  CHECK(full->byte_count == 70);
  CHECK(full->status == 0x1234);
  CHECK(full->event_count == 0x0108);
  CHECK(full->message_count == 0x0121);
  CHECK(full->data.size() == 64);
  log[1] = 71;
  log.push_back(0x40);
  CHECK(decode_response_unpaired(view(log)).error() == errc::modbus_byte_count);
}

TEST_CASE("client decoders: FC18's longest queue, FC2B/0E's header fields and its shortest PDU") {
  // FC18 (§6.19): up to 31 registers in the queue; 32 is a quantity error
  bytes fifo = {0x18, 0x00, 64, 0x00, 31};
  for (unsigned i = 0; i < 62U; ++i) {
    fifo.push_back(static_cast<std::uint8_t>(i));
  }
  const auto full = decode_response_unpaired(view(fifo));
  REQUIRE(full.is_complete());
  CHECK(full->fifo_count == 31);
  CHECK(full->data.size() == 62);
  fifo[2] = 66;
  fifo[4] = 32;
  fifo.push_back(0x00);
  fifo.push_back(0x00);
  CHECK(decode_response_unpaired(view(fifo)).error() == errc::modbus_quantity);
  // FC2B/0E (§6.21): conformity level, more follows (0xFF), next object id, object count
  const bytes ident = {0x2B, 0x0E, 0x01, 0x81, 0xFF, 0x03, 0x01, 0x00, 0x02, 'M', 'B'};
  const auto id = decode_response_unpaired(view(ident));
  REQUIRE(id.is_complete());
  CHECK(id->conformity == 0x81);
  CHECK(id->more_follows);
  CHECK(id->next_object == 0x03);
  CHECK(id->object_count == 1);
  const bytes last = {0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 0x00};
  const auto no_more = decode_response_unpaired(view(last));
  REQUIRE(no_more.is_complete());
  CHECK_FALSE(no_more->more_follows);
  // a response of the MEI type and nothing more is truncated, not passed on as another type
  CHECK(decode_response_unpaired(view({0x2B, 0x0E})).error() == errc::truncated);
}

TEST_CASE("client: FC14 responses, the head's failures and exception, and each sub-response") {
  // a request of two sub-requests of different lengths (1 and 2 registers), and its answer
  const bytes sent = {0x14, 0x0E, 0x06, 0x00, 0x04, 0x00, 0x01, 0x00,
                      0x01, 0x06, 0x00, 0x03, 0x00, 0x09, 0x00, 0x02};
  const bytes answer = {0x14, 0x0A, 0x03, 0x06, 0x11, 0x22, 0x05, 0x06, 0x33, 0x44, 0x55, 0x66};
  const auto ok = decode_read_file_record_response(view(sent), view(answer));
  REQUIRE(ok.is_complete());
  CHECK(ok->count == 2);
  // the head: a failure consumes the whole PDU; a request that is no FC14 request is an
  // invalid argument; an exception response names the function and is a response
  const bytes other = {0x03, 0x02, 0x00, 0x00};
  const auto mismatch = decode_read_file_record_response(view(sent), view(other));
  CHECK(mismatch.error() == errc::modbus_mismatch);
  CHECK(mismatch.consumed() == other.size());
  const bytes not_fc14 = {0x03, 0x00, 0x00, 0x00, 0x01};
  const auto invalid = decode_read_file_record_response(view(not_fc14), view(answer));
  CHECK(invalid.error() == errc::invalid_argument);
  CHECK(invalid.consumed() == answer.size());
  const auto exception = decode_read_file_record_response(view(sent), view({0x94, 0x02}));
  REQUIRE(exception.is_complete());
  CHECK(exception->exception);
  CHECK(exception->exception_code == 0x02);
  CHECK(exception->function == 0x14);
  CHECK(exception->response);
  // a byte count of 0: no sub-response, fewer than asked (not truncated)
  CHECK(decode_read_file_record_response(view(sent), view({0x14, 0x00})).error() ==
        errc::modbus_mismatch);
  // one sub-response more than asked
  bytes more = answer;
  more[1] = 0x0E;
  more.insert(more.end(), {0x03, 0x06, 0x77, 0x88});
  CHECK(decode_read_file_record_response(view(sent), view(more)).error() == errc::modbus_mismatch);
  // and with the request in a longer buffer (a client's transmit buffer, whose bytes after the
  // request would read as a sub-request of 1 register): a sub-response past the last one asked
  // is a mismatch, whatever follows it
  const std::uint8_t tx[16] = {0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00,
                               0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01};
  const bytes extra = {0x14, 0x0A, 0x03, 0x06, 0xAA, 0xBB, 0x03, 0x06, 0xCC, 0xDD, 0x02, 0x06};
  CHECK(decode_read_file_record_response(byte_view(tx, 9), view(extra)).error() ==
        errc::modbus_mismatch);
}

TEST_CASE("client: failures without evidence carry expected and received 0") {
  // evidence (expected, received) is the functions of a mismatch; a failure of the body has
  // none, paired or not
  const bytes fc07 = {0x07};
  const auto paired = decode_response_for(view(fc07), view({0x07, 0x6D, 0x00}));
  CHECK(paired.error() == errc::modbus_byte_count);
  CHECK(paired.expected() == 0);
  CHECK(paired.received() == 0);
  const auto unpaired = decode_response_unpaired(view({0x07, 0x6D, 0x00}));
  CHECK(unpaired.error() == errc::modbus_byte_count);
  CHECK(unpaired.expected() == 0);
  CHECK(unpaired.received() == 0);
}
