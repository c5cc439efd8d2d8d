// BiSS-C pieces shared by the CLI's commands (decode biss csd, decode biss capture).
#ifndef MOTIONBUS_TOOLS_BISS_IO_HPP
#define MOTIONBUS_TOOLS_BISS_IO_HPP

#include <motionbus/biss.hpp>

#include <cstdint>
#include <vector>

#include "cli.hpp"

namespace biss_io {

/// The slave layout from the layout options (default: AMO ABSYS).
motionbus::biss::slave_layout layout_from(const cli::options& opts);
/// A sensor data frame from the SL samples taken on MA's rising edges (0/1 each).
cli::outcome describe_samples(const std::vector<std::uint8_t>& samples,
                              const motionbus::biss::slave_layout& layout);

}  // namespace biss_io

#endif
