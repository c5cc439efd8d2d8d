// `motionbus crc <tformat|modbus|biss6|biss4> <input|->`
#include <motionbus/core/crc.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "cli.hpp"
#include "options.hpp"

namespace mb = motionbus;

namespace {

// Packs a 0/1 list into bytes, first bit in the MSB of the first byte.
std::vector<std::uint8_t> pack_msb_first(const std::vector<std::uint8_t>& bits) {
  std::vector<std::uint8_t> bytes((bits.size() + 7U) / 8U, 0);
  mb::bit_writer w(mb::mutable_byte_view(bytes.data(), bytes.size()), mb::bit_order::msb_first);
  for (const std::uint8_t b : bits) {
    (void)w.write_bit(b != 0);  // cannot fail: the buffer holds every bit
  }
  return bytes;
}

template <class Crc>
cli::outcome crc_of_bits(const std::string& input, const cli::no_options&) {
  std::string error;
  const auto bits = cli::parse_bits(input, error);
  if (!bits) {
    return cli::outcome::failure(error);
  }
  const auto bytes = pack_msb_first(*bits);
  Crc c;
  if (c.update_stream(mb::byte_view(bytes.data(), bytes.size()), mb::bit_order::msb_first, 0,
                      bits->size()) != mb::errc::ok) {
    return cli::outcome::failure("truncated");
  }
  cli::record f;
  f.hex("crc", c.value(), 2);
  return cli::outcome::success(f);
}

// The CRC as a number, and for a 16-bit CRC also as the wire bytes: low byte first, as the
// Modbus CRC is appended (Modbus over Serial Line V1.02 §2.5.1.2): crc=0x8776 wire=[76 87].
template <class Crc>
cli::outcome crc_of_hex(const std::string& input, const cli::no_options&) {
  std::string error;
  const auto bytes = cli::parse_hex(input, error);
  if (!bytes) {
    return cli::outcome::failure(error);
  }
  const auto crc = Crc::compute(mb::byte_view(bytes->data(), bytes->size()));
  cli::record f;
  f.hex("crc", crc, Crc::spec::width > 8 ? 4 : 2);
  if (Crc::spec::width > 8) {
    const std::uint8_t wire[2] = {static_cast<std::uint8_t>(crc & 0xFFU),
                                  static_cast<std::uint8_t>((crc >> 8U) & 0xFFU)};
    f.bytes("wire", wire, sizeof wire);
  }
  return cli::outcome::success(f);
}

}  // namespace

namespace cli {

protocol_entries crc_entries() {
  protocol_entries e;
  e.decoders.push_back(
      lines("crc", "tformat", "", "T-format CRC-8 of hex bytes", &crc_of_hex<mb::crc8_tformat<>>));
  e.decoders.push_back(lines("crc", "modbus", "",
                             "Modbus CRC-16 of hex bytes, and its bytes as sent (low byte first)",
                             &crc_of_hex<mb::crc16_modbus<>>));
  e.decoders.push_back(lines("crc", "biss6", "",
                             "BiSS-C CRC6 (x^6+x+1) of a 0/1 bit string, as sent (inverted)",
                             &crc_of_bits<mb::crc6_biss<>>));
  e.decoders.push_back(lines("crc", "biss4", "",
                             "BiSS-C CRC4 (x^4+x+1) of a 0/1 bit string, as sent (inverted)",
                             &crc_of_bits<mb::crc4_biss<>>));
  for (std::size_t i = 2; i < 4; ++i) {
    e.decoders[i].input_help = "0/1 bits, first bit first";
  }
  return e;
}

}  // namespace cli
