// BiSS-C in the CLI:
//   decode biss csd <bits> [layout options]                the 0/1 samples on SL from the first
//   clock decode biss csd --hex <words> [--bits N] [layout options]  the same as hex words, MSB
//   first encode biss csd --position N [--ne B] [--nw B] [--ack N] [--cds B] [--line-delay N]
//   [layout options]
// Layout options (default: AMO ABSYS): --data-bits N (32), --crc-bits N (6), --crc-poly HEX
// (BiSS notation with the x^N term, 43; the form without it is accepted too), --crc-start N (0),
// --no-crc-invert.
#include <motionbus/biss.hpp>
#include <motionbus/core/errc.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "biss_io.hpp"
#include "capture.hpp"
#include "cli.hpp"
#include "options_bind.hpp"

namespace mb = motionbus;
namespace bs = motionbus::biss;

namespace {

// A hexadecimal number with or without 0x.
std::optional<std::uint64_t> parse_hex_number(std::string t) {
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t = t.substr(2);
  }
  if (t.empty() || t.size() > 16) {
    return std::nullopt;
  }
  std::uint64_t v = 0;
  for (const char c : t) {
    const int d = (c >= '0' && c <= '9')   ? c - '0'
                  : (c >= 'a' && c <= 'f') ? c - 'a' + 10
                  : (c >= 'A' && c <= 'F') ? c - 'A' + 10
                                           : -1;
    if (d < 0) {
      return std::nullopt;
    }
    v = (v << 4U) | static_cast<std::uint64_t>(d);
  }
  return v;
}

}  // namespace

namespace biss_io {

void layout_options::bind(CLI::App& app) {
  cli::number(app, "data-bits", data_bits, 1, 64);
  cli::number(app, "crc-bits", crc_bits, 0, bs::max_crc_bits);
  cli::text(app, "crc-poly", crc_poly);
  cli::number(app, "crc-start", crc_start, 0, 0xFFFFFFFFU);
  cli::flag(app, "no-crc-invert", no_crc_invert);
}

bs::slave_layout layout_options::layout() const {
  bs::slave_layout l = bs::absys_layout;
  l.single_turn_bits = data_bits;
  const unsigned width = crc_bits;
  std::uint64_t poly = 0x43;
  if (crc_poly) {
    const auto v = parse_hex_number(*crc_poly);
    if (!v) {
      throw cli::usage_error{"--crc-poly needs a hexadecimal polynomial such as 43"};
    }
    poly = *v;
  } else if (width != 6) {
    throw cli::usage_error{"--crc-bits other than 6 needs --crc-poly"};
  }
  const std::uint64_t top = std::uint64_t{1} << width;
  if (width == 0) {
    poly = 0;
  } else if ((poly & ~(top - 1U)) == top) {
    poly &= top - 1U;  // BiSS notation: drop the x^width term
  } else if (poly >= top) {
    throw cli::usage_error{"--crc-poly does not fit --crc-bits"};
  }
  l.crc.width = width;
  l.crc.poly = static_cast<std::uint32_t>(poly);
  const std::uint64_t max_start = width == 0 ? 0 : top - 1U;
  if (crc_start > max_start) {
    throw cli::usage_error{"--crc-start needs a number up to " + std::to_string(max_start)};
  }
  l.crc.start = static_cast<std::uint32_t>(crc_start);
  l.crc.inverted = !no_crc_invert;
  return l;
}

cli::outcome describe_samples(const std::vector<std::uint8_t>& samples,
                              const bs::slave_layout& layout) {
  const std::vector<std::uint8_t>* bits = &samples;
  std::vector<std::uint8_t> words((bits->size() + 7U) / 8U, 0);
  for (std::size_t i = 0; i < bits->size(); ++i) {
    if ((*bits)[i] != 0U) {
      words[i / 8U] = static_cast<std::uint8_t>(words[i / 8U] | (0x80U >> (i % 8U)));
    }
  }
  const auto r = bs::decode_frame(mb::span<const std::uint8_t>(words.data(), words.size()),
                                  bits->size(), layout);
  const bs::slave_data& d = r->slaves[0];
  if (r.is_incomplete()) {
    // The capture is all there is: name what it lacks.
    std::size_t ack = 0;
    while (ack < bits->size() && (*bits)[ack] != 0U) {
      ++ack;
    }
    std::size_t start = ack;
    while (start < bits->size() && (*bits)[start] == 0U) {
      ++start;
    }
    const mb::errc e = ack == bits->size()     ? mb::errc::biss_no_ack
                       : start == bits->size() ? mb::errc::biss_no_start
                                               : mb::errc::truncated;
    return cli::outcome::failure(mb::to_string(e));
  }
  if (r.is_failed()) {
    return cli::failure_of(r, 2);
  }
  cli::record f;
  f.add("position", d.single_turn);
  f.add("ne", d.ne ? 1 : 0);
  f.add("nw", d.nw ? 1 : 0);
  f.add("cds", r->cds ? 1 : 0);
  f.hex("crc", d.crc);
  f.add("line_delay", r->line_delay);
  f.add("start", r->start);
  f.add("ack_bits", r->ack_bits());
  return cli::outcome::success(f);
}

}  // namespace biss_io

namespace {

// decode biss csd: the layout, and the samples as --hex words cut to --bits (else the input).
struct csd_options {
  biss_io::layout_options layout;
  std::optional<std::string> hex;
  std::optional<std::uint64_t> bits;
  void bind(CLI::App& app) {
    layout.bind(app);
    cli::text(app, "hex", hex);
    cli::number(app, "bits", bits, 0, ~std::uint64_t{0});
  }
};

// The capture as 0/1 samples: the positional bit string, or --hex words (MSB first) cut to
// --bits samples.
std::optional<std::vector<std::uint8_t>> samples_from(const std::string& input,
                                                      const csd_options& opts, std::string& error) {
  std::vector<std::uint8_t> bits;
  if (const auto& hex = opts.hex) {
    for (std::size_t i = 0; i < hex->size(); ++i) {
      const char c = (*hex)[i];
      if (c == ' ' || c == '_' || c == ',' || c == ':') {
        continue;
      }
      if (c == '0' && i + 1 < hex->size() && ((*hex)[i + 1] == 'x' || (*hex)[i + 1] == 'X')) {
        ++i;
        continue;
      }
      const auto d = parse_hex_number(std::string(1, c));
      if (!d) {
        error = "invalid_hex";
        return std::nullopt;
      }
      for (int b = 3; b >= 0; --b) {
        bits.push_back(static_cast<std::uint8_t>((*d >> static_cast<unsigned>(b)) & 1U));
      }
    }
    const std::uint64_t n = opts.bits.value_or(bits.size());
    if (n > bits.size()) {
      throw cli::usage_error{"--bits needs a number up to " + std::to_string(bits.size())};
    }
    bits.resize(static_cast<std::size_t>(n));
    if (bits.empty()) {
      error = "empty_input";
      return std::nullopt;
    }
    return bits;
  }
  return cli::parse_bits(input, error);
}

cli::outcome decode_csd(const std::string& input, const csd_options& opts) {
  const bs::slave_layout layout = opts.layout.layout();
  std::string error;
  const auto bits = samples_from(input, opts, error);
  if (!bits) {
    return cli::outcome::failure(error);
  }
  return biss_io::describe_samples(*bits, layout);
}

// encode biss csd: the layout, the frame's values and bits, and the --vcd waveform's clock.
struct encode_options {
  biss_io::layout_options layout;
  std::optional<std::uint64_t> position;
  unsigned ne = 1;
  unsigned nw = 1;
  std::size_t ack = 1;
  unsigned cds = 0;
  std::size_t line_delay = 0;
  std::optional<std::string> vcd;
  std::uint64_t baud = 1000000;
  void bind(CLI::App& app) {
    layout.bind(app);
    cli::number(app, "position", position, 0, ~std::uint64_t{0});
    cli::number(app, "ne", ne, 0, 1);
    cli::number(app, "nw", nw, 0, 1);
    cli::number(app, "ack", ack, 1, 4096);
    cli::number(app, "cds", cds, 0, 1);
    cli::number(app, "line-delay", line_delay, 0, 4096);
    cli::text(app, "vcd", vcd);
    cli::number(app, "baud", baud, 1, 100000000);
  }
};

int encode_csd(const encode_options& opts) {
  const bs::slave_layout layout = opts.layout.layout();
  if (!opts.position) {
    throw cli::usage_error{"encode biss csd needs --position N"};
  }
  bs::slave_values v;
  v.single_turn = *opts.position;
  v.ne = opts.ne != 0U;
  v.nw = opts.nw != 0U;
  bs::line_options line;
  line.ack_bits = opts.ack;
  line.line_delay = opts.line_delay;
  line.cds = opts.cds != 0U;
  std::vector<std::uint8_t> words(
      (bs::encoded_bits(mb::span<const bs::slave_layout>(&layout, 1), line) + 7U) / 8U + 1U, 0);
  const std::size_t n = cli::built(
      bs::encode_frame(layout, v, mb::span<std::uint8_t>(words.data(), words.size()), line),
      "--position " + std::to_string(v.single_turn) + " in this layout");
  std::string bits;
  for (std::size_t i = 0; i < n; ++i) {
    bits.push_back(((words[i / 8U] >> (7U - i % 8U)) & 1U) != 0U ? '1' : '0');
  }
  cli::record f;
  f.add("bits", bits);
  if (const auto& vcd = opts.vcd) {  // MA and SLO at --baud clocks a second, from 1 us
    std::vector<std::uint8_t> samples;
    for (const char c : bits) {
      samples.push_back(c == '1' ? 1 : 0);
    }
    capture::channel ma;
    capture::channel slo;
    ma.name = "MA";
    slo.name = "SLO";
    capture::biss_levels(samples, static_cast<double>(opts.baud), 1e-6, ma, slo);
    capture::write_vcd_file(*vcd, {ma, slo});
    f.add("vcd", *vcd);
  }
  return cli::finish(cli::outcome::success(f));
}

}  // namespace

namespace cli {

protocol_entries biss_entries() {
  protocol_entries e;
  e.decoders.push_back(lines("decode", "biss", "csd",
                             "a sensor data frame from the SL samples taken on MA's rising edges "
                             "(bits, or --hex words); default layout AMO ABSYS",
                             &decode_csd));
  e.decoders.back().input = false;
  e.decoders.back().input_help =
      "the SL samples as 0/1 bits, first clock first (hex words: --hex instead)";
  e.typed.push_back(typed("encode", "biss", "csd",
                          "the SL bits of a sensor data frame (default layout AMO ABSYS)",
                          &encode_csd));
  return e;
}

}  // namespace cli
