// BiSS-C electronic data sheet banks: the common part's checksum, verified on request, and
// the bank sizes the codec refuses (the BP3 profile and the ABSYS banks are in
// tests/devices/absys_test.cpp).
#include "motionbus/biss/eds.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <utility>

using namespace motionbus;
using namespace motionbus::biss;

TEST_CASE("EDS common part: a checksum that does not match, when asked to verify; a short bank") {
  // the bank is the first 64 bytes of a longer array (a byte 0xEE after it): the evidence is
  // the bank's own checksum byte, 0x3F, not what follows it
  std::uint8_t bank[bank_size + 1U] = {};
  bank[bank_size] = 0xEE;
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

TEST_CASE("EDS common part and BP3 profile: == compares every field, each one alone") {
  // Each field changed alone makes the two unequal: a comparison that skipped a field (or
  // stopped at the first) would call them equal.
  const eds_common c;
  CHECK(c == eds_common{});
  std::uint8_t eds_common::*const common_fields[] = {
      &eds_common::version,       &eds_common::length,       &eds_common::user_bank_start,
      &eds_common::user_bank_end, &eds_common::channels,     &eds_common::validity,
      &eds_common::location,      &eds_common::profile_bank, &eds_common::data_length,
      &eds_common::data_format,   &eds_common::crc_poly};
  for (auto field : common_fields) {
    eds_common other = c;
    other.*field = static_cast<std::uint8_t>(other.*field + 1U);
    CHECK_FALSE(c == other);
    CHECK_FALSE(other == c);
  }

  const bp3_profile p;
  CHECK(p == bp3_profile{});
  std::uint8_t bp3_profile::*const bytes_fields[] = {
      &bp3_profile::version,           &bp3_profile::length,
      &bp3_profile::feedback1,         &bp3_profile::feedback2,
      &bp3_profile::power_on_delay_ms, &bp3_profile::positions,
      &bp3_profile::mt_length,         &bp3_profile::mt_format,
      &bp3_profile::coarse_length,     &bp3_profile::coarse_format,
      &bp3_profile::fine_length,       &bp3_profile::fine_format};
  for (auto field : bytes_fields) {
    bp3_profile other = p;
    other.*field = static_cast<std::uint8_t>(other.*field + 1U);
    CHECK_FALSE(p == other);
  }
  std::uint32_t bp3_profile::*const word_fields[] = {
      &bp3_profile::mt_count, &bp3_profile::sip_count, &bp3_profile::sip_resolution,
      &bp3_profile::crc_poly, &bp3_profile::crc_start};
  for (auto field : word_fields) {
    bp3_profile other = p;
    other.*field += 1U;
    CHECK_FALSE(p == other);
  }
  bp3_profile other = p;
  other.profile_id = 0x6321;
  CHECK_FALSE(p == other);
  other = p;
  other.type = encoder_type::linear;
  CHECK_FALSE(p == other);
}

TEST_CASE("BP3 profile: pulses per revolution and LSB size, 0 when 2^SIP_RES does not fit") {
  bp3_profile p;
  p.sip_count = 3;
  p.sip_resolution = 31;
  CHECK(p.pulses_per_revolution() == (std::uint64_t{3} << 31U));
  CHECK(p.lsb_nm() == 3.0 / 2147483648.0);  // exact: a power-of-two divisor (Approx takes 0)
  p.sip_resolution = 32;  // above what decode_bp3 accepts (20), a profile built by hand
  CHECK(p.pulses_per_revolution() == 0U);
  CHECK(p.lsb_nm() == 0.0);
}

TEST_CASE("bank_checksum: bytes 0x00..0x3E of a whole bank, or what a short view holds") {
  std::uint8_t bank[bank_size] = {};
  for (std::size_t i = 0; i < bank_size; ++i) {
    bank[i] = 1;
  }
  CHECK(bank_checksum(byte_view(bank, bank_size)) == 63U);  // byte 0x3F is the checksum
  CHECK(bank_checksum(byte_view(bank, 10)) == 10U);
  CHECK(bank_checksum(byte_view()) == 0U);
}

TEST_CASE("EDS common part: each invalid field alone is biss_eds") {
  // length, channels and data length 0, data length above 64 bits, CRC polynomial 0
  auto with = [](std::size_t at, std::uint8_t value) {
    std::uint8_t bank[bank_size] = {};
    REQUIRE(encode_eds_common(eds_common{}, mutable_byte_view(bank, bank_size)) == errc::ok);
    bank[at] = value;
    return decode_eds_common(byte_view(bank, bank_size));
  };
  CHECK(with(0x01, 1).is_complete());
  CHECK(with(0x01, 0).error() == errc::biss_eds);
  CHECK(with(0x10, 0).error() == errc::biss_eds);
  CHECK(with(0x15, 0).error() == errc::biss_eds);
  CHECK(with(0x15, 64).is_complete());
  CHECK(with(0x15, 65).error() == errc::biss_eds);
  CHECK(with(0x17, 0).error() == errc::biss_eds);
}

TEST_CASE("BP3 profile: each one-byte field written at its offset and read back from it") {
  struct at {
    std::uint8_t bp3_profile::*field;
    std::size_t offset;
  };
  const at fields[] = {{&bp3_profile::feedback1, 0x04},     {&bp3_profile::feedback2, 0x05},
                       {&bp3_profile::positions, 0x09},     {&bp3_profile::mt_format, 0x0B},
                       {&bp3_profile::coarse_format, 0x0D}, {&bp3_profile::fine_format, 0x0F}};
  for (const at& f : fields) {
    CAPTURE(f.offset);
    bp3_profile p;
    p.*f.field = 0x5A;  // a value no other field of the default profile holds
    std::uint8_t bank[bank_size] = {};
    REQUIRE(encode_bp3(p, bank) == errc::ok);
    CHECK(bank[f.offset] == 0x5A);
    const auto back = decode_bp3(bank);
    REQUIRE(back.is_complete());
    CHECK(back.value().*f.field == 0x5A);
    CHECK(back.value() == p);
  }
}

namespace {

// The low byte of the sum of bytes 0x00..0x3E: this library's checksum (eds.hpp).
std::uint8_t sum_of(const std::uint8_t (&bank)[bank_size]) {
  unsigned sum = 0;
  for (std::size_t i = 0; i < 0x3F; ++i) {
    sum += bank[i];
  }
  return static_cast<std::uint8_t>(sum);
}

// Every byte of a bank as expected, each one its own check (a failure names the byte).
void check_bank(const std::uint8_t (&bank)[bank_size], const std::uint8_t (&want)[bank_size]) {
  for (std::size_t i = 0; i < bank_size; ++i) {
    CAPTURE(i);
    CHECK(bank[i] == want[i]);
  }
}

}  // namespace

TEST_CASE("EDS common part: the default bank is the AMO ABSYS document's, byte by byte (§2.8)") {
  // §2.8's table: version 0x01, length 0x02, USER banks 0x84..0x84, one data channel, validity
  // 0x01, location 0x80, channel 1 described in bank 0x81, 0x20 data bits of format 0x00,
  // CPOLY 0x21; everything else 0, the checksum last.
  std::uint8_t want[bank_size] = {};
  want[0x00] = 0x01;
  want[0x01] = 0x02;
  want[0x02] = 0x84;
  want[0x03] = 0x84;
  want[0x10] = 0x01;
  want[0x11] = 0x01;
  want[0x12] = 0x80;
  want[0x14] = 0x81;
  want[0x15] = 0x20;
  want[0x16] = 0x00;
  want[0x17] = 0x21;
  want[0x3F] = sum_of(want);
  std::uint8_t bank[bank_size];
  for (std::uint8_t& b : bank) {
    b = 0xEE;
  }
  REQUIRE(encode_eds_common(eds_common{}, mutable_byte_view(bank, bank_size)) == errc::ok);
  check_bank(bank, want);
  const auto back = decode_eds_common(byte_view(bank, bank_size));
  REQUIRE(back.is_complete());
  CHECK(back.value() == eds_common{});
}

TEST_CASE("BP3 profile: the default bank byte by byte (§2.9), and EN_TYP linear is 0x01") {
  // §2.9's defaults, with BP_VER 0x03 (the newer of the two versions it describes; the ABSYS
  // device's own is devices/absys.hpp's) and the fields the table leaves to the device (EN_TYP
  // rotary 0x00, SIP_CNT, SIP_RES) 0: BP_LEN 0x01, BP_ID 0x63 0x20, FB1 0x01, FB2 0x02, PON_DLY
  // 0xFF, POS_NUM 0x01, FI_LEN 0x20, MT_CNT 0, CPOLY 0x00000021, CSTART 0.
  std::uint8_t want[bank_size] = {};
  want[0x00] = 0x03;
  want[0x01] = 0x01;
  want[0x02] = 0x63;
  want[0x03] = 0x20;
  want[0x04] = 0x01;
  want[0x05] = 0x02;
  want[0x06] = 0xFF;
  want[0x09] = 0x01;
  want[0x0E] = 0x20;
  want[0x1F] = 0x21;
  want[0x3F] = sum_of(want);
  std::uint8_t bank[bank_size] = {};
  REQUIRE(encode_bp3(bp3_profile{}, bank) == errc::ok);
  check_bank(bank, want);
  // §2.9.3: rotary 0x00, linear 0x01, both ways
  bp3_profile lin;
  lin.type = encoder_type::linear;
  REQUIRE(encode_bp3(lin, bank) == errc::ok);
  CHECK(bank[0x08] == 0x01);
  want[0x08] = 0x01;
  want[0x3F] = sum_of(want);
  const auto back = decode_bp3(want);
  REQUIRE(back.is_complete());
  CHECK(back.value().type == encoder_type::linear);
}

TEST_CASE("BP3 profile: layout() takes MT_LEN, CO_LEN + FI_LEN, and the CRC from CPOLY, CSTART") {
  // 12 multi-turn bits, 4 coarse and 16 fine single-turn bits; CPOLY 0x09 is bits (4:1) of
  // x^4 + x + 1 (BiSS notation 0x13: width 4, poly 0x3), CSTART 0x5; nE and nW, no alignment.
  bp3_profile p;
  p.mt_length = 12;
  p.coarse_length = 4;
  p.fine_length = 16;
  p.crc_poly = 0x09;
  p.crc_start = 0x5;
  const slave_layout l = p.layout();
  CHECK(l.multi_turn_bits == 12U);
  CHECK(l.single_turn_bits == 20U);
  CHECK(l.alignment_bits == 0U);
  CHECK(l.has_error);
  CHECK(l.has_warning);
  CHECK(l.crc.width == 4U);
  CHECK(l.crc.poly == 0x3U);
  CHECK(l.crc.start == 0x5U);
  CHECK(l.crc.inverted);
}

TEST_CASE("EDS common part: each field written at its offset and read back (§2.8)") {
  // Every field a value of its own, none the default's: each at its table offset.
  eds_common e;
  e.version = 0x11;
  e.length = 0x12;
  e.user_bank_start = 0x85;
  e.user_bank_end = 0x86;
  e.channels = 0x13;
  e.validity = 0x14;
  e.location = 0x87;
  e.profile_bank = 0x88;
  e.data_length = 0x30;
  e.data_format = 0x15;
  e.crc_poly = 0x16;
  std::uint8_t bank[bank_size] = {};
  REQUIRE(encode_eds_common(e, mutable_byte_view(bank, bank_size)) == errc::ok);
  const std::pair<std::size_t, std::uint8_t> at[] = {
      {0x00, 0x11}, {0x01, 0x12}, {0x02, 0x85}, {0x03, 0x86}, {0x10, 0x13}, {0x11, 0x14},
      {0x12, 0x87}, {0x14, 0x88}, {0x15, 0x30}, {0x16, 0x15}, {0x17, 0x16}};
  for (const auto& f : at) {
    CAPTURE(f.first);
    CHECK(bank[f.first] == f.second);
  }
  const auto back = decode_eds_common(byte_view(bank, bank_size));
  REQUIRE(back.is_complete());
  CHECK(back.value() == e);
}

TEST_CASE("BP3 profile: lengths and 32-bit fields at their offsets, big-endian; the bounds") {
  // §2.9: MT_LEN 0x0A, CO_LEN 0x0C, FI_LEN 0x0E, BP_ID 0x02..0x03, MT_CNT 0x10..0x13,
  // SIP_CNT 0x14..0x17, SIP_RES 0x18..0x1B, CPOLY 0x1C..0x1F, CSTART 0x20..0x23, each most
  // significant byte first. SIP_RES up to 20 (§2.9.4), 64 data bits in all, CPOLY of at most
  // 16 bits (x^16 at most: bits (16:1) of the notation).
  bp3_profile p;
  p.mt_length = 12;
  p.coarse_length = 4;
  p.fine_length = 16;
  p.profile_id = 0x6320;
  p.mt_count = 0x0A0B0C0D;
  p.sip_count = 0x01020304;
  p.sip_resolution = 20;
  p.crc_poly = 0x09;
  p.crc_start = 0x0005;
  std::uint8_t bank[bank_size] = {};
  REQUIRE(encode_bp3(p, bank) == errc::ok);
  const std::pair<std::size_t, std::uint8_t> at[] = {
      {0x0A, 12},   {0x0C, 4},    {0x0E, 16},   {0x02, 0x63}, {0x03, 0x20}, {0x10, 0x0A},
      {0x11, 0x0B}, {0x12, 0x0C}, {0x13, 0x0D}, {0x14, 0x01}, {0x15, 0x02}, {0x16, 0x03},
      {0x17, 0x04}, {0x18, 0x00}, {0x1B, 20},   {0x1F, 0x09}, {0x22, 0x00}, {0x23, 0x05}};
  for (const auto& f : at) {
    CAPTURE(f.first);
    CHECK(bank[f.first] == f.second);
  }
  const auto back = decode_bp3(bank);
  REQUIRE(back.is_complete());
  CHECK(back.value() == p);
  // the bounds, each alone: 64 data bits and a 16-bit CPOLY accepted, one more refused
  const auto decoded = [](const bp3_profile& q) {
    std::uint8_t b[bank_size] = {};
    REQUIRE(encode_bp3(q, b) == errc::ok);
    return decode_bp3(b);
  };
  bp3_profile q = p;
  q.fine_length = 48;  // 12 + 4 + 48 = 64
  CHECK(decoded(q).is_complete());
  q.fine_length = 49;
  CHECK(decoded(q).error() == errc::biss_eds);
  q = p;
  q.crc_poly = 0xFFFF;  // x^16 + ... + 1: 16 bits
  CHECK(decoded(q).is_complete());
  CHECK(decoded(q).value().layout().crc.width == 16U);
  q.crc_poly = 0x10000;  // x^17: 17 bits
  CHECK(decoded(q).error() == errc::biss_eds);
  q = p;
  q.sip_resolution = 21;
  CHECK(decoded(q).error() == errc::biss_eds);
}
