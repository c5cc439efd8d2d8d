// Passive bus monitors (a port that listens to a tapped line and never sends):
//   monitor modbus --device PATH [--baud N] [--parity E|O|N] [--stop-bits N] [--fc11 sm]
//   monitor modbus --ascii ...                  a Modbus ASCII line (ascii_monitor below)
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

namespace mb = motionbus;
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
  // times on the 64-bit clock: in 32 bits, microseconds wrap after 4294 s (a watch's times and
  // --duration, up to 4e12 us, would)
  const std::uint64_t start = serial::now_us64();
  const std::uint64_t duration_us = std::uint64_t{l.duration_s} * 1000000U;
  std::uint8_t buffer[256];
  std::uint64_t last_byte = start;
  int status = 0;
  while (!serial::stop_requested() && (l.count == 0 || m.counts().frames < l.count)) {
    if (duration_us != 0 && serial::now_us64() - start >= duration_us) {
      break;
    }
    const long n = port.read_some(buffer, sizeof buffer, 2);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      status = 1;
      break;
    }
    const std::uint64_t t = serial::now_us64();
    if (n > 0) {
      last_byte = t;
      m.bytes(buffer, static_cast<std::size_t>(n), t - start);
    }
    m.tick(t - start, t - last_byte);
  }
  m.end(serial::now_us64() - start);
  cli::print_record(m.counts().summary(summary_key));
  return status;
}

// A Modbus ASCII line: its frames carry their own ends (':' ... CR LF), so the library's ASCII
// framer as a listener frames them (a bad LRC is crc_mismatch, a non-hex character
// non_hex_character: one failure each, with the error of the framer) and tells each frame's
// direction (heard_response(): the pairing, ASCII frames having no length rule); a request
// left unanswered past --response-ms is told to it (no_response()). Each frame
// is described as its RTU form would be (the same fields; `crc` is that form's) with `lrc`,
// the frame's own. The silence (--gap-us) is not used: a pause inside an ASCII frame is
// allowed (Serial Line §2.5.2.2: up to 1 s).
class ascii_monitor {
 public:
  ascii_monitor(mo::report_id_format fc11, std::uint64_t response_us)
      : fc11_(fc11), response_us_(response_us) {}

  void bytes(const std::uint8_t* data, std::size_t n, std::uint64_t time_us) {
    (void)mb::feed_all(rx_, mb::byte_view(data, n), [&](const auto& r) {
      ++t_.frames;
      if (!r.is_complete()) {
        ++(r.error() == mb::errc::crc_mismatch ? t_.crc_errors : t_.other_errors);
        cli::print(cli::outcome::failure(mb::to_string(r.error())), bus_monitor::at(time_us, "?"));
        return true;
      }
      frame(r.value(), time_us);
      return true;
    });
  }
  void tick(std::uint64_t time_us, std::uint64_t /*silent_us*/) {
    if (pending_ && time_us - pending_time_ >= response_us_) {
      rx_.no_response();
      missing(time_us);
    }
  }
  void end(std::uint64_t time_us) {
    if (pending_) {
      missing(time_us);
    }
  }
  const bus_monitor::tally& counts() const { return t_; }

 private:
  void frame(const mo::ascii_frame& f, std::uint64_t time) {
    std::vector<std::uint8_t> rtu(mo::max_rtu_size);
    rtu.resize(
        mo::encode_rtu(f.slave, f.pdu, mb::mutable_byte_view(rtu.data(), rtu.size())).value_or(0));
    const auto as_rtu = mo::decode_rtu(mb::byte_view(rtu.data(), rtu.size()));
    if (!as_rtu.is_complete()) {  // an address of 248..255 or a PDU of no function
      ++t_.other_errors;
      cli::print(cli::outcome::failure(mb::to_string(as_rtu.error())), bus_monitor::at(time, "?"));
      return;
    }
    const bool response = pending_ && rx_.heard_response();
    cli::record p = bus_monitor::at(time, response ? "response" : "request");
    if (response) {
      const auto request = mo::decode_rtu(mb::byte_view(request_.data(), request_.size()));
      cli::outcome o = modbus_io::describe_response(as_rtu.value(), &request.value(), fc11_);
      ++t_.responses;
      ++t_.by_key[f.slave].responses;
      if (!o.ok) {
        ++t_.other_errors;
        ++t_.by_key[f.slave].errors;
      } else if (f.pdu[0] >= mo::exception_flag) {
        ++t_.exceptions;
        ++t_.by_key[f.slave].errors;
      }
      p.add("latency_us", time - pending_time_).hex("lrc", f.lrc);
      cli::print(o, p);
      pending_ = false;
      return;
    }
    if (pending_) {
      missing(time);  // a request follows a request
    }
    ++t_.requests;
    ++t_.by_key[f.slave].requests;
    p.hex("lrc", f.lrc);
    cli::print(modbus_io::describe_request(as_rtu.value()), p);
    if (!f.broadcast()) {  // a broadcast is never answered
      request_ = rtu;
      pending_ = true;
      pending_time_ = time;
    }
  }
  void missing(std::uint64_t time) {
    ++t_.missing;
    ++t_.by_key[request_[0]].errors;
    cli::record e;
    e.add("slave", request_[0]).hex("function", request_[1]);
    e.add("request_time_us", pending_time_);
    cli::print(cli::outcome::failure("no_response", e), bus_monitor::at(time, "response"));
    pending_ = false;
  }

  mo::ascii_framer rx_{mo::framer_role::listener};
  mo::report_id_format fc11_;
  std::uint64_t response_us_;
  std::vector<std::uint8_t> request_;  // the pending request in its RTU form
  bool pending_ = false;
  std::uint64_t pending_time_ = 0;
  bus_monitor::tally t_;
};

int monitor_modbus(const cli::monitor_options& opts) {
  const mo::report_id_format fc11 = modbus_io::fc11_of(opts.watched.fc11);
  serial::port port;
  if (!opts.watched.line.open(port)) {
    return 1;
  }
  if (opts.ascii) {
    ascii_monitor m(fc11, std::uint64_t{opts.response_ms} * 1000U);
    return watch(port, opts, m, "slave");
  }
  const serial::settings s = opts.watched.line.settings();
  const mo::parity p = modbus_io::parity_of(s);
  const std::uint32_t t35 = mo::t35_us(s.baud, p, s.stop_bits);
  modbus_monitor m(fc11, opts.watched.gap_or(t35 > min_gap_us ? t35 : min_gap_us),
                   mo::character_time_us(s.baud, p, s.stop_bits),
                   std::uint64_t{opts.response_ms} * 1000U);
  return watch(port, opts, m, "slave");
}

int monitor_tformat(const cli::monitor_options& opts) {
  serial::port port;
  if (!opts.watched.line.open(port)) {
    return 1;
  }
  tformat_monitor m(opts.watched.gap_or(min_gap_us),
                    10U * 1000000U / opts.watched.line.settings().baud,
                    std::uint64_t{opts.response_ms} * 1000U);
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
