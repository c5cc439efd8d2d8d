// read tformat --watch: the same request every --interval-ms, each response fed to the library's
// position tracker and link health through the T-format adapters (tformat/position.hpp:
// update_position, record; core/position.hpp, core/link_health.hpp), printed as
//   a terminal (text):  one live line, rewritten in place (\r and ANSI "erase to end of line");
//   not a terminal:     a line per read ("read=N time_us=T  ok|FAIL error  fields");
//   --json:             a JSON object per read;
// then a summary record. The deadline of each read is the library's (transaction_timeout_ns:
// the request's and the response's fields at the line's rate plus the response start allowance)
// plus --timeout-ms, the host's allowance: a USB adapter or a pseudo-terminal hands bytes over
// milliseconds after the line carried them, where the line's own deadline is tens of
// microseconds.
#include <unistd.h>
#include <motionbus/core/link_health.hpp>
#include <motionbus/core/position.hpp>
#include <motionbus/tformat.hpp>
#include <motionbus/tformat/position.hpp>

#include <cstdint>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"
#include "options.hpp"
#include "serial.hpp"
#include "tformat_io.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace tformat_io {

namespace {

// The longest sleep between checks of Ctrl-C while waiting for the next read.
constexpr std::uint64_t sleep_slice_us = 20000;

// What one read came to: a response or a failure as the receiver settled it, or nothing by
// the deadline.
struct transaction {
  std::optional<mb::decode_result<tf::response>> result;
  bool port_error = false;
};

transaction transact(serial::port& port, tf::receiver& rx, const watch_setup& s,
                     std::uint64_t deadline_us) {
  transaction t;
  port.flush_input();  // a late answer to the last read must not pass for this one's
  if (!port.write_all(s.request, s.request_size)) {
    std::cerr << "motionbus: write error\n";
    t.port_error = true;
    return t;
  }
  const std::uint64_t sent = serial::now_us64();
  rx.sent(mb::byte_view(s.request, s.request_size));
  std::uint8_t buffer[64];
  for (std::uint64_t now = sent; now - sent < deadline_us; now = serial::now_us64()) {
    const std::uint64_t left_us = deadline_us - (now - sent);
    const long got =
        port.read_some(buffer, sizeof buffer, static_cast<int>((left_us + 999U) / 1000U));
    if (got < 0) {
      std::cerr << "motionbus: read error\n";
      t.port_error = true;
      return t;
    }
    // the first result settles the read, as for a single read
    (void)mb::feed_all(rx, mb::byte_view(buffer, static_cast<std::size_t>(got)),
                       [&](const auto& r) {
                         t.result = r;
                         return false;
                       });
    if (t.result) {
      return t;
    }
  }
  return t;
}

// The resolution a response's position is in: --resolution, else an ID3 response's ENID, else
// the TS5700N8500's (17 + 16 bits), as the receiver decodes it.
tf::resolution resolution_of(const tf::receiver_options& ro, const tf::response& r) {
  const tf::resolution res = ro.decode.res;
  if (ro.decode.resolution_from_enid && r.layout().enid()) {
    return tf::resolution_for_enid(r.enid, res);
  }
  return res;
}

std::string fixed(double v, int decimals) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

// The counters of the link and the tracker, as one JSON object (one text field each).
cli::record counters_record(const mb::link_health& h, std::uint32_t implausible) {
  const mb::link_counters& c = h.counters();
  cli::record r;
  r.add("frames", c.frames)
      .add("good", c.good)
      .add("alarms", c.alarms)
      .add("crc_errors", c.crc_errors)
      .add("timeouts", c.timeouts)
      .add("invalid", c.invalid)
      .add("losses", c.losses)
      .add("implausible_steps", implausible);
  return r;
}

// The live line: position, speed, link state and counts, as short as a terminal line allows.
std::string live_line(std::uint64_t read, const std::optional<mb::position_tracker>& t,
                      const std::optional<double>& rpm, const mb::link_health& h,
                      const std::string& last) {
  const mb::link_counters& c = h.counters();
  std::string line = "read " + std::to_string(read) + "  ";
  if (t && t->has_position()) {
    line += "pos " + std::to_string(t->counts()) + " (" + fixed(t->revolutions(), 4) + " rev, " +
            fixed(t->degrees(), 2) + " deg)";
  } else {
    line += "pos -";
  }
  line += "  speed " + (rpm ? fixed(*rpm, 1) + " rpm" : std::string("-"));
  line += "  link " + std::string(mb::to_string(h.state()));
  line += "  crc " + std::to_string(c.crc_errors) + " timeouts " + std::to_string(c.timeouts) +
          " invalid " + std::to_string(c.invalid) + " alarms " + std::to_string(c.alarms) +
          " implausible " + std::to_string(t ? t->implausible_steps() : 0U);
  line += "  last " + last;
  return line;
}

}  // namespace

int watch(serial::port& port, const watch_setup& s, const cli::watch_options& w) {
  serial::install_stop_handler();
  const bool live = cli::output_format() == cli::format::text && isatty(STDOUT_FILENO) == 1;
  tf::receiver rx(s.receiver);
  mb::link_config lc;
  lc.lose_after = w.lose_after;
  lc.restore_after = w.restore_after;
  mb::link_health health(lc);
  // Built at the first response, whose ENID may give the resolution (--resolution absent).
  std::optional<mb::position_tracker> tracker;
  // The library's deadline for the whole transaction, in whole microseconds, plus the host's.
  const std::uint32_t line_ns = tf::transaction_timeout_ns(s.id, s.baud);
  const std::uint64_t deadline_us =
      (std::uint64_t{line_ns} + 999U) / 1000U + std::uint64_t{s.timeout_ms} * 1000U;
  const std::uint64_t interval_us = std::uint64_t{w.interval_ms} * 1000U;
  const std::uint64_t start = serial::now_us64();
  std::uint64_t next = start;
  std::uint64_t reads = 0;
  std::optional<std::uint64_t> last_accepted_us;  // when the last accepted reading was taken
  std::optional<double> rpm;
  int status = 0;
  while (!serial::stop_requested() && (w.count == 0 || reads < w.count)) {
    for (std::uint64_t now = serial::now_us64(); now < next && !serial::stop_requested();
         now = serial::now_us64()) {
      const std::uint64_t left = next - now;
      serial::sleep_us(static_cast<std::uint32_t>(left < sleep_slice_us ? left : sleep_slice_us));
    }
    if (serial::stop_requested()) {
      break;
    }
    const std::uint64_t taken = serial::now_us64();
    next = next + interval_us > taken ? next + interval_us : taken + interval_us;
    ++reads;
    const transaction t = transact(port, rx, s, deadline_us);
    if (t.port_error) {
      status = 1;
      break;
    }
    mb::link_event event = mb::link_event::none;
    mb::position_status ps = mb::position_status::no_reading;
    mb::link_outcome outcome = mb::link_outcome::timeout;
    if (t.result) {
      const auto& r = *t.result;
      if (!tracker && r.is_complete()) {
        const tf::resolution res = resolution_of(s.receiver, r.value());
        tracker.emplace(tf::position_config_for(res, s.id, w.max_step));
      }
      outcome = tf::outcome_of(r);
      event = tf::record(health, r);
      if (tracker) {
        ps = tf::update_position(*tracker, r);
      }
    } else {
      event = health.record_timeout();
      if (tracker) {
        tracker->missed();
      }
    }
    if (ps == mb::position_status::accepted && last_accepted_us && taken > *last_accepted_us) {
      // counts per microsecond between the two readings, as turns per minute
      rpm = static_cast<double>(tracker->step()) * 60e6 /
            (static_cast<double>(taken - *last_accepted_us) *
             static_cast<double>(tracker->counts_per_turn()));
    }
    if (ps == mb::position_status::accepted || ps == mb::position_status::seeded) {
      last_accepted_us = taken;
    }
    if (ps == mb::position_status::seeded) {
      rpm.reset();
    }

    // The read's record: what the transaction gave, then the position and the link.
    cli::record fields;
    fields.add("outcome", mb::to_string(outcome));
    if (t.result && t.result->is_complete()) {
      const tf::response& v = t.result->value();
      if (v.layout().abs()) {
        fields.add("abs", v.abs);
      }
      if (v.layout().abm()) {
        fields.add("abm", v.abm);
      }
      if (v.layout().almc()) {
        fields.hex("almc", v.almc);
      }
    }
    fields.add("position_status", mb::to_string(ps));
    if (tracker && tracker->has_position()) {
      fields.add("counts", tracker->counts())
          .add("turns", tracker->turns())
          .add("within_turn", tracker->within_turn())
          .add("step", tracker->step())
          .add("revolutions", nlohmann::ordered_json(tracker->revolutions()),
               fixed(tracker->revolutions(), 6))
          .add("degrees", nlohmann::ordered_json(tracker->degrees()), fixed(tracker->degrees(), 3));
    }
    if (rpm) {
      fields.add("speed_rpm", nlohmann::ordered_json(*rpm), fixed(*rpm, 3));
    }
    fields.add("link", mb::to_string(health.state()));
    if (event != mb::link_event::none) {
      fields.add("event", event == mb::link_event::lost ? "lost" : "restored");
    }
    const cli::record counts = counters_record(health, tracker ? tracker->implausible_steps() : 0U);
    fields.add("counters", counts.json(), "{" + counts.text() + "}");
    cli::outcome o;
    if (t.result && t.result->is_complete()) {
      o = cli::outcome::success(fields);
    } else if (t.result) {
      o = cli::failure_of(*t.result, 2);
      o.evidence.append(fields);
    } else {
      o = cli::outcome::failure("timeout", fields);
    }
    if (live) {
      const std::string last = o.ok ? mb::to_string(outcome) : o.error;
      std::cout << "\r\x1b[K" << live_line(reads, tracker, rpm, health, last) << std::flush;
    } else {
      cli::record at;
      at.add("read", reads).add("time_us", taken - start);
      cli::print(o, at);
      std::cout.flush();
    }
  }
  if (live && reads > 0) {
    std::cout << '\n';
  }
  // The summary: reads, the link's state and counters, the position reached.
  cli::record summary;
  summary.add("summary", "watch").add("reads", reads).add("link", mb::to_string(health.state()));
  summary.append(counters_record(health, tracker ? tracker->implausible_steps() : 0U));
  if (tracker && tracker->has_position()) {
    summary.add("counts", tracker->counts());
  }
  cli::print_record(summary);
  std::cout.flush();
  // 0: the link is up at the end; 1: lost (or never up), or the port failed.
  return status != 0 || health.lost() ? 1 : 0;
}

}  // namespace tformat_io
