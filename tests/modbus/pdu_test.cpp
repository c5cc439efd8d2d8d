// Modbus request PDUs (pdu.hpp): decode_request's limits and counts in the order of the
// Modbus Application Protocol V1.1b3 §6, every prefix of its worked examples, FC2B MEI types.
#include "motionbus/modbus/pdu.hpp"

#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/pdu_server.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/modbus_examples.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

TEST_CASE("server: limits and counts, checked in the spec's order") {
  auto err = [](const bytes& pdu) { return decode_request(view(pdu)).error(); };
  CHECK(err({}) == errc::modbus_pdu_length);
  CHECK(err(bytes(254, 0x03)) == errc::modbus_pdu_length);
  CHECK(err({0x83, 0x00}) == errc::modbus_illegal_function);
  CHECK(err({0x00}) == errc::modbus_illegal_function);
  // quantities
  CHECK(err({0x01, 0x00, 0x00, 0x00, 0x00}) == errc::modbus_quantity);
  CHECK(err({0x01, 0x00, 0x00, 0x07, 0xD1}) == errc::modbus_quantity);        // 2001
  CHECK(decode_request(view({0x01, 0x00, 0x00, 0x07, 0xD0})).is_complete());  // 2000
  CHECK(err({0x03, 0x00, 0x00, 0x00, 0x7E}) == errc::modbus_quantity);        // 126
  CHECK(decode_request(view({0x04, 0x00, 0x00, 0x00, 0x7D})).is_complete());  // 125
  // quantity is checked before the address range (exception 03 before 02)
  CHECK(err({0x03, 0xFF, 0xFF, 0x00, 0x00}) == errc::modbus_quantity);
  CHECK(err({0x03, 0xFF, 0xFF, 0x00, 0x02}) == errc::modbus_address_overflow);
  CHECK(decode_request(view({0x03, 0xFF, 0xFF, 0x00, 0x01})).is_complete());
  // truncated and over-long fixed-size requests
  CHECK(err({0x03, 0x00, 0x6B, 0x00}) == errc::truncated);
  CHECK(err({0x03, 0x00, 0x6B, 0x00, 0x03, 0x00}) == errc::modbus_byte_count);
  // FC05 values
  CHECK(err({0x05, 0x00, 0xAC, 0x12, 0x34}) == errc::modbus_coil_value);
  CHECK(decode_request(view({0x05, 0x00, 0xAC, 0x00, 0x00})).is_complete());
  // FC0F / FC10 byte counts against quantity and bytes present
  CHECK(err({0x0F, 0x00, 0x13, 0x00, 0x0A, 0x01, 0xCD}) == errc::modbus_byte_count);
  CHECK(err({0x0F, 0x00, 0x13, 0x00, 0x0A, 0x02, 0xCD}) == errc::modbus_byte_count);
  CHECK(err({0x0F, 0x00, 0x13, 0x07, 0xB1, 0xF7}) == errc::modbus_quantity);  // 1969
  CHECK(err({0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01}) == errc::modbus_byte_count);
  CHECK(err({0x10, 0x00, 0x01, 0x00, 0x02, 0x03, 0x00, 0x0A, 0x01}) == errc::modbus_byte_count);
  CHECK(err({0x10, 0x00, 0x01, 0x00, 0x7C, 0xF8}) == errc::modbus_quantity);  // 124
  CHECK(err({0x10, 0xFF, 0xFF, 0x00, 0x02, 0x04, 0, 0, 0, 0}) == errc::modbus_address_overflow);
  CHECK(err({0x10, 0x00, 0x01, 0x00}) == errc::truncated);
  // FC17 write quantity 122, byte count mismatch
  CHECK(err({0x17, 0, 3, 0, 6, 0, 14, 0, 0x7A, 0xF4}) == errc::modbus_quantity);
  CHECK(err({0x17, 0, 3, 0, 6, 0, 14, 0, 3, 0x06, 0, 0xFF}) == errc::modbus_byte_count);
  // functions without data must not be read as if they had an address
  CHECK(decode_request(view({0x11})).is_complete());
  CHECK(err({0x11, 0x00, 0x01}) == errc::modbus_byte_count);
  CHECK(err({0x07, 0x00}) == errc::modbus_byte_count);
  // unknown function: raw
  const auto raw = decode_request(view({0x41, 0x01, 0x02}));
  REQUIRE(raw.is_complete());
  CHECK(raw->data.size() == 2);
  // exceptions for each error
  CHECK(exception_for(errc::modbus_illegal_function) == exception_code::illegal_function);
  CHECK(exception_for(errc::modbus_quantity) == exception_code::illegal_data_value);
  CHECK(exception_for(errc::modbus_byte_count) == exception_code::illegal_data_value);
  CHECK(exception_for(errc::modbus_coil_value) == exception_code::illegal_data_value);
  CHECK(exception_for(errc::modbus_address_overflow) == exception_code::illegal_data_address);
}

TEST_CASE("every prefix of every spec request is rejected; the whole request decodes") {
  for (const auto& ex : spec_examples()) {
    for (std::size_t n = 0; n < ex.request.size(); ++n) {
      CAPTURE(ex.name);
      CAPTURE(n);
      CHECK(decode_request(view(ex.request).first(n)).is_failed());
    }
    CHECK(decode_request(view(ex.request)).is_complete());
  }
}

TEST_CASE("server: FC2B with another MEI type is passed on; a lone 0x2B is truncated") {
  const bytes other_mei = {0x2B, 0x0D, 0x01, 0x02};
  const auto q = decode_request(view(other_mei));
  REQUIRE(q.is_complete());
  CHECK(q->mei_type == 0x0D);
  CHECK(q->data.size() == 2);
  CHECK(decode_request(view({0x2B})).error() == errc::truncated);
}

namespace {

// decode_request<Served> on `pdu`: for a function in Served, what decode_request<all> gives;
// for one outside it, the raw request (the function and its data, unchecked).
template <function_set Served>
void check_served_set(const bytes& pdu) {
  CAPTURE(static_cast<unsigned>(pdu[0]));
  const auto all = decode_request(view(pdu));
  const auto some = decode_request<Served>(view(pdu));
  if (in_function_set<Served>(pdu[0])) {
    REQUIRE(some.status() == all.status());
    CHECK(some.error() == all.error());
    if (all.is_complete()) {
      CHECK(some->quantity == all->quantity);
      CHECK(some->data.size() == all->data.size());
    }
  } else {
    REQUIRE(some.is_complete());
    CHECK(some->function == pdu[0]);
    CHECK(some->data.size() == pdu.size() - 1U);
  }
}

template <function_set Served>
void check_served_set_all() {
  // a valid request of each function the codec frames, and an invalid one of several
  const bytes requests[] = {
      {0x01, 0x00, 0x00, 0x00, 0x08},
      {0x02, 0x00, 0x00, 0x00, 0x08},
      {0x03, 0x00, 0x00, 0x00, 0x02},
      {0x04, 0x00, 0x00, 0x00, 0x02},
      {0x04, 0x00, 0x00, 0x00, 0x00},  // quantity 0
      {0x05, 0x00, 0x01, 0xFF, 0x00},
      {0x06, 0x00, 0x01, 0x12, 0x34},
      {0x06, 0x00, 0x01, 0x12},  // short
      {0x0F, 0x00, 0x00, 0x00, 0x08, 0x01, 0xFF},
      {0x10, 0x00, 0x00, 0x00, 0x01, 0x02, 0x12, 0x34},
      {0x10, 0x00, 0x00, 0x00, 0x01, 0x03, 0x12, 0x34, 0x56},  // byte count
      {0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25},
      {0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x02, 0x12, 0x34},
      {0x07},
      {0x07, 0x00},  // data where none is
      {0x0B},
      {0x0B, 0x00},
      {0x0C},
      {0x0C, 0x00},
      {0x11},
      {0x11, 0x00},
      {0x08, 0x00, 0x00, 0x12, 0x34},
      {0x18, 0x00, 0x04},
      {0x2B, 0x0E, 0x01, 0x00},
      {0x41, 0x01, 0x02}};
  for (const bytes& pdu : requests) {
    check_served_set<Served>(pdu);
  }
}

}  // namespace

TEST_CASE("decode_request<Served>: a function outside the set decodes raw, one in it as usual") {
  // sets with one function of each branch (the others compiled out), and combinations
  check_served_set_all<functions_of(0x01)>();
  check_served_set_all<functions_of(0x02)>();
  check_served_set_all<functions_of(0x03)>();
  check_served_set_all<functions_of(0x04)>();
  check_served_set_all<functions_of(0x05)>();
  check_served_set_all<functions_of(0x06)>();
  check_served_set_all<functions_of(0x0F)>();
  check_served_set_all<functions_of(0x10)>();
  check_served_set_all<functions_of(0x07)>();
  check_served_set_all<functions_of(0x0B)>();
  check_served_set_all<functions_of(0x0C)>();
  check_served_set_all<functions_of(0x11)>();
  check_served_set_all<functions_of(0x16, 0x17)>();
  check_served_set_all<functions_of(0x08, 0x18, 0x2B)>();
  // each of those alone: a branch that named another function of its group than the one served
  // would then decode it raw
  check_served_set_all<functions_of(0x16)>();
  check_served_set_all<functions_of(0x17)>();
  check_served_set_all<functions_of(0x08)>();
  check_served_set_all<functions_of(0x18)>();
  check_served_set_all<functions_of(0x2B)>();
  check_served_set_all<function_set{0}>();
}

TEST_CASE("function sets and diagnostic sub-functions at run time, every code") {
  // in_function_set against the set's bits; codes 64 and up are in no set
  constexpr function_set set = functions_of(0x01, 0x1F, 0x20, 0x3F);
  for (unsigned f = 0; f < 256U; ++f) {
    CAPTURE(f);
    const auto code = static_cast<std::uint8_t>(f);
    const bool in = f < 64U && ((set >> f) & 1U) != 0U;
    CHECK(in_function_set<set>(code) == in);
    CHECK(in_function_set<all_functions>(code) == (f < 64U));
  }
  // the defined sub-functions: 00-04, 0A-12, 14 (Modbus over Serial Line §6.1)
  for (unsigned sub = 0; sub < 0x40U; ++sub) {
    CAPTURE(sub);
    const bool defined = sub <= 0x04U || (sub >= 0x0AU && sub <= 0x12U) || sub == 0x14U;
    CHECK(diagnostic::is_defined(static_cast<std::uint16_t>(sub)) == defined);
  }
}

TEST_CASE("FC08 and FC2B requests: each check of the sub-function and the MEI request alone") {
  auto err = [](const bytes& pdu) { return decode_request(view(pdu)).error(); };
  CHECK(err({0x08, 0x00, 0x01, 0x00, 0x00}) == errc::ok);  // restart, log kept
  CHECK(err({0x08, 0x00, 0x01, 0xFF, 0x00}) == errc::ok);  // restart, log cleared
  CHECK(err({0x08, 0x00, 0x01, 0x12, 0x34}) == errc::modbus_coil_value);
  CHECK(err({0x08, 0x00, 0x0A, 0x12, 0x34}) == errc::ok);  // any data for another one
  CHECK(err({0x08, 0x00, 0x0A, 0x00}) == errc::modbus_byte_count);
  CHECK(err({0x08, 0x00, 0x00, 0x12}) == errc::modbus_byte_count);  // query data: even
  CHECK(err({0x08, 0x00, 0x05, 0x00, 0x00}) == errc::modbus_illegal_function);
  CHECK(err({0x2B, 0x0E, 0x01, 0x00}) == errc::ok);
  CHECK(err({0x2B, 0x0E, 0x00, 0x00}) == errc::modbus_quantity);  // read device ID code 0
  CHECK(err({0x2B, 0x0E, 0x05, 0x00}) == errc::modbus_quantity);
  CHECK(err({0x2B, 0x0E, 0x01, 0x00, 0x00}) == errc::modbus_byte_count);  // an extra byte
  CHECK(err({0x2B, 0x0E, 0x01}) != errc::ok);                             // a byte short
}

TEST_CASE("FC08 sub-function codes: the specification's table (App. Protocol §6.8.1)") {
  // The table's codes as it prints them, in decimal (Modbus Application Protocol V1.1b3
  // §6.8.1; the same in pymodbus's diag_message): a wrong constant would send another
  // counter's request.
  CHECK(diagnostic::return_query_data == 0);
  CHECK(diagnostic::restart_communications == 1);
  CHECK(diagnostic::return_diagnostic_register == 2);
  CHECK(diagnostic::change_ascii_delimiter == 3);
  CHECK(diagnostic::force_listen_only == 4);
  CHECK(diagnostic::clear_counters == 10);
  CHECK(diagnostic::return_bus_message_count == 11);
  CHECK(diagnostic::return_bus_error_count == 12);
  CHECK(diagnostic::return_exception_count == 13);
  CHECK(diagnostic::return_server_message_count == 14);
  CHECK(diagnostic::return_no_response_count == 15);
  CHECK(diagnostic::return_nak_count == 16);
  CHECK(diagnostic::return_busy_count == 17);
  CHECK(diagnostic::return_overrun_count == 18);
  CHECK(diagnostic::clear_overrun_counter == 20);
}

TEST_CASE("function and exception codes: the wire values of the Application Protocol (§5.1, §7)") {
  // The public function codes of Modbus Application Protocol V1.1b3 §5.1 and the exception
  // codes of §7, as the specification prints them: a wrong constant would put another
  // function (or another exception) on the wire.
  CHECK(function_code::read_coils == 0x01);
  CHECK(function_code::read_discrete_inputs == 0x02);
  CHECK(function_code::read_holding_registers == 0x03);
  CHECK(function_code::read_input_registers == 0x04);
  CHECK(function_code::write_single_coil == 0x05);
  CHECK(function_code::write_single_register == 0x06);
  CHECK(function_code::read_exception_status == 0x07);
  CHECK(function_code::diagnostics == 0x08);
  CHECK(function_code::get_comm_event_counter == 0x0B);
  CHECK(function_code::get_comm_event_log == 0x0C);
  CHECK(function_code::write_multiple_coils == 0x0F);
  CHECK(function_code::write_multiple_registers == 0x10);
  CHECK(function_code::report_server_id == 0x11);
  CHECK(function_code::mask_write_register == 0x16);
  CHECK(function_code::read_write_multiple_registers == 0x17);
  CHECK(function_code::read_fifo_queue == 0x18);
  CHECK(function_code::encapsulated_interface == 0x2B);
  auto wire = [](exception_code c) { return static_cast<unsigned>(c); };
  CHECK(wire(exception_code::illegal_function) == 0x01);
  CHECK(wire(exception_code::illegal_data_address) == 0x02);
  CHECK(wire(exception_code::illegal_data_value) == 0x03);
  CHECK(wire(exception_code::server_device_failure) == 0x04);
  CHECK(wire(exception_code::acknowledge) == 0x05);
  CHECK(wire(exception_code::server_device_busy) == 0x06);
  CHECK(wire(exception_code::memory_parity_error) == 0x08);
  CHECK(wire(exception_code::gateway_path_unavailable) == 0x0A);
  CHECK(wire(exception_code::gateway_target_failed) == 0x0B);
  // report_id_format's values are those the Python package's ReportIdFormat and the fuzz
  // targets pass as a number (0 the standard layout, 1 the SM unit's two bytes)
  CHECK(static_cast<unsigned>(report_id_format::standard) == 0);
  CHECK(static_cast<unsigned>(report_id_format::two_bytes_no_count) == 1);
}

TEST_CASE("a decoded request or response holds 0 in every field its function does not carry") {
  // FC07 Read Exception Status carries nothing but its function code (a request) and one
  // status byte (a response): every other field keeps the struct's default, 0, so that two
  // decodings of the same bytes compare equal field by field
  const auto q = decode_request(view(bytes{0x07}));
  REQUIRE(q.is_complete());
  const request& r = q.value();
  CHECK(r.function == 0x07);
  CHECK(r.data.empty());
  CHECK(r.address == 0);
  CHECK(r.quantity == 0);
  CHECK(r.value == 0);
  CHECK(r.and_mask == 0);
  CHECK(r.or_mask == 0);
  CHECK(r.write_address == 0);
  CHECK(r.write_quantity == 0);
  CHECK(r.sub_function == 0);
  CHECK(r.mei_type == 0);
  CHECK(r.read_code == 0);
  CHECK(r.object_id == 0);
  for (const bytes& pdu : {bytes{0x07, 0x6D}, bytes{0x83, 0x02}}) {
    CAPTURE(pdu.size());
    const auto a = decode_response_unpaired(view(pdu));
    REQUIRE(a.is_complete());
    const response& p = a.value();
    const bool exception = pdu[0] == 0x83;
    CHECK(p.function == (exception ? 0x03 : 0x07));
    CHECK(p.exception == exception);
    CHECK(p.exception_code == (exception ? 0x02 : 0x00));
    CHECK(p.status == (exception ? 0x00 : 0x6D));
    CHECK(p.data.empty());
    CHECK(p.byte_count == 0);
    CHECK(p.address == 0);
    CHECK(p.quantity == 0);
    CHECK(p.value == 0);
    CHECK(p.and_mask == 0);
    CHECK(p.or_mask == 0);
    CHECK(p.sub_function == 0);
    CHECK(p.event_count == 0);
    CHECK(p.message_count == 0);
    CHECK(p.fifo_count == 0);
    CHECK(p.conformity == 0);
    CHECK_FALSE(p.more_follows);
    CHECK(p.next_object == 0);
    CHECK(p.object_count == 0);
  }
  // and a caller that fills a request or response by hand starts from all zeros: no function
  CHECK(request{}.function == 0);
  CHECK(response{}.function == 0);
  CHECK_FALSE(response{}.exception);
}

TEST_CASE("the PDU encoders write the bytes they return and no more; an exact buffer is enough") {
  // Each encoder into a buffer of 0xA5s: the bytes past the length it returns keep their
  // 0xA5; into a buffer of exactly that length it writes the same bytes; one byte less is
  // buffer_too_small. The packed coils are the first two bytes of four, so that a copy one
  // byte too long would show (0x5A past the end).
  const std::uint8_t four[4] = {0xFF, 0x03, 0x5A, 0x5A};
  const byte_view packed(four, 2);
  const std::uint16_t regs[3] = {0x1234, 0x5678, 0x9ABC};
  const span<const std::uint16_t> values(regs, 3);
  using encoder = std::function<result<std::size_t>(mutable_byte_view)>;
  const encoder encoders[] = {
      [](mutable_byte_view out) { return encode_read(0x03, 0x0010, 2, out); },
      [](mutable_byte_view out) { return encode_write_single_coil(0x0020, true, out); },
      [](mutable_byte_view out) { return encode_write_single_register(0x0030, 0xBEEF, out); },
      [](mutable_byte_view out) { return encode_mask_write_register(0x0004, 0x00F2, 0x0025, out); },
      [&](mutable_byte_view out) { return encode_write_multiple_coils(0x0013, 10, packed, out); },
      [&](mutable_byte_view out) { return encode_write_multiple_registers(0x0001, values, out); },
      [&](mutable_byte_view out) {
        return encode_read_write_multiple_registers(0x0003, 6, 0x000E, values, out);
      },
      [&](mutable_byte_view out) { return encode_read_bits_response(0x01, 10, packed, out); },
      [&](mutable_byte_view out) { return encode_read_registers_response(0x03, values, out); },
      [](mutable_byte_view out) { return encode_comm_event_counter_response(0xFFFF, 0x0108, out); },
  };
  for (std::size_t k = 0; k < sizeof encoders / sizeof encoders[0]; ++k) {
    CAPTURE(k);
    bytes big(300, 0xA5);
    const auto n = encoders[k](mutable_byte_view(big.data(), big.size()));
    REQUIRE(n.ok());
    const std::size_t len = n.value();
    for (std::size_t i = len; i < big.size(); ++i) {
      CAPTURE(i);
      REQUIRE(big[i] == 0xA5);
    }
    bytes exact(len, 0xA5);
    const auto m = encoders[k](mutable_byte_view(exact.data(), exact.size()));
    REQUIRE(m.ok());
    CHECK(m.value() == len);
    CHECK(exact == bytes(big.begin(), big.begin() + static_cast<std::ptrdiff_t>(len)));
    bytes short_by_one(len - 1U, 0xA5);
    CHECK(encoders[k](mutable_byte_view(short_by_one.data(), short_by_one.size())).error() ==
          errc::buffer_too_small);
  }
}

TEST_CASE("FC2B/0E: an object of length 0 that ends the response is inside it") {
  // Read Device Identification (Application Protocol §6.21): two objects, the last one of
  // length 0 ending exactly at the PDU's end; both are there, the second with an empty value
  const bytes pdu = {0x2B, 0x0E, 0x01, 0x01, 0x00, 0x00, 0x02, 0x00, 0x01, 'A', 0x01, 0x00};
  const auto a = decode_response_unpaired(view(pdu));
  REQUIRE(a.is_complete());
  const response& r = a.value();
  CHECK(r.object_count == 2);
  const auto first = object_at(r, 0);
  REQUIRE(first.ok());
  CHECK(first.value().id == 0x00);
  CHECK(first.value().value.size() == 1);
  const auto last = object_at(r, 1);
  REQUIRE(last.ok());
  CHECK(last.value().id == 0x01);
  CHECK(last.value().value.empty());
  CHECK(object_at(r, 2).error() == errc::out_of_range);
  // one byte less: the last object's length byte is missing
  const auto cut = decode_response_unpaired(view(bytes(pdu.begin(), pdu.end() - 1)));
  CHECK_FALSE(cut.is_complete());
}

TEST_CASE("requests at the edges of their layouts: no data, FC08's data, FC2B's MEI types") {
  // FC07, 0B, 0C and 11 carry no data (§6.7, 6.9, 6.10, 6.13): one byte more is a byte count
  // error, not an address
  for (const std::uint8_t f :
       {std::uint8_t{0x07}, std::uint8_t{0x0B}, std::uint8_t{0x0C}, std::uint8_t{0x11}}) {
    CAPTURE(static_cast<unsigned>(f));
    CHECK(decode_request(view(bytes{f})).is_complete());
    CHECK(decode_request(view(bytes{f, 0x00})).error() == errc::modbus_byte_count);
  }
  // FC08 (§6.8): Return Query Data echoes any even number of bytes, none included; the other
  // sub-functions take exactly one word
  const auto none = decode_request(view(bytes{0x08, 0x00, 0x00}));
  REQUIRE(none.is_complete());
  CHECK(none->sub_function == diagnostic::return_query_data);
  CHECK(none->data.empty());
  const auto four = decode_request(view(bytes{0x08, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04}));
  REQUIRE(four.is_complete());
  CHECK(four->data.size() == 4);
  CHECK(decode_request(view(bytes{0x08, 0x00, 0x00, 0x01, 0x02, 0x03})).error() ==
        errc::modbus_byte_count);
  CHECK(decode_request(view(bytes{0x08, 0x00, 0x0A, 0x00, 0x00})).is_complete());
  CHECK(decode_request(view(bytes{0x08, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00})).error() ==
        errc::modbus_byte_count);
  CHECK(decode_request(view(bytes{0x08, 0x00})).error() == errc::truncated);
  // FC2B (§6.21): another MEI type with no data is passed on; read device identification
  // takes read codes 1 to 4 (4: one specific object) and the object id
  const auto other = decode_request(view(bytes{0x2B, 0x0D}));
  REQUIRE(other.is_complete());
  CHECK(other->mei_type == 0x0D);
  CHECK(other->data.empty());
  const auto one_object = decode_request(view(bytes{0x2B, 0x0E, 0x04, 0x05}));
  REQUIRE(one_object.is_complete());
  CHECK(one_object->read_code == 4);
  CHECK(one_object->object_id == 0x05);
  CHECK(decode_request(view(bytes{0x2B, 0x0E, 0x05, 0x00})).error() == errc::modbus_quantity);
  CHECK(decode_request(view(bytes{0x2B, 0x0E, 0x00, 0x00})).error() == errc::modbus_quantity);
}

TEST_CASE("FC0F built in place: the coils may already lie where the request puts them") {
  // a client that lays out its coils in its transmit buffer first, at the request's data
  // (byte 6 on), then encodes the request around them: the head is written before, and
  // around, the coils, never over them (the §6.11 example: coils CD 01)
  std::uint8_t buf[16] = {0, 0, 0, 0, 0, 0, 0xCD, 0x01};
  const auto n = encode_write_multiple_coils(0x0013, 10, byte_view(buf + 6, 2),
                                             mutable_byte_view(buf, sizeof buf));
  REQUIRE(n.ok());
  CHECK(bytes(buf, buf + n.value()) == bytes{0x0F, 0x00, 0x13, 0x00, 0x0A, 0x02, 0xCD, 0x01});
}
