// Core bit reader at its edges: find() for both values and both bit orders across word and
// 64-bit step boundaries, field_at refusals, countr_zero64.
#include <doctest/doctest.h>

#include <cstdint>

#include "motionbus/core/bits.hpp"

using namespace motionbus;

TEST_CASE("countr_zero64: trailing zeros, 64 for zero") {
  CHECK(countr_zero64(0) == 64U);
  CHECK(countr_zero64(1) == 0U);
  CHECK(countr_zero64(std::uint64_t{1} << 63U) == 63U);
  CHECK(countr_zero64(0x28) == 3U);
}

TEST_CASE("bit reader find: 0s and 1s, MSB and LSB first, past 64 bits, not found") {
  // 96 bits: 70 ones, a zero at 70, ones to the end (MSB first); the same words read
  // LSB first put that zero at bit 70 - 64 + (31 - 6) ... computed below from the words.
  const std::uint32_t words[3] = {0xFFFFFFFFU, 0xFFFFFFFFU, 0xFDFFFFFFU};
  const basic_bit_reader<std::uint32_t> msb(span<const std::uint32_t>(words, 3));
  CHECK(msb.find(false, 0) == 70U);        // three 64-bit steps: the zero in the second
  CHECK(msb.find(false, 71) == msb.npos);  // ones to the end
  CHECK(msb.find(true, 0) == 0U);
  CHECK(msb.find(false, 0, 70) == msb.npos);  // limit stops before it
  CHECK(msb.find(false, 96) == msb.npos);     // from at the end
  const basic_bit_reader<std::uint32_t> lsb(span<const std::uint32_t>(words, 3),
                                            bit_order::lsb_first);
  CHECK(lsb.find(false, 0) == 64U + 25U);  // bit 25 of the third word, counted from its LSB
  CHECK(lsb.find(true, 89) == 90U);
  // field_at refusals
  CHECK(msb.field_at(0, 65).error() == errc::invalid_argument);
  CHECK(msb.field_at(90, 8).error() == errc::truncated);
  CHECK(msb.field_at(97, 0).error() == errc::truncated);
}
