// Passive bus monitors (a port that listens to a tapped line and never sends):
//   monitor modbus --device PATH [--baud N] [--parity E|O|N] [--stop-bits N] [--fc11 sm]
//   monitor tformat --device PATH [--baud N]
//   both: [--count N] [--duration S] [--json]
// Every frame seen, with the microseconds since the monitor started (at its first byte's
// arrival), its direction (request or response, from the pairing), its fields and CRC state;
// a response is paired with its request; a missing response, an exception, a CRC error and
// garbage are flagged. A summary (frames, errors, per slave or Data ID) ends the output.
//
// Framing: a frame is taken as soon as its length rule and CRC agree (the function code and
// counts for Modbus, the CF for T-format); bytes that form no frame are reported when the line
// has been silent for the gap (t3.5 or 20 ms, whichever is longer: a USB adapter hands bytes
// over in bursts, so a host cannot see a character-time gap). A request is answered when its
// response arrives before the next request or within --response-ms.
#include <motionbus/modbus.hpp>
#include <motionbus/tformat.hpp>

#include <cstdint>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "cli.hpp"
#include "modbus_io.hpp"
#include "serial.hpp"
#include "tformat_io.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;
namespace tf = motionbus::tformat;

namespace {

constexpr std::uint32_t min_gap_us = 20000;

// What the monitor counts, for the summary.
struct tally {
  std::uint64_t frames = 0;
  std::uint64_t requests = 0;
  std::uint64_t responses = 0;
  std::uint64_t exceptions = 0;
  std::uint64_t crc_errors = 0;
  std::uint64_t other_errors = 0;
  std::uint64_t missing = 0;
  std::uint64_t garbage_bytes = 0;
  struct per_key {
    std::uint64_t requests = 0;
    std::uint64_t responses = 0;
    std::uint64_t errors = 0;
  };
  std::map<unsigned, per_key> by_key;

  cli::record summary(const char* key_name) const {
    cli::record r;
    r.add_bool("summary", true)
        .add("frames", static_cast<std::int64_t>(frames))
        .add("requests", static_cast<std::int64_t>(requests))
        .add("responses", static_cast<std::int64_t>(responses))
        .add("missing_responses", static_cast<std::int64_t>(missing))
        .add("exceptions", static_cast<std::int64_t>(exceptions))
        .add("crc_errors", static_cast<std::int64_t>(crc_errors))
        .add("other_errors", static_cast<std::int64_t>(other_errors))
        .add("garbage_bytes", static_cast<std::int64_t>(garbage_bytes));
    for (const auto& k : by_key) {
      r.add(std::string(key_name) + "_" + std::to_string(k.first),
            std::vector<std::int64_t>{static_cast<std::int64_t>(k.second.requests),
                                      static_cast<std::int64_t>(k.second.responses),
                                      static_cast<std::int64_t>(k.second.errors)});
    }
    return r;
  }
};

// The stop conditions shared by both monitors.
struct limits {
  std::uint64_t count = 0;     // frames (0: no limit)
  std::uint32_t duration = 0;  // seconds (0: no limit)
  std::uint32_t response_us = 0;

  static limits of(const cli::options& opts) {
    limits l;
    l.count = cli::option_number(opts, "count", 0, ~std::uint64_t{0});
    l.duration = static_cast<std::uint32_t>(cli::option_number(opts, "duration", 0, 4000000));
    l.response_us =
        static_cast<std::uint32_t>(cli::option_number(opts, "response-ms", 1000, 60000)) * 1000U;
    return l;
  }
};

cli::record at(std::uint32_t time_us, const char* direction) {
  cli::record p;
  p.add("time_us", static_cast<std::int64_t>(time_us)).add("dir", direction);
  return p;
}

// The read loop: bytes with their arrival time, silences, and the stop conditions. `on_bytes`
// takes the bytes read; `on_tick` runs after every read (with the time since the last byte);
// `done` says whether enough frames were seen.
template <class OnBytes, class OnTick, class Done>
int listen(serial::port& port, const limits& l, std::uint32_t start, OnBytes on_bytes,
           OnTick on_tick, Done done) {
  serial::install_stop_handler();
  std::uint8_t buffer[256];
  std::uint32_t last_byte = start;
  while (!serial::stop_requested() && !done()) {
    const std::uint32_t now = serial::now_us();
    if (l.duration != 0 && now - start >= l.duration * 1000000U) {
      break;
    }
    const long n = port.read_some(buffer, sizeof buffer, 2);
    if (n < 0) {
      std::cerr << "motionbus: read error\n";
      return 1;
    }
    const std::uint32_t t = serial::now_us();
    if (n > 0) {
      last_byte = t;
      on_bytes(buffer, static_cast<std::size_t>(n), t - start);
    }
    on_tick(t - start, t - last_byte);
  }
  return 0;
}

// The bytes heard and not yet framed, with the time of the first: a burst's arrival moved back
// by the bytes' time on the wire (a driver hands bytes over after they arrived), but never
// before the previous frame was complete (a pseudo-terminal hands them over at once).
class heard_bytes {
 public:
  explicit heard_bytes(std::uint32_t byte_us) : byte_us_(byte_us) {}

  void add(const std::uint8_t* data, std::size_t n, std::uint32_t time_us) {
    if (bytes_.empty()) {
      const std::uint32_t wire = static_cast<std::uint32_t>(n) * byte_us_;
      start_ = time_us - wire;
      if (static_cast<std::int32_t>(start_ - floor_) < 0) {
        start_ = floor_;
      }
    }
    bytes_.insert(bytes_.end(), data, data + n);
    last_ = time_us;
  }
  /// The first `n` bytes, removed; `time` gets the first one's time.
  std::vector<std::uint8_t> take(std::size_t n, std::uint32_t& time) {
    std::vector<std::uint8_t> out(bytes_.begin(), bytes_.begin() + static_cast<long>(n));
    bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<long>(n));
    time = start_;
    start_ += static_cast<std::uint32_t>(n) * byte_us_;
    floor_ = last_;
    return out;
  }
  const std::vector<std::uint8_t>& held() const { return bytes_; }
  bool empty() const { return bytes_.empty(); }
  std::size_t size() const { return bytes_.size(); }
  std::uint8_t operator[](std::size_t i) const { return bytes_[i]; }
  std::uint32_t start() const { return start_; }

 private:
  std::uint32_t byte_us_;
  std::vector<std::uint8_t> bytes_;
  std::uint32_t start_ = 0;
  std::uint32_t last_ = 0;   // the last burst's arrival
  std::uint32_t floor_ = 0;  // when the last frame taken was complete
};

// --- Modbus RTU ---------------------------------------------------------------------------------

class modbus_monitor {
 public:
  modbus_monitor(mo::report_id_format fc11, std::uint32_t gap_us, std::uint32_t byte_us,
                 std::uint32_t response_us)
      : fc11_(fc11), gap_us_(gap_us), response_us_(response_us), held_(byte_us) {}

  void bytes(const std::uint8_t* data, std::size_t n, std::uint32_t time_us) {
    held_.add(data, n, time_us);
    frame(false);
  }

  void tick(std::uint32_t time_us, std::uint32_t silent_us) {
    if (!held_.empty() && silent_us >= gap_us_) {
      frame(true);
    }
    if (pending_ && time_us - pending_time_ >= response_us_) {
      missing(time_us);
    }
  }

  void end(std::uint32_t time_us) {
    if (!held_.empty()) {
      frame(true);
    }
    if (pending_) {
      missing(time_us);
    }
  }

  const tally& counts() const { return t_; }

 private:
  // Takes every frame the bytes held begin with; at a silence, whatever is left is one frame
  // (or garbage).
  void frame(bool at_silence) {
    while (!held_.empty()) {
      const mb::byte_view in(held_.held().data(), held_.size());
      const std::size_t n = complete_frame(in);
      if (n > 0) {
        take(n);
        continue;
      }
      if (!at_silence) {
        return;
      }
      take(held_.size());
    }
  }

  // The size of a CRC-valid frame at the front of `in` (a response to the pending request
  // first), 0 when none is complete yet.
  std::size_t complete_frame(mb::byte_view in) const {
    std::size_t sizes[2] = {0, 0};
    if (pending_) {
      sizes[0] = mo::predict_response_size(in, request_[1], fc11_);
    }
    sizes[1] = mo::predict_request_size(in);
    for (const std::size_t size : sizes) {
      if (size >= 4U && size != mo::unknown_length && size <= in.size() &&
          mo::decode_rtu(in.first(size)).is_complete()) {
        return size;
      }
    }
    return 0;
  }

  void take(std::size_t n) {
    std::uint32_t time = 0;
    const std::vector<std::uint8_t> bytes = held_.take(n, time);
    report(bytes, time);
  }

  void report(const std::vector<std::uint8_t>& bytes, std::uint32_t time) {
    ++t_.frames;
    const auto f = mo::decode_rtu(mb::byte_view(bytes.data(), bytes.size()));
    if (!f.is_complete()) {
      if (bytes.size() < 4U) {  // not even a frame's address, function and CRC
        t_.garbage_bytes += bytes.size();
        cli::record e;
        e.bytes("bytes", bytes.data(), bytes.size());
        cli::print(cli::outcome::failure("garbage", e), at(time, "?"));
        return;
      }
      if (f.error() == mb::errc::crc_mismatch) {
        ++t_.crc_errors;
      } else {
        ++t_.other_errors;
      }
      cli::outcome o = cli::failure_of(f, 4);
      o.evidence.add("slave", bytes[0]).bytes("bytes", bytes.data(), bytes.size());
      ++t_.by_key[bytes[0]].errors;
      cli::print(o, at(time, "?"));
      return;
    }
    const mo::rtu_frame& frame = f.value();
    if (pending_ && answers(frame)) {
      const auto request = mo::decode_rtu(mb::byte_view(request_.data(), request_.size()));
      cli::outcome o = modbus_io::describe_response(frame, &request.value(), fc11_);
      ++t_.responses;
      ++t_.by_key[frame.slave].responses;
      if (!o.ok) {
        ++t_.other_errors;
        ++t_.by_key[frame.slave].errors;
      } else if (frame.pdu[0] >= mo::exception_flag) {
        ++t_.exceptions;
        ++t_.by_key[frame.slave].errors;
      }
      cli::record p = at(time, "response");
      p.add("latency_us", static_cast<std::int64_t>(time - pending_time_));
      cli::print(o, p);
      pending_ = false;
      return;
    }
    if (pending_) {
      missing(time);  // a request follows a request
    }
    ++t_.requests;
    ++t_.by_key[frame.slave].requests;
    const cli::outcome o = modbus_io::describe_request(frame);
    cli::print(o, at(time, "request"));
    if (frame.slave != mo::broadcast_address) {  // a broadcast is never answered
      request_ = bytes;
      pending_ = true;
      pending_time_ = time;
    }
  }

  bool answers(const mo::rtu_frame& f) const {
    return f.slave == request_[0] && (f.pdu[0] & 0x7FU) == request_[1];
  }

  void missing(std::uint32_t time) {
    ++t_.missing;
    ++t_.by_key[request_[0]].errors;
    cli::record e;
    e.add("slave", request_[0]).hex("function", request_[1]);
    e.add("request_time_us", static_cast<std::int64_t>(pending_time_));
    cli::print(cli::outcome::failure("no_response", e), at(time, "response"));
    pending_ = false;
  }

  mo::report_id_format fc11_;
  std::uint32_t gap_us_;
  std::uint32_t response_us_;
  heard_bytes held_;
  std::vector<std::uint8_t> request_;
  bool pending_ = false;
  std::uint32_t pending_time_ = 0;
  tally t_;
};

int monitor_modbus(const cli::options& opts) {
  const limits l = limits::of(opts);
  const serial::settings s = modbus_io::line_settings(opts);
  const mo::report_id_format fc11 = modbus_io::fc11_of(opts, mo::report_id_format::standard);
  serial::port port;
  if (!modbus_io::open_port(port, opts)) {
    return 1;
  }
  const mo::parity p =
      s.parity == 'N' ? mo::parity::none : (s.parity == 'O' ? mo::parity::odd : mo::parity::even);
  const std::uint32_t t35 = mo::t35_us(s.baud, p, s.stop_bits);
  const std::uint32_t bits = 1U + 8U + (s.parity == 'N' ? 0U : 1U) + s.stop_bits;
  modbus_monitor m(fc11, t35 > min_gap_us ? t35 : min_gap_us, bits * 1000000U / s.baud,
                   l.response_us);
  const std::uint32_t start = serial::now_us();
  const int status = listen(
      port, l, start,
      [&](const std::uint8_t* d, std::size_t n, std::uint32_t t) { m.bytes(d, n, t); },
      [&](std::uint32_t t, std::uint32_t silent) { m.tick(t, silent); },
      [&] { return l.count != 0 && m.counts().frames >= l.count; });
  m.end(serial::now_us() - start);
  cli::print_record(m.counts().summary("slave"));
  return status;
}

// --- T-format -----------------------------------------------------------------------------------

class tformat_monitor {
 public:
  tformat_monitor(std::uint32_t gap_us, std::uint32_t byte_us, std::uint32_t response_us)
      : gap_us_(gap_us), response_us_(response_us), held_(byte_us) {}

  void bytes(const std::uint8_t* data, std::size_t n, std::uint32_t time_us) {
    held_.add(data, n, time_us);
    frame(false);
  }

  void tick(std::uint32_t time_us, std::uint32_t silent_us) {
    if (!held_.empty() && silent_us >= gap_us_) {
      frame(true);
    }
    if (pending_ && time_us - pending_time_ >= response_us_) {
      missing(time_us);
    }
  }

  void end(std::uint32_t time_us) {
    if (!held_.empty()) {
      frame(true);
    }
    if (pending_) {
      missing(time_us);
    }
  }

  const tally& counts() const { return t_; }

 private:
  void frame(bool at_silence) {
    while (!held_.empty()) {
      const std::uint8_t cf = held_[0];
      const std::uint8_t code = tf::data_id_code(cf);
      if (cf != tf::valid_control_fields[code]) {  // not a CF: garbage up to the next CF
        std::size_t n = 1;
        while (n < held_.size() &&
               held_[n] != tf::valid_control_fields[tf::data_id_code(held_[n])]) {
          ++n;
        }
        garbage(n);
        continue;
      }
      if (pending_ && cf == request_[0]) {  // the response to the request seen
        const std::size_t size = tf::response_layouts[code].size;
        if (held_.size() < size) {
          if (!at_silence) {
            return;
          }
          failed(held_.size(), "response", cli::outcome::failure("truncated"));
          pending_ = false;
          continue;
        }
        response(size);
        continue;
      }
      if (pending_) {
        missing(held_.start());  // another request: the last one went unanswered
      }
      const mb::byte_view in(held_.held().data(), held_.size());
      const auto q = tf::decode_request(in);
      if (q.is_incomplete()) {
        if (!at_silence) {
          return;
        }
        failed(held_.size(), "request", cli::outcome::failure("truncated"));
        continue;
      }
      if (q.is_failed()) {
        failed(tf::request_size(static_cast<tf::data_id>(code)) < held_.size()
                   ? tf::request_size(static_cast<tf::data_id>(code))
                   : held_.size(),
               "request", cli::failure_of(q, 2));
        continue;
      }
      request(q.consumed(), q.value());
    }
  }

  std::vector<std::uint8_t> take(std::size_t n, std::uint32_t& time) {
    ++t_.frames;
    return held_.take(n, time);
  }

  void request(std::size_t n, const tf::request& q) {
    std::uint32_t time = 0;
    request_ = take(n, time);
    ++t_.requests;
    ++t_.by_key[static_cast<unsigned>(q.id)].requests;
    cli::print(cli::outcome::success(tformat_io::request_record(q)), at(time, "request"));
    pending_ = true;
    pending_time_ = time;
  }

  void response(std::size_t n) {
    std::uint32_t time = 0;
    const std::vector<std::uint8_t> bytes = take(n, time);
    const auto r = tf::decode_response_for(mb::byte_view(request_.data(), request_.size()),
                                           mb::byte_view(bytes.data(), bytes.size()));
    const unsigned id = tf::data_id_code(request_[0]);
    cli::record p = at(time, "response");
    p.add("latency_us", static_cast<std::int64_t>(time - pending_time_));
    pending_ = false;
    ++t_.responses;
    ++t_.by_key[id].responses;
    if (!r.is_complete()) {
      count_error(r.error(), id);
      cli::outcome o = cli::failure_of(r, 2);
      o.evidence.bytes("bytes", bytes.data(), bytes.size());
      cli::print(o, p);
      return;
    }
    if ((r->almc != 0U || r->ea0() || r->ea1()) && r->layout().sf()) {
      ++t_.by_key[id].errors;  // the encoder reports an error or alarm: flagged in the fields
    }
    cli::print(cli::outcome::success(tformat_io::response_record(r.value())), p);
  }

  void failed(std::size_t n, const char* direction, cli::outcome o) {
    const unsigned id = tf::data_id_code(held_[0]);
    std::uint32_t time = 0;
    const std::vector<std::uint8_t> bytes = take(n, time);
    count_error(o.error == "crc_mismatch" ? mb::errc::crc_mismatch : mb::errc::truncated, id);
    o.evidence.bytes("bytes", bytes.data(), bytes.size());
    cli::print(o, at(time, direction));
  }

  void garbage(std::size_t n) {
    std::uint32_t time = 0;
    const std::vector<std::uint8_t> bytes = take(n, time);
    t_.garbage_bytes += n;
    cli::record e;
    e.bytes("bytes", bytes.data(), bytes.size());
    cli::print(cli::outcome::failure("garbage", e), at(time, "?"));
  }

  void count_error(mb::errc e, unsigned id) {
    if (e == mb::errc::crc_mismatch) {
      ++t_.crc_errors;
    } else {
      ++t_.other_errors;
    }
    ++t_.by_key[id].errors;
  }

  void missing(std::uint32_t time) {
    ++t_.missing;
    const unsigned id = tf::data_id_code(request_[0]);
    ++t_.by_key[id].errors;
    cli::record e;
    e.add("data_id", static_cast<std::int64_t>(id)).hex("cf", request_[0]);
    e.add("request_time_us", static_cast<std::int64_t>(pending_time_));
    cli::print(cli::outcome::failure("no_response", e), at(time, "response"));
    pending_ = false;
  }

  std::uint32_t gap_us_;
  std::uint32_t response_us_;
  heard_bytes held_;
  std::vector<std::uint8_t> request_;
  bool pending_ = false;
  std::uint32_t pending_time_ = 0;
  tally t_;
};

int monitor_tformat(const cli::options& opts) {
  const limits l = limits::of(opts);
  serial::settings s;
  s.baud = static_cast<unsigned>(cli::option_number(opts, "baud", 2500000, 100000000));
  if (s.baud == 0) {
    throw cli::usage_error{"--baud must be above 0"};
  }
  const auto device = opts.get("device");
  if (!device) {
    throw cli::usage_error{"--device PORT is required"};
  }
  serial::port port;
  if (!serial::open_reporting(port, *device, s)) {
    return 1;
  }
  tformat_monitor m(min_gap_us, 10U * 1000000U / s.baud, l.response_us);
  const std::uint32_t start = serial::now_us();
  const int status = listen(
      port, l, start,
      [&](const std::uint8_t* d, std::size_t n, std::uint32_t t) { m.bytes(d, n, t); },
      [&](std::uint32_t t, std::uint32_t silent) { m.tick(t, silent); },
      [&] { return l.count != 0 && m.counts().frames >= l.count; });
  m.end(serial::now_us() - start);
  cli::print_record(m.counts().summary("data_id"));
  return status;
}

}  // namespace

namespace cli {

protocol_entries monitor_entries() {
  const std::vector<option_use> common = {
      {"count", "0"}, {"duration", "0"}, {"response-ms", "1000"}};
  std::vector<option_use> modbus = {
      "device", {"baud", "9600"}, {"parity", "E"}, {"stop-bits", "1"}, {"fc11", "standard"}};
  modbus.insert(modbus.end(), common.begin(), common.end());
  std::vector<option_use> tformat = {"device", {"baud", "2500000"}};
  tformat.insert(tformat.end(), common.begin(), common.end());
  protocol_entries e;
  e.commands.push_back({"monitor",
                        "modbus",
                        "",
                        "watch a tapped Modbus RTU line: every frame timed, requests paired with "
                        "their responses, missing responses, exceptions, CRC errors and garbage "
                        "flagged, a summary at the end",
                        &monitor_modbus,
                        modbus,
                        {},
                        {}});
  e.commands.push_back({"monitor",
                        "tformat",
                        "",
                        "watch a tapped T-format line: every request and response timed and "
                        "paired, CRC errors, missing responses and garbage flagged, a summary",
                        &monitor_tformat,
                        tformat,
                        {},
                        {}});
  return e;
}

}  // namespace cli
