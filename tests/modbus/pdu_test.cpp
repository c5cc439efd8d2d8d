// Modbus request PDUs (pdu.hpp): decode_request's limits and counts in the order of the
// Modbus Application Protocol V1.1b3 §6, every prefix of its worked examples, FC2B MEI types.
#include "motionbus/modbus/pdu.hpp"

#include <doctest/doctest.h>

#include <cstdint>
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
