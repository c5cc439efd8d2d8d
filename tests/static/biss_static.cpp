// Compile-time suite for BiSS-C and the ABSYS profile: CRC vectors, layouts, a frame encoded
// and decoded by the compiler, the serial number decoder.
#include <cstdint>

#include "motionbus/biss.hpp"
#include "motionbus/devices/absys.hpp"

namespace mb = motionbus;
namespace bs = motionbus::biss;
namespace ab = motionbus::devices::absys;

namespace {

// Worked by hand from the definition, CRC = M(x) * x^w mod P(x), MSB first, then inverted.
// CRC6 0x43 over position 0x00000000, nE = 1, nW = 1: M = x + 1, M * x^6 = x^7 + x^6; with
// x^6 = x + 1 and x^7 = x^2 + x that is x^2 + 1 = 0b000101, on the wire 0b111010 = 0x3A.
static_assert(mb::crc6_biss<>::compute_bits(0x3, 34) == 0x3A, "CRC6 of zero position, nE nW 1");
static_assert(bs::wire_crc(bs::crc6_43, 0, 32, 0x3, 2) == 0x3A, "wire CRC, table path");
static_assert(bs::wire_crc(bs::crc_from_biss_notation(0x43, 0, bs::crc_output::inverted), 0, 32,
                           0x3, 2) == 0x3A,
              "wire CRC from the BiSS notation");
static_assert(mb::dynamic_crc(bs::crc6_43.parameters()).update_bits(0x3, 34).value() == 0x3A,
              "run-time CRC, bit by bit");
// CRC4 0x13 of a control frame's CTS = 1, ID 000, ADR 0000000 (11 bits): M = x^10,
// M * x^4 = x^14; with x^4 = x + 1, x^8 = x^2 + 1, x^12 = x^3 + x^2 + x + 1, x^14 = x^3 + 1 =
// 0b1001, on the wire 0b0110.
static_assert(mb::crc4_biss<>::compute_bits(0x400, 11) == 0x6, "CRC4 of CTS=1, ID 0, ADR 0");

static_assert(bs::crc_from_biss_notation(0x43) == bs::crc6_43, "0x43 is x^6 + x + 1");
static_assert(bs::crc_from_eds(0x21) == bs::crc6_43, "EDS CPOLY 0x21 is 0x43");
static_assert(bs::absys_layout.frame_bits() == 40, "ABSYS: 32 + nE + nW + CRC6");
static_assert(bs::slave_layout{}.crc == bs::crc6_43, "the ABSYS layout is the default");

constexpr bool frame_round_trip() {
  std::uint32_t words[3] = {};
  bs::line_options line;
  line.line_delay = 5;
  line.ack_bits = 3;
  line.cds = true;
  bs::slave_values v;
  v.single_turn = 0xDEADBEEF;
  v.nw = false;
  const auto n = bs::encode_frame(bs::absys_layout, v, mb::span<std::uint32_t>(words, 3), line);
  if (!n.ok() || *n != 5 + 3 + 2 + 40) {
    return false;
  }
  const auto r = bs::decode_frame(mb::span<const std::uint32_t>(words, 3), *n, bs::absys_layout);
  const bs::slave_data& d = r->slaves[0];
  return r.is_complete() && r->start == 8 && r->line_delay == 5 && r->cds && r->size() == 1 &&
         d.single_turn == 0xDEADBEEF && d.ne && !d.nw && d.crc_ok() && r.consumed_bits() == 50;
}
static_assert(frame_round_trip(), "encode -> decode at compile time");

// decode_frame takes the capture as span<const Word>, span<Word> or a plain array, as the
// Modbus and T-format decoders take arrays (chain and single-slave forms, 8- to 64-bit words);
// encode_frame writes into a plain array. Each form gives the same frame.
template <class Word>
constexpr bool capture_forms() {
  Word words[128 / (8 * sizeof(Word))] = {};
  constexpr std::size_t count = sizeof words / sizeof words[0];
  bs::line_options line;
  line.line_delay = 3;
  line.ack_bits = 2;
  bs::slave_values v;
  v.single_turn = 0x01234567;
  const auto n = bs::encode_frame(bs::absys_layout, v, words, line);  // a plain array
  if (!n.ok()) {
    return false;
  }
  const Word(&cwords)[count] = words;
  const bs::slave_layout chain[1] = {bs::absys_layout};
  const mb::span<Word> writable(words, count);
  const mb::span<const Word> readable(words, count);
  const auto same = [](const auto& r) {
    return r.is_complete() && r->line_delay == 3 && r->ack_bits() == 2 && r->size() == 1 &&
           r->slaves[0].single_turn == 0x01234567 && r->slaves[0].crc_ok();
  };
  return same(bs::decode_frame(readable, *n, bs::absys_layout)) &&
         same(bs::decode_frame(writable, *n, bs::absys_layout)) &&
         same(bs::decode_frame(words, *n, bs::absys_layout)) &&
         same(bs::decode_frame(cwords, *n, bs::absys_layout)) &&
         same(bs::decode_frame(writable, *n, chain)) && same(bs::decode_frame(words, *n, chain));
}
static_assert(capture_forms<std::uint8_t>(), "arrays and spans of 8-bit words");
static_assert(capture_forms<std::uint16_t>(), "arrays and spans of 16-bit words");
static_assert(capture_forms<std::uint32_t>(), "arrays and spans of 32-bit words");
static_assert(capture_forms<std::uint64_t>(), "arrays and spans of 64-bit words");

constexpr bool truncated_and_no_ack() {
  const std::uint8_t ones[4] = {0xFF, 0xFF, 0xFF, 0xFF};
  bs::decode_options o;
  o.max_line_delay = 20;
  return bs::decode_frame(mb::span<const std::uint8_t>(ones, 4), 32, bs::absys_layout, o).error() ==
             mb::errc::biss_no_ack &&
         bs::decode_frame(mb::span<const std::uint8_t>(ones, 4), 16, bs::absys_layout, o)
             .is_incomplete();
}
static_assert(truncated_and_no_ack(), "no Ack vs need more input");

// ABSYS serial number (ABSYS document §2.4, registers 0x44..0x4B): three ASCII bytes, the
// number most significant byte first (the text's 0x00BC614E = 12345678), one ASCII byte.
constexpr std::uint8_t serial_regs[ab::serial_number_size] = {'A',  'T',  'J',  0x00,
                                                              0xBC, 0x61, 0x4E, 'C'};
constexpr bool serial_number_decodes() {
  const auto s = ab::decode_serial_number(serial_regs);
  return s.is_complete() && s.consumed() == 8 && s->prefix[0] == 'A' && s->prefix[1] == 'T' &&
         s->prefix[2] == 'J' && s->number == 12345678U && s->suffix == 'C';
}
static_assert(serial_number_decodes(), "serial number: ASCII, 0x00BC614E, ASCII");
static_assert(ab::decode_serial_number(mb::byte_view(serial_regs, 7)).needed() == 1U,
              "seven bytes are too few: one more is needed");
constexpr std::uint8_t serial_not_ascii[ab::serial_number_size] = {'A', 'T', 0x80, 0, 0, 0, 1, 'C'};
static_assert(ab::decode_serial_number(serial_not_ascii).error() == mb::errc::out_of_range,
              "a byte above 0x7F where ASCII belongs");

}  // namespace

int main() {
  return 0;
}
