// BiSS-C electronic data sheet banks: the common part's checksum, verified on request, and
// the bank sizes the codec refuses (the BP3 profile and the ABSYS banks are in
// tests/devices/absys_test.cpp).
#include "motionbus/biss/eds.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using namespace motionbus;
using namespace motionbus::biss;

TEST_CASE("EDS common part: a checksum that does not match, when asked to verify; a short bank") {
  std::uint8_t bank[bank_size] = {};
  REQUIRE(encode_eds_common(eds_common{}, mutable_byte_view(bank, bank_size)) == errc::ok);
  eds_options verify;
  verify.verify_checksum = true;
  CHECK(decode_eds_common(byte_view(bank, bank_size), verify).is_complete());
  bank[0x3F] = static_cast<std::uint8_t>(bank[0x3F] + 1U);
  const auto bad = decode_eds_common(byte_view(bank, bank_size), verify);
  CHECK(bad.error() == errc::biss_eds);
  CHECK(bad.consumed() == bank_size);
  CHECK(bad.expected() == bank_checksum(byte_view(bank, bank_size)));  // the evidence
  CHECK(bad.received() == bank[0x3F]);
  CHECK(decode_eds_common(byte_view(bank, bank_size)).is_complete());  // not verified by default
  CHECK(decode_eds_common(byte_view(bank, bank_size)).consumed() == bank_size);
  const auto part = decode_eds_common(byte_view(bank, 40));  // a decoder's "need more input"
  CHECK(part.is_incomplete());
  CHECK(part.needed() == bank_size - 40U);
  CHECK(encode_eds_common(eds_common{}, mutable_byte_view(bank, bank_size - 1U)) ==
        errc::buffer_too_small);
}
