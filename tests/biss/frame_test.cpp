// BiSS-C frame vocabulary (frame.hpp): CRC formats from the BiSS and EDS polynomial notations,
// slave layouts, their bit counts and their validation.
#include "motionbus/biss/frame.hpp"

#include <doctest/doctest.h>

using namespace motionbus;
using namespace motionbus::biss;

TEST_CASE("BiSS polynomial notations") {
  CHECK(crc_from_biss_notation(0x43) == crc6_43);
  CHECK(crc_from_biss_notation(0x13).width == 4);
  CHECK(crc_from_biss_notation(0x13).poly == 0x3);
  CHECK(crc_from_biss_notation(0x97).width == 7);
  CHECK(crc_from_biss_notation(0x1).width == 0);
  CHECK(crc_from_eds(0x21) == crc6_43);  // EDS CPOLY (31:1) 0x21 is 0x43
  CHECK(absys_layout.frame_bits() == 40);
  CHECK(absys_layout.data_bits() == 32);
}

TEST_CASE("slave_layout: frame_bits() counts data, nE, nW and CRC bits") {
  slave_layout l;
  l.multi_turn_bits = 12;
  l.single_turn_bits = 18;
  l.alignment_bits = 2;
  CHECK(l.data_bits() == 32);
  CHECK(l.status_bits() == 2);
  CHECK(l.frame_bits() == 32 + 2 + 6);
  l.has_warning = false;
  l.crc = crc_from_biss_notation(0x13);  // CRC4
  CHECK(l.status_bits() == 1);
  CHECK(l.frame_bits() == 32 + 1 + 4);
}

TEST_CASE("slave_layout: validate() takes 1..64 data bits and a CRC that fits its width") {
  CHECK(absys_layout.validate() == errc::ok);
  slave_layout l;
  l.multi_turn_bits = 32;
  CHECK(l.validate() == errc::ok);  // 64 data bits
  l.alignment_bits = 1;
  CHECK(l.validate() == errc::biss_layout);  // 65
  l = slave_layout{};
  l.single_turn_bits = 0;
  CHECK(l.validate() == errc::biss_layout);  // none
  l = slave_layout{};
  l.multi_turn_bits = ~0U;  // a width that would overflow the sum is refused on its own
  l.single_turn_bits = 2;
  CHECK(l.validate() == errc::biss_layout);
  l = slave_layout{};
  l.crc.width = 17;
  CHECK(l.validate() == errc::biss_layout);
  l = slave_layout{};
  l.crc.poly = 0x43;  // 7 bits in a 6-bit CRC
  CHECK(l.validate() == errc::biss_layout);
  l = slave_layout{};
  l.crc.start = 0x40;
  CHECK(l.validate() == errc::biss_layout);
}

TEST_CASE("crc_format: == compares every field; parameters() of a 32-bit CRC") {
  const crc_format c;
  CHECK(c == crc_format{});
  crc_format o = c;
  o.width = 5;
  CHECK(o != c);
  o = c;
  o.poly = 0x05;
  CHECK(o != c);
  o = c;
  o.start = 0x01;
  CHECK(o != c);
  o = c;
  o.inverted = false;
  CHECK(o != c);
  CHECK(c.parameters().xorout == 0x3FU);
  CHECK(o.parameters().xorout == 0U);
  crc_format wide{32, 0x04C11DB7, 0, true};  // the mask of every bit: no 32-bit shift
  CHECK(wide.parameters().xorout == 0xFFFFFFFFU);
}

TEST_CASE("slave_layout: validate() refuses each too-wide field alone") {
  slave_layout l;
  l.single_turn_bits = 65;
  CHECK(l.validate() == errc::biss_layout);
  l = slave_layout{};
  l.multi_turn_bits = 65;
  l.single_turn_bits = 0;
  CHECK(l.validate() == errc::biss_layout);
  l = slave_layout{};
  l.alignment_bits = 65;
  CHECK(l.validate() == errc::biss_layout);
}

TEST_CASE("crc_from_biss_notation: the smallest polynomials, the output choice, the defaults") {
  // The width is the position of the highest set bit: 0 and 1 give no CRC, x (0x2) and x + 1
  // (0x3, a parity bit) a width of 1.
  CHECK(crc_from_biss_notation(0x0).width == 0U);
  CHECK(crc_from_biss_notation(0x1).width == 0U);
  CHECK(crc_from_biss_notation(0x2).width == 1U);
  CHECK(crc_from_biss_notation(0x2).poly == 0x0U);
  CHECK(crc_from_biss_notation(0x3).width == 1U);
  CHECK(crc_from_biss_notation(0x3).poly == 0x1U);
  CHECK(crc_from_biss_notation(0x80000001U).width == 31U);
  // sent inverted unless asked plain
  CHECK(crc_from_biss_notation(0x43).inverted);
  CHECK(crc_from_biss_notation(0x43, 0, crc_output::inverted).inverted);
  CHECK_FALSE(crc_from_biss_notation(0x43, 0, crc_output::plain).inverted);
  CHECK(crc_from_biss_notation(0x43, 0, crc_output::plain).width == 6U);
  // a default crc_format is the BiSS CRC6 x^6 + x + 1 (notation 0x43), start 0, inverted
  CHECK(crc_format{} == crc_from_biss_notation(0x43));
  CHECK(crc_format{}.poly == 0x03U);
}
