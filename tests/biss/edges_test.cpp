// BiSS-C at its edges: a layout without CRC, 64 data bits plus status (the CRC over more
// than one 64-bit step), invalid layouts refused by the encoder, and the ABSYS emulator's
// registers read directly.
#include <doctest/doctest.h>

#include <cstdint>

#include "motionbus/biss/codec.hpp"
#include "motionbus/biss/eds.hpp"
#include "motionbus/devices/absys_emulator.hpp"

using namespace motionbus;
using namespace motionbus::biss;
namespace ab = motionbus::devices::absys;

namespace {

// Encodes one frame of `layout` with `values` and decodes it back.
decode_result<frame_info> round_trip(const slave_layout& layout, const slave_values& values,
                                     slave_data& d) {
  std::uint32_t words[6] = {};
  line_options line;
  line.idle_bits = 3;
  line.ack_bits = 2;
  const auto n = encode_frame(layout, values, span<std::uint32_t>(words, 6), line);
  REQUIRE(n.ok());
  return decode_frame(span<const std::uint32_t>(words, 6), n.value(), layout, d);
}

}  // namespace

TEST_CASE("BiSS-C layouts: no CRC, and 64 data bits with nE and nW") {
  slave_layout plain;
  plain.crc = crc_format{0, 0, 0, false};
  slave_values v;
  v.single_turn = 0x1234;
  slave_data d;
  auto r = round_trip(plain, v, d);
  REQUIRE(r.is_complete());
  CHECK(d.single_turn == 0x1234);
  CHECK(d.crc == 0);
  CHECK(d.crc_computed == 0);

  slave_layout wide;
  wide.multi_turn_bits = 32;
  wide.single_turn_bits = 32;
  v.multi_turn = 0xCAFEF00DU;
  v.single_turn = 0x89ABCDEFU;
  v.ne = false;
  r = round_trip(wide, v, d);
  REQUIRE(r.is_complete());
  CHECK(d.multi_turn == 0xCAFEF00DU);
  CHECK(d.single_turn == 0x89ABCDEFU);
  CHECK(d.error());
  CHECK(d.crc_ok());
}

TEST_CASE("BiSS-C encoder: an invalid layout is refused, and encoded_bits says 0") {
  slave_layout bad;
  bad.single_turn_bits = 0;  // no data bits at all
  const slave_layout chain[1] = {bad};
  CHECK(encoded_bits(span<const slave_layout>(chain, 1), line_options{}) == 0U);
  std::uint32_t words[4] = {};
  CHECK(encode_frame(bad, slave_values{}, span<std::uint32_t>(words, 4)).error() ==
        errc::biss_layout);
}

TEST_CASE("ABSYS emulator registers: banks, command, preset, reserve, undefined addresses") {
  ab::emulator e;
  ab::emulator::registers regs(e);
  regs.write(ab::reg::bank_select, ab::bank::eds_reserved_3);
  CHECK(e.selected_bank() == ab::bank::eds_reserved_3);
  CHECK(regs.read(0x00) == 0);  // reserved EDS banks read 0x00
  regs.write(ab::reg::eds_bank, 0x81);
  CHECK(regs.read(ab::reg::eds_bank) == 0x81);
  CHECK(regs.read(ab::reg::command) == 0);
  CHECK(regs.read(ab::reg::preset_mode) == e.read_register(ab::reg::preset_mode));
  e.set_functional_reserve(200, 1);
  CHECK(regs.read(ab::reg::functional_reserve) == 200);
  CHECK(regs.read(ab::reg::functional_reserve_indicator) == 1);
  CHECK(regs.read(0x50) == 0);         // no register there
  regs.write(ab::reg::command, 0x77);  // no such command: nothing happens
  CHECK(e.offset() == 0);
}

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
