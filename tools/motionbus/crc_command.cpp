// `motionbus crc <tformat|modbus|biss6|biss4> <input>`
#include <motionbus/core/crc.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"

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
cli::outcome crc_of_bits(const std::string& input) {
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
  cli::json_object f;
  f.add("crc", static_cast<std::int64_t>(c.value()));
  return cli::outcome::success(f);
}

template <class Crc>
cli::outcome crc_of_hex(const std::string& input) {
  std::string error;
  const auto bytes = cli::parse_hex(input, error);
  if (!bytes) {
    return cli::outcome::failure(error);
  }
  cli::json_object f;
  f.add("crc",
        static_cast<std::int64_t>(Crc::compute(mb::byte_view(bytes->data(), bytes->size()))));
  return cli::outcome::success(f);
}

}  // namespace

int command_crc(const std::vector<std::string>& args) {
  if (args.size() != 4) {
    throw cli::usage_error{"usage: motionbus crc <tformat|modbus|biss6|biss4> <input|->"};
  }
  const std::string& which = args[2];
  cli::outcome (*handler)(const std::string&) = nullptr;
  if (which == "tformat") {
    handler = &crc_of_hex<mb::crc8_tformat<>>;
  } else if (which == "modbus") {
    handler = &crc_of_hex<mb::crc16_modbus<>>;
  } else if (which == "biss6") {
    handler = &crc_of_bits<mb::crc6_biss<>>;
  } else if (which == "biss4") {
    handler = &crc_of_bits<mb::crc4_biss<>>;
  } else {
    throw cli::usage_error{"unknown CRC '" + which + "' (tformat, modbus, biss6, biss4)"};
  }
  return cli::run_inputs(args[3], handler);
}
