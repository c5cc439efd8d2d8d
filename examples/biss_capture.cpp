// Decoding BiSS-C captures on a host, as logic analyzers export them: one capture per line,
// either the 0/1 samples of SL from the first clock, or hex words (MSB first) prefixed with
// "hex:" and optionally followed by "/<bits>". Every frame is decoded with the AMO ABSYS layout
// (32-bit position, nE, nW, CRC6 0x43) unless --data-bits N is given.
//
//   motionbus_example_biss_capture [--data-bits N] [capture ...]     (no capture: read stdin)
//
// Example:  motionbus_example_biss_capture 1100100000000000000000001111000100100000011101111
#include <motionbus/biss.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace mb = motionbus;
namespace bs = motionbus::biss;

namespace {

bool parse(const std::string& text, std::vector<std::uint8_t>& samples) {
  samples.clear();
  if (text.rfind("hex:", 0) == 0) {
    std::string digits = text.substr(4);
    std::size_t limit = std::string::npos;
    const auto slash = digits.find('/');
    if (slash != std::string::npos) {
      limit = std::strtoul(digits.c_str() + slash + 1, nullptr, 10);
      digits.resize(slash);
    }
    for (std::size_t i = 0; i < digits.size(); ++i) {
      const char c = digits[i];
      if (c == '0' && i + 1 < digits.size() && (digits[i + 1] == 'x' || digits[i + 1] == 'X')) {
        ++i;
        continue;
      }
      const int v = (c >= '0' && c <= '9')   ? c - '0'
                    : (c >= 'a' && c <= 'f') ? c - 'a' + 10
                    : (c >= 'A' && c <= 'F') ? c - 'A' + 10
                                             : -1;
      if (v < 0) {
        if (c == ' ' || c == ',' || c == '_') {
          continue;
        }
        return false;
      }
      for (int b = 3; b >= 0; --b) {
        samples.push_back(
            static_cast<std::uint8_t>((static_cast<unsigned>(v) >> static_cast<unsigned>(b)) & 1U));
      }
    }
    if (limit < samples.size()) {
      samples.resize(limit);
    }
    return !samples.empty();
  }
  for (const char c : text) {
    if (c == '0' || c == '1') {
      samples.push_back(static_cast<std::uint8_t>(c - '0'));
    } else if (c != ' ' && c != '_') {
      return false;
    }
  }
  return !samples.empty();
}

void decode(const std::string& text, const bs::slave_layout& layout) {
  std::vector<std::uint8_t> samples;
  if (!parse(text, samples)) {
    std::printf("%-12s not a capture\n", "?");
    return;
  }
  // Pack the samples MSB first into 32-bit words, as an SPI master's DMA buffer holds them.
  std::vector<std::uint32_t> words((samples.size() + 31U) / 32U, 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    words[i / 32U] |= static_cast<std::uint32_t>(samples[i]) << (31U - i % 32U);
  }
  const auto r = bs::decode_frame(mb::span<const std::uint32_t>(words.data(), words.size()),
                                  samples.size(), layout);
  const bs::slave_data& d = r->slaves[0];
  if (r.is_incomplete()) {
    std::printf("incomplete: %zu more samples needed\n", r.needed_bits());
  } else if (r.is_failed()) {
    std::printf("error: %s", mb::to_string(r.error()));
    if (r.error() == mb::errc::crc_mismatch) {
      std::printf(" (received 0x%02X, data calls for 0x%02X)", static_cast<unsigned>(r.received()),
                  static_cast<unsigned>(r.expected()));
    }
    std::printf("\n");
  } else {
    std::printf("position %llu  line delay %zu bits  Ack %zu  CDS %d  %s%s  CRC 0x%02X ok\n",
                static_cast<unsigned long long>(d.single_turn), r->line_delay, r->ack_bits(),
                r->cds ? 1 : 0, d.error() ? "ERROR " : "", d.warning() ? "WARNING" : "",
                static_cast<unsigned>(d.crc));
  }
}

}  // namespace

int main(int argc, char** argv) {
  bs::slave_layout layout = bs::absys_layout;
  std::vector<std::string> captures;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--data-bits" && i + 1 < argc) {
      layout.single_turn_bits = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    } else {
      captures.push_back(a);
    }
  }
  if (layout.validate() != mb::errc::ok) {
    std::fprintf(stderr, "invalid layout\n");
    return 2;
  }
  if (captures.empty()) {
    for (std::string line; std::getline(std::cin, line);) {
      if (!line.empty()) {
        decode(line, layout);
      }
    }
  }
  for (const auto& c : captures) {
    decode(c, layout);
  }
  return 0;
}
