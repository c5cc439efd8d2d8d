// Compile-time suite for the core: every assertion is evaluated by the compiler, where constant
// evaluation also rejects undefined behaviour. Compiling this file is the test.
#include <cstdint>

#include "motionbus/core.hpp"

namespace mb = motionbus;

namespace {

constexpr std::uint8_t check_input[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

// --- CRC check values (reveng CRC catalogue; BiSS values from the independent reference in
// tests/support/reference_crc.hpp, re-checked at run time by tests/core/crc_test.cpp) ---------
template <template <mb::crc_table_size> class Crc, std::uint32_t Expected>
constexpr bool all_tables(mb::byte_view data) {
  return Crc<mb::crc_table_size::byte>::compute(data) == Expected &&
         Crc<mb::crc_table_size::nibble>::compute(data) == Expected &&
         Crc<mb::crc_table_size::bitwise>::compute(data) == Expected;
}

static_assert(all_tables<mb::crc16_modbus, 0x4B37>(check_input), "CRC-16/MODBUS check value");
static_assert(all_tables<mb::crc8_tformat, 0x31>(check_input), "T-format CRC = XOR of the bytes");
static_assert(all_tables<mb::crc6_biss, 0x2E>(check_input), "BiSS CRC6 check value");
static_assert(all_tables<mb::crc4_biss, 0x1>(check_input), "BiSS CRC4 check value");

// Modbus over Serial Line V1.02: 11 03 00 6B 00 03 is followed by CRC bytes 76 87.
constexpr std::uint8_t modbus_frame[] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03};
static_assert(mb::crc16_modbus<>::compute(modbus_frame) == 0x8776, "Modbus example frame");
static_assert(mb::crc16_modbus<mb::crc_table_size::slice4>::compute(check_input) == 0x4B37,
              "CRC-16/MODBUS, slice-by-4");
static_assert(mb::crc16_modbus<mb::crc_table_size::slice8>::compute(check_input) == 0x4B37,
              "CRC-16/MODBUS, slice-by-8");
static_assert(mb::crc<mb::crc_spec<32, 0x04C11DB7, 0xFFFFFFFF, true, true, 0xFFFFFFFF>,
                      mb::crc_table_size::slice4>::compute(check_input) == 0xCBF43926U,
              "CRC-32, slice-by-4");

// A BiSS-C sensor frame's CRC6 (34 bits: position, nE, nW) and bit fields of other lengths:
// the byte table (byte steps, whatever path the count selects) agrees with the bitwise engine,
// also after a first field that leaves the register non-zero.
constexpr bool byte_steps_agree(std::uint64_t v, unsigned n) {
  using byte = mb::crc6_biss<mb::crc_table_size::byte>;
  using bitwise = mb::crc6_biss<mb::crc_table_size::bitwise>;
  return byte::compute_bits(v, n) == bitwise::compute_bits(v, n) &&
         byte().update_bits(0x1A5, 9).update_bits(v, n).value() ==
             bitwise().update_bits(0x1A5, 9).update_bits(v, n).value();
}
static_assert(byte_steps_agree((0x12345678ULL << 2U) | 3U, 34), "BiSS CRC6, 34 bits");
static_assert(byte_steps_agree(0xFEDCBA9876543210ULL, 64) && byte_steps_agree(0xA5, 8) &&
                  byte_steps_agree(0x1FFFF, 17) && byte_steps_agree(0x5, 3),
              "BiSS CRC6, 64, 8, 17 and 3 bits");

// A frame with its CRC appended (low byte first) has residue 0 for CRC-16/MODBUS.
constexpr std::uint8_t modbus_with_crc[] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87};
static_assert(mb::crc16_modbus<>::compute(modbus_with_crc) == 0x0000, "Modbus residue");
// ... and with the slice walks, whose last step ends at the frame's end (eight bytes)
static_assert(mb::crc16_modbus<mb::crc_table_size::slice4>::compute(modbus_with_crc) == 0x0000 &&
                  mb::crc16_modbus<mb::crc_table_size::slice8>::compute(modbus_with_crc) == 0x0000,
              "Modbus residue, slice-by-4 and slice-by-8");

// T-format: a request CF alone (ID0 = 0x02) has CRC 0x02; XOR of any bytes.
constexpr std::uint8_t tformat_bytes[] = {0x02, 0x20, 0xB4};
static_assert(mb::crc8_tformat<>::compute(tformat_bytes) == (0x02 ^ 0x20 ^ 0xB4), "T-format XOR");

// Reflected and refin != refout catalogue entries.
static_assert(mb::crc<mb::crc_spec<12, 0x80F, 0, false, true, 0>>::compute(check_input) == 0xDAF,
              "CRC-12/UMTS");
static_assert(mb::crc<mb::crc_spec<5, 0x05, 0x1F, true, true, 0x1F>,
                      mb::crc_table_size::nibble>::compute(check_input) == 0x19,
              "CRC-5/USB");
static_assert(mb::crc<mb::crc_spec<32, 0x04C11DB7, 0xFFFFFFFF, true, true, 0xFFFFFFFF>>::compute(
                  check_input) == 0xCBF43926U,
              "CRC-32/ISO-HDLC");

// Bit granularity: feeding 8 bits at a time equals bytes; a 34-bit BiSS word by pieces.
constexpr bool bits_equal_bytes() {
  mb::crc16_modbus<mb::crc_table_size::nibble> a;
  for (std::uint8_t b : check_input) {
    a.update_bits(b, 8);
  }
  return a.value() == 0x4B37;
}
static_assert(bits_equal_bytes(), "update_bits(byte, 8) == update(byte)");

constexpr bool biss_pieces() {
  const std::uint64_t word = (std::uint64_t{0x12345678} << 2U) | 0x3U;
  mb::crc6_biss<> whole;
  whole.update_bits(word, 34);
  mb::crc6_biss<mb::crc_table_size::bitwise> pieces;
  pieces.update_bits(word >> 20U, 14).update_bits(word & 0xFFFFFU, 20);
  return whole.value() == pieces.value();
}
static_assert(biss_pieces(), "CRC6 over bits in pieces");

constexpr bool stream_crc() {
  std::uint8_t buffer[6] = {};
  mb::bit_writer w(buffer, mb::bit_order::msb_first, 3);
  for (std::uint8_t b : check_input) {
    if (b > '5') {
      break;
    }
    if (w.write(b, 8) != mb::errc::ok) {
      return false;
    }
  }
  mb::crc6_biss<> c;
  if (c.update_stream(mb::byte_view(buffer), mb::bit_order::msb_first, 3, 40) != mb::errc::ok) {
    return false;
  }
  return c.value() == mb::crc6_biss<>::compute(mb::byte_view(check_input, 5));
}
static_assert(stream_crc(), "CRC over a bit stream at an offset");

// --- bit I/O ---------------------------------------------------------------------------------
constexpr std::uint8_t bytes[] = {0xA5, 0x3C, 0x0F};

constexpr std::uint64_t read_at(mb::bit_order order, std::size_t offset, unsigned count) {
  mb::bit_reader r(bytes, order, offset);
  return r.read(count).value();
}
static_assert(read_at(mb::bit_order::msb_first, 0, 16) == 0xA53C, "msb_first is big-endian");
static_assert(read_at(mb::bit_order::lsb_first, 0, 16) == 0x3CA5, "lsb_first is little-endian");
static_assert(read_at(mb::bit_order::msb_first, 4, 8) == 0x53, "msb_first at a nibble");
static_assert(read_at(mb::bit_order::lsb_first, 4, 8) == 0xCA, "lsb_first at a nibble");
static_assert(read_at(mb::bit_order::msb_first, 23, 1) == 1, "last bit");

constexpr bool truncation_is_an_error() {
  mb::bit_reader r(bytes, mb::bit_order::msb_first, 20);
  const auto too_far = r.read(5);
  return !too_far.ok() && too_far.error() == mb::errc::truncated && r.position() == 20 &&
         r.read(4).ok() && r.remaining() == 0;
}
static_assert(truncation_is_an_error(), "truncation");

constexpr bool write_then_read() {
  std::uint16_t words[2] = {0xFFFF, 0xFFFF};
  mb::basic_bit_writer<std::uint16_t> w(words, mb::bit_order::lsb_first, 5);
  if (w.write(0x2AAAAU, 18) != mb::errc::ok || w.write(1, 10) != mb::errc::buffer_too_small) {
    return false;
  }
  mb::basic_bit_reader<std::uint16_t> r(words, mb::bit_order::lsb_first, 5);
  return r.read(18).value() == 0x2AAAAU && words[0] == static_cast<std::uint16_t>(0x555F);
}
static_assert(write_then_read(), "write then read, neighbours untouched");

static_assert(mb::reverse_bits(std::uint8_t{0x1D}) == 0xB8, "reverse byte");
static_assert(mb::reverse_bits(0x0BULL, 4) == 0xD, "reverse 4 bits");

// --- results ---------------------------------------------------------------------------------
constexpr mb::decode_result<int> need() {
  return mb::need_input{3};
}
constexpr mb::decode_result<int> fail() {
  return mb::decode_failure{mb::errc::crc_mismatch, 2, 1, 2};
}
static_assert(need().is_incomplete() && need().needed() == 3, "incomplete");
static_assert(fail().is_failed() && fail().error() == mb::errc::crc_mismatch &&
                  fail().consumed() == 2,
              "failed");
static_assert(mb::decode_result<int>::complete(5, 4).value() == 5, "complete");
constexpr mb::decode_result<int> built(int step) {
  mb::decode_result<int> r = mb::need_input{1};
  mb::decode_result<int>::outcome o(r);
  if (step == 0) {
    o.need(3);
  } else if (step == 1) {
    o.fail(mb::errc::crc_mismatch, 2, 1, 2);
  } else if (step == 2) {
    o.complete_value(4, 5);
  } else {
    o.complete_in_place(4) = 6;  // in constant evaluation, value-initialised first
  }
  return r;
}
static_assert(built(0).is_incomplete() && built(0).needed() == 3, "built in place: incomplete");
static_assert(built(1).is_failed() && built(1).error() == mb::errc::crc_mismatch &&
                  built(1).consumed() == 2 && built(1).received() == 2,
              "built in place: failed");
static_assert(built(2).is_complete() && built(2).value() == 5 && built(2).consumed() == 4,
              "built in place: complete");
static_assert(built(3).is_complete() && built(3).value() == 6, "built in place: in place");
static_assert(mb::decode_result<int, mb::input_unit::bits>::complete(1, 9).consumed_bits() == 9,
              "a bit-counted result");
static_assert(mb::result<int>(mb::errc::truncated).error() == mb::errc::truncated, "result error");
static_assert(mb::to_string(mb::errc::crc_mismatch)[0] == 'c', "error names");

}  // namespace

int main() {
  return 0;
}
