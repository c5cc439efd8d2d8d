// BiSS-C pieces shared by the CLI's commands (decode biss csd, decode biss capture).
#ifndef MOTIONBUS_TOOLS_BISS_IO_HPP
#define MOTIONBUS_TOOLS_BISS_IO_HPP

#include <motionbus/biss.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"
#include "options.hpp"

namespace biss_io {

/// The layout options (default: AMO ABSYS): --data-bits, --crc-bits, --crc-poly (BiSS notation,
/// with or without the x^N term), --crc-start, --no-crc-invert.
struct layout_options {
  unsigned data_bits = 32;
  unsigned crc_bits = 6;
  std::optional<std::string> crc_poly;
  std::uint64_t crc_start = 0;
  bool no_crc_invert = false;
  void bind(CLI::App& app);
  /// The layout they give; a usage error when they do not fit together.
  motionbus::biss::slave_layout layout() const;
};

/// A sensor data frame from the SL samples taken on MA's rising edges (0/1 each).
cli::outcome describe_samples(const std::vector<std::uint8_t>& samples,
                              const motionbus::biss::slave_layout& layout);

}  // namespace biss_io

#endif
