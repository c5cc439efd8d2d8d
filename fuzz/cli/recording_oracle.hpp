// The oracle of the recording readers' fuzz targets (vcd, csv, sr): a file is either read, and
// then the recording keeps capture::parse's promises (at least one channel; each channel's
// times rise from 0 to at most `end`, finite; its levels alternate; level_at agrees with them;
// a UART decode of it ends, its bytes within the recording), or refused with a usage error
// that starts with the file's name and says what is wrong. Any other exception, a crash or a
// hang is a finding.
#ifndef MOTIONBUS_FUZZ_CLI_RECORDING_ORACLE_HPP
#define MOTIONBUS_FUZZ_CLI_RECORDING_ORACLE_HPP

#include <cmath>
#include <string>

#include "../fuzz_check.hpp"
#include "capture.hpp"
#include "cli.hpp"

namespace fuzz_cli {

inline void check_channel(const capture::channel& c, double end) {
  MOTIONBUS_FUZZ_CHECK(c.times.size() == c.levels.size());
  for (std::size_t i = 0; i < c.times.size(); ++i) {
    MOTIONBUS_FUZZ_CHECK(std::isfinite(c.times[i]) && c.times[i] >= 0 && c.times[i] <= end);
    if (i > 0) {
      MOTIONBUS_FUZZ_CHECK(c.times[i] >= c.times[i - 1]);
      MOTIONBUS_FUZZ_CHECK(c.levels[i] != c.levels[i - 1]);
    }
    if (i + 1 == c.times.size() || c.times[i + 1] > c.times[i]) {
      MOTIONBUS_FUZZ_CHECK(c.level_at(c.times[i]) == c.levels[i]);
    }
  }
  // a UART at 1 Mbit/s, 8E1, and at 9600 bit/s, 8N2: every byte found starts on a change
  for (const double baud : {1e6, 9600.0}) {
    const auto bytes = capture::decode_uart(c, baud, baud > 1e5 ? 'E' : 'N', baud > 1e5 ? 1 : 2);
    double last = -1;
    for (const capture::uart_byte& b : bytes) {
      MOTIONBUS_FUZZ_CHECK(b.start >= 0 && b.start <= end && b.start > last);
      MOTIONBUS_FUZZ_CHECK(b.end > b.start);
      last = b.start;
    }
  }
}

inline void check_recording(const std::string& format, const std::string& data) {
  const std::string path = "input." + format;
  try {
    const capture::recording r = capture::parse(format, data, path);
    MOTIONBUS_FUZZ_CHECK(r.format == format);
    MOTIONBUS_FUZZ_CHECK(!r.channels.empty());
    MOTIONBUS_FUZZ_CHECK(std::isfinite(r.end) && r.end >= 0);
    for (const capture::channel& c : r.channels) {
      check_channel(c, r.end);
    }
  } catch (const cli::usage_error& e) {
    // "<path>: <what is wrong>"
    MOTIONBUS_FUZZ_CHECK(e.message.rfind(path + ": ", 0) == 0);
    MOTIONBUS_FUZZ_CHECK(e.message.size() > path.size() + 2);
  }
}

}  // namespace fuzz_cli

#endif
