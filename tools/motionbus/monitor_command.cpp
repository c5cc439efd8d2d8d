// Passive bus monitors (a port that listens to a tapped line and never sends):
//   monitor modbus --device PATH [--baud N] [--parity E|O|N] [--stop-bits N] [--fc11 sm]
//   monitor tformat --device PATH [--baud N]
//   both: [--gap-us N] [--count N] [--duration S] [--response-ms N] [--json]
// Every frame seen, with the microseconds since the monitor started (at its first byte's
// arrival), its direction (request or response, from the pairing), its fields and CRC state;
// a response is paired with its request; a missing response, an exception, a CRC error and
// garbage are flagged. A summary (frames, errors, per slave or Data ID) ends the output.
//
// Framing and pairing: the library's listeners (bus_monitor.hpp): length rule and CRC find
// the frames, frames closer than any silence are framed apart. --gap-us is the silence after
// which what is held is settled (a frame cut short reported truncated): by default t3.5 or
// 20 ms, whichever is longer, for Modbus, and 20 ms for T-format (a USB adapter hands bytes
// over in bursts: a host sees no character-time gap, and a shorter gap could cut a frame that
// arrives in two bursts). A request is flagged as unanswered when no response arrives before
// the next request or within --response-ms.
#include <motionbus/modbus.hpp>
#include <motionbus/tformat.hpp>

#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include "bus_monitor.hpp"
#include "cli.hpp"
#include "modbus_io.hpp"
#include "options.hpp"
#include "serial.hpp"

namespace mo = motionbus::modbus;

namespace {

constexpr std::uint32_t min_gap_us = 20000;

using bus_monitor::modbus_monitor;
using bus_monitor::tformat_monitor;

// Watches the port until Ctrl-C, --count frames or --duration: every read's bytes go to the
// monitor with their arrival time, and the time since the last byte after every read; then the
// monitor settles what it holds and the summary is printed.
template <class Monitor>
int watch(serial::port& port, const cli::monitor_options& l, Monitor& m, const char* summary_key) {
  serial::install_stop_handler();
  const std::uint32_t start = serial::now_us();
  std::uint8_t buffer[256];
  std::uint32_t last_byte = start;
  int status = 0;
  while (!serial::stop_requested() && (l.count == 0 || m.counts().frames < l.count)) {
    if (l.duration_s != 0 && serial::now_us() - start >= l.duration_s * 1000000U) {
      break;
    }
    const long n = port.read_some(buffer, sizeof buffer, 2);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      status = 1;
      break;
    }
    const std::uint32_t t = serial::now_us();
    if (n > 0) {
      last_byte = t;
      m.bytes(buffer, static_cast<std::size_t>(n), t - start);
    }
    m.tick(t - start, t - last_byte);
  }
  m.end(serial::now_us() - start);
  cli::print_record(m.counts().summary(summary_key));
  return status;
}

int monitor_modbus(const cli::monitor_options& opts) {
  const mo::report_id_format fc11 = modbus_io::fc11_of(opts.watched.fc11);
  serial::port port;
  if (!opts.watched.line.open(port)) {
    return 1;
  }
  const serial::settings s = opts.watched.line.settings();
  const mo::parity p = modbus_io::parity_of(s);
  const std::uint32_t t35 = mo::t35_us(s.baud, p, s.stop_bits);
  modbus_monitor m(fc11, opts.watched.gap_or(t35 > min_gap_us ? t35 : min_gap_us),
                   mo::character_time_us(s.baud, p, s.stop_bits), opts.response_ms * 1000U);
  return watch(port, opts, m, "slave");
}

int monitor_tformat(const cli::monitor_options& opts) {
  serial::port port;
  if (!opts.watched.line.open(port)) {
    return 1;
  }
  tformat_monitor m(opts.watched.gap_or(min_gap_us),
                    10U * 1000000U / opts.watched.line.settings().baud, opts.response_ms * 1000U);
  return watch(port, opts, m, "data_id");
}

}  // namespace

namespace cli {

protocol_entries monitor_entries() {
  protocol_entries e;
  e.typed.push_back(typed("monitor", "modbus", "",
                          "watch a tapped Modbus RTU line: every frame timed, requests paired with "
                          "their responses, missing responses, exceptions, CRC errors and garbage "
                          "flagged, a summary at the end",
                          &monitor_modbus, monitor_options::modbus()));
  e.typed.push_back(typed("monitor", "tformat", "",
                          "watch a tapped T-format line: every request and response timed and "
                          "paired, CRC errors, missing responses and garbage flagged, a summary",
                          &monitor_tformat, monitor_options{}));
  return e;
}

}  // namespace cli
