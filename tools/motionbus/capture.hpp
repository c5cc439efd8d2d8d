// Logic-analyzer and simulation recordings for the CLI: read (sigrok session files, VCD, CSV),
// turned into levels over time per channel; a UART decoder over a line; and a VCD writer for
// the waveforms `encode ... --vcd` draws.
#ifndef MOTIONBUS_TOOLS_CAPTURE_HPP
#define MOTIONBUS_TOOLS_CAPTURE_HPP

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace capture {

/// One digital channel: its level from each time on (seconds from the recording's start,
/// rising; the first entry is the level at the start).
struct channel {
  std::string name;
  std::vector<double> times;
  std::vector<bool> levels;

  /// The level just before `t` (what a receiver sampling at `t` sees when the line changes
  /// exactly then).
  bool level_before(double t) const;
  /// The level at `t` (changes at `t` included).
  bool level_at(double t) const;
};

struct recording {
  std::string format;  ///< "sr", "vcd" or "csv"
  std::vector<channel> channels;
  double end = 0;  ///< the time of the last sample or change

  /// The channel named `name` (as the file names it; for VCD also with its scope, "tb.ma"); a
  /// usage error that lists the channels when there is none.
  const channel& find(const std::string& name) const;
};

/// Reads a recording by its extension (.sr, .vcd, .csv); a usage error when it cannot.
recording load(const std::string& path);

/// Reads a recording of `format` ("sr", "vcd" or "csv") from `data`, a file's bytes: what load
/// does once the file is read. A malformed file is a usage error that starts with `path` and
/// names what is wrong; a recording read has at least one channel, each channel's times rise
/// (never back) from 0 to at most `end`, and its levels alternate (a change each).
recording parse(const std::string& format, const std::string& data, const std::string& path);

/// A member of a sigrok session by name into `out`; false when there is none.
using session_member = std::function<bool(const std::string& name, std::string& out)>;
/// A sigrok session from its "metadata" text and its members (what parse does with a .sr once
/// the archive is open; the fuzz target gives it members without an archive).
recording read_session(const std::string& metadata, const session_member& member,
                       const std::string& path);

/// A byte a UART receiver found on a line (idle high, start bit low, 8 data bits LSB first,
/// parity, stop bits), sampled at the middle of each bit from the start bit's falling edge.
struct uart_byte {
  double start = 0;  ///< the start bit's falling edge
  double end = 0;    ///< the end of the last stop bit
  std::uint8_t value = 0;
  bool parity_error = false;
  bool framing_error = false;  ///< a stop bit read low
};
std::vector<uart_byte> decode_uart(const channel& line, double baud, char parity,
                                   unsigned stop_bits);

/// The level sequence of a UART line sending `bytes` back to back from `start` (idle high
/// before and after).
void uart_levels(const std::vector<std::uint8_t>& bytes, double baud, char parity,
                 unsigned stop_bits, double start, channel& line);

/// BiSS-C MA and SLO for the SL samples `bits` (0/1, as sampled on MA's rising edges): MA idle
/// high, then one clock per sample from `start` (falling edge, rising edge half a period
/// later), SLO set at each falling edge so that it is stable at the rising edge; both high
/// after the frame.
void biss_levels(const std::vector<std::uint8_t>& bits, double clock_hz, double start, channel& ma,
                 channel& slo);

/// Writes channels as a VCD file (timescale 1 ns, module "motionbus").
void write_vcd(std::ostream& out, const std::vector<channel>& channels);
/// write_vcd to the file `path`; a usage error when it cannot be written.
void write_vcd_file(const std::string& path, const std::vector<channel>& channels);

}  // namespace capture

#endif
