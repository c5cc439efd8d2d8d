// Every frame in a logic-analyzer or simulation recording (sigrok .sr, VCD, CSV):
//   decode modbus capture FILE --line CH [--baud N] [--parity E|O|N] [--stop-bits N] [--fc11 sm]
//                              [--gap-us N]
//   decode tformat capture FILE --line CH [--baud N] [--gap-us N]
//   decode biss capture FILE --clock CH --data CH [layout options]
// Channels by the names the file gives them. The UART protocols go through the bus monitors'
// framing and pairing (bus_monitor.hpp, on the library's listeners): a T-format line holds
// both directions (half duplex), and each frame is labelled request or response; length rule
// and CRC find the frames, a silence of --gap-us (default t3.5 for Modbus, 10 byte times for
// T-format) settles a frame cut short. A byte with a parity or framing error makes its frame
// fail (parity_error, framing_error, with the byte's index). BiSS-C: SL is sampled at each rising
// edge of MA (the level just before the edge); a frame is a burst of MA clocks, the next one
// starting after MA stayed high for more than four clock periods. Times are microseconds from the
// recording's start.
#include <motionbus/biss.hpp>
#include <motionbus/modbus.hpp>
#include <motionbus/tformat.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "biss_io.hpp"
#include "bus_monitor.hpp"
#include "capture.hpp"
#include "cli.hpp"
#include "modbus_io.hpp"
#include "options_bind.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

// A recording's time in the decoders' microseconds (64-bit: a recording's 10^6 s at most fit).
std::uint64_t us(double seconds) {
  return static_cast<std::uint64_t>(std::llround(seconds * 1e6));
}

// Feeds the bytes a UART decoder found to a bus monitor (a silence of `gap_us` between two
// bytes settles what is held; a byte's parity or framing error fails its frame), then prints
// the summary under `summary_key`. 0 when every frame was sound, else 1.
template <class Monitor>
int decode_line(Monitor& m, const std::vector<capture::uart_byte>& bytes, std::uint32_t gap_us,
                const char* summary_key) {
  double last_end = 0;
  bool first = true;
  for (const capture::uart_byte& b : bytes) {
    // (a sampled start edge may come a sample before the previous stop bit's computed end)
    const double silent = b.start - last_end;
    if (!first && silent > 0 && us(silent) >= gap_us) {
      m.tick(us(b.start), us(silent));
    }
    // the UART's error: the name the frame fails with (error: cli.error_names finds it)
    const char* error =
        b.parity_error ? "parity_error" : (b.framing_error ? "framing_error" : nullptr);
    m.byte_at(b.value, us(b.start), error);
    last_end = b.end;
    first = false;
  }
  m.end(us(last_end) + gap_us);
  cli::print_record(m.counts().summary(summary_key));
  const bus_monitor::tally& t = m.counts();
  return t.crc_errors + t.other_errors + t.missing + t.garbage_bytes == 0 ? 0 : 1;
}

int modbus_capture(const cli::uart_capture_options& opts) {
  const capture::recording r = capture::load(opts.file);
  const capture::channel& line = r.find(opts.line_channel);
  const serial::settings s = opts.watched.line.settings();
  const mo::parity p = modbus_io::parity_of(s);
  // a response is expected before the next request: the recording's end settles the last one
  const std::uint32_t gap = opts.watched.gap_or(mo::t35_us(s.baud, p, s.stop_bits));
  bus_monitor::modbus_monitor m(modbus_io::fc11_of(opts.watched.fc11), gap,
                                mo::character_time_us(s.baud, p, s.stop_bits), ~std::uint64_t{0});
  return decode_line(m, capture::decode_uart(line, s.baud, s.parity, s.stop_bits), gap, "slave");
}

int tformat_capture(const cli::uart_capture_options& opts) {
  const capture::recording r = capture::load(opts.file);
  const capture::channel& line = r.find(opts.line_channel);
  const auto baud = static_cast<double>(opts.watched.line.baud);
  const auto byte_us = static_cast<std::uint32_t>(std::ceil(10e6 / baud));
  const std::uint32_t gap = opts.watched.gap_or(10 * byte_us);  // well past the turnaround
  bus_monitor::tformat_monitor m(gap, byte_us, ~std::uint64_t{0});
  return decode_line(m, capture::decode_uart(line, baud, 'N', 1), gap, "data_id");
}

// decode biss capture: the recording, its MA (--clock) and SLO (--data) channels, the layout.
struct biss_capture_options {
  std::string file;
  std::string clock;
  std::string data;
  biss_io::layout_options layout;
  void bind(CLI::App& app) {
    cli::recording(app, file);
    cli::channel(app, "clock", clock);
    cli::channel(app, "data", data);
    layout.bind(app);
  }
};

int biss_capture(const biss_capture_options& opts) {
  const capture::recording r = capture::load(opts.file);
  const capture::channel& ma = r.find(opts.clock);
  const capture::channel& slo = r.find(opts.data);
  const mb::biss::slave_layout layout = opts.layout.layout();
  std::vector<double> rises;
  std::vector<double> falls;
  for (std::size_t i = 1; i < ma.times.size(); ++i) {
    (ma.levels[i] ? rises : falls).push_back(ma.times[i]);
  }
  double period = 0;
  for (std::size_t i = 1; i < rises.size(); ++i) {
    const double d = rises[i] - rises[i - 1];
    period = period == 0 ? d : std::min(period, d);
  }
  std::uint64_t frames = 0;
  std::uint64_t failed = 0;
  std::size_t i = 0;
  while (i < rises.size()) {
    std::size_t j = i + 1;
    while (j < rises.size() && rises[j] - rises[j - 1] <= 4 * period) {
      ++j;
    }
    std::vector<std::uint8_t> samples;
    for (std::size_t k = i; k < j; ++k) {
      samples.push_back(slo.level_before(rises[k]) ? 1 : 0);
    }
    // the frame starts at MA's falling edge before its first rising edge
    const auto fall = std::upper_bound(falls.begin(), falls.end(), rises[i]);
    const double start = fall == falls.begin() ? rises[i] : *(fall - 1);
    cli::record at;
    at.add("time_us", us(start)).add("clocks", j - i);
    const cli::outcome o = biss_io::describe_samples(samples, layout);
    cli::print(o, at);
    ++frames;
    failed += o.ok ? 0 : 1;
    i = j;
  }
  cli::record summary;
  summary.add_bool("summary", true).add("frames", frames).add("errors", failed);
  if (period > 0) {
    summary.add("clock_hz", std::llround(1.0 / period));
  }
  cli::print_record(summary);
  return failed == 0 ? 0 : 1;
}

}  // namespace

namespace cli {

protocol_entries capture_entries() {
  protocol_entries e;
  e.typed.push_back(typed("decode", "modbus", "capture",
                          "every Modbus RTU frame on a UART line in a recording (.sr, .vcd, .csv), "
                          "requests paired with responses",
                          &modbus_capture, uart_capture_options::modbus(), "<file>"));
  e.typed.push_back(typed("decode", "tformat", "capture",
                          "every T-format request and response on a line in a recording (.sr, "
                          ".vcd, .csv): both directions, labelled",
                          &tformat_capture, uart_capture_options{}, "<file>"));
  e.typed.push_back(typed("decode", "biss", "capture",
                          "every BiSS-C sensor data frame in a recording of MA and SLO (.sr, .vcd, "
                          ".csv)",
                          &biss_capture, biss_capture_options{}, "<file>"));
  return e;
}

}  // namespace cli
