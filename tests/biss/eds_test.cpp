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
  CHECK(decode_eds_common(byte_view(bank, bank_size), verify).ok());
  bank[0x3F] = static_cast<std::uint8_t>(bank[0x3F] + 1U);
  CHECK(decode_eds_common(byte_view(bank, bank_size), verify).error() == errc::biss_eds);
  CHECK(decode_eds_common(byte_view(bank, bank_size)).ok());  // not verified by default
  CHECK(encode_eds_common(eds_common{}, mutable_byte_view(bank, bank_size - 1U)) ==
        errc::buffer_too_small);
}
