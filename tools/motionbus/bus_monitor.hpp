// The bus monitors' framing, pairing and tally, fed by `monitor` (bytes from a port, with their
// arrival times) and by `decode ... capture` (bytes a UART decoder found in a recording, with
// their start times). Every frame is printed as it is settled (cli::print) with its time and
// direction; a summary record ends the output.
//
// Framing: a frame is taken as soon as its length rule and CRC agree (the function code and
// counts for Modbus, the CF for T-format); bytes that form no frame are reported when the line
// has been silent for the gap. A request is answered when its response arrives before the next
// request or within the response time.
#ifndef MOTIONBUS_TOOLS_BUS_MONITOR_HPP
#define MOTIONBUS_TOOLS_BUS_MONITOR_HPP

#include <motionbus/modbus.hpp>
#include <motionbus/tformat.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "cli.hpp"
#include "modbus_io.hpp"
#include "tformat_io.hpp"

namespace bus_monitor {

namespace mb = motionbus;
namespace mo = motionbus::modbus;
namespace tf = motionbus::tformat;

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

inline cli::record at(std::uint32_t time_us, const char* direction) {
  cli::record p;
  p.add("time_us", static_cast<std::int64_t>(time_us)).add("dir", direction);
  return p;
}

// The read loop: bytes with their arrival time, silences, and the stop conditions. `on_bytes`
// takes the bytes read; `on_tick` runs after every read (with the time since the last byte);

// The bytes heard and not yet framed, each with its start time. On a port, a burst's arrival
// moved back by the bytes' time on the wire (a driver hands bytes over after they arrived), but
// never before the previous frame was complete (a pseudo-terminal hands them over at once); in
// a capture, each byte's own start.
class heard_bytes {
 public:
  explicit heard_bytes(std::uint32_t byte_us) : byte_us_(byte_us) {}

  void add(const std::uint8_t* data, std::size_t n, std::uint32_t time_us) {
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t start = time_us - static_cast<std::uint32_t>(n - i) * byte_us_;
      if (static_cast<std::int32_t>(start - floor_) < 0) {
        start = floor_;
      }
      add_at(data[i], start, time_us);
    }
  }
  void add_at(std::uint8_t byte, std::uint32_t start_us, std::uint32_t end_us) {
    bytes_.push_back(byte);
    starts_.push_back(start_us);
    last_ = end_us;
  }
  /// The first `n` bytes, removed; `time` gets the first one's start.
  std::vector<std::uint8_t> take(std::size_t n, std::uint32_t& time) {
    time = starts_[0];
    std::vector<std::uint8_t> out(bytes_.begin(), bytes_.begin() + static_cast<long>(n));
    bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<long>(n));
    starts_.erase(starts_.begin(), starts_.begin() + static_cast<long>(n));
    floor_ = last_;
    return out;
  }
  const std::vector<std::uint8_t>& held() const { return bytes_; }
  bool empty() const { return bytes_.empty(); }
  std::size_t size() const { return bytes_.size(); }
  std::uint8_t operator[](std::size_t i) const { return bytes_[i]; }
  std::uint32_t start() const { return starts_.empty() ? last_ : starts_[0]; }

 private:
  std::uint32_t byte_us_;
  std::vector<std::uint8_t> bytes_;
  std::vector<std::uint32_t> starts_;
  std::uint32_t last_ = 0;   // the last byte's arrival (or end)
  std::uint32_t floor_ = 0;  // when the last frame taken was complete
};

// What both monitors share: the bytes heard, the silence that ends what no length rule frames,
// the request waiting for its response, the tally. `Protocol` frames (frame(at_silence): takes
// every frame the bytes held begin with; at a silence, whatever is left) and reports a request
// left unanswered (missing(time)).
template <class Protocol>
class line_monitor {
 public:
  line_monitor(std::uint32_t gap_us, std::uint32_t byte_us, std::uint32_t response_us)
      : gap_us_(gap_us), response_us_(response_us), held_(byte_us) {}

  /// Bytes read from a port, with their arrival time.
  void bytes(const std::uint8_t* data, std::size_t n, std::uint32_t time_us) {
    held_.add(data, n, time_us);
    self().frame(false);
  }
  /// A byte a UART decoder found in a recording, with its start and end.
  void byte_at(std::uint8_t byte, std::uint32_t start_us, std::uint32_t end_us) {
    held_.add_at(byte, start_us, end_us);
    self().frame(false);
  }
  /// Time passes: `silent_us` since the last byte.
  void tick(std::uint32_t time_us, std::uint32_t silent_us) {
    if (!held_.empty() && silent_us >= gap_us_) {
      self().frame(true);
    }
    if (pending_ && time_us - pending_time_ >= response_us_) {
      self().missing(time_us);
    }
  }
  /// The line is no longer watched: what is held is settled.
  void end(std::uint32_t time_us) {
    if (!held_.empty()) {
      self().frame(true);
    }
    if (pending_) {
      self().missing(time_us);
    }
  }

  const tally& counts() const { return t_; }

 protected:
  Protocol& self() { return static_cast<Protocol&>(*this); }

  std::uint32_t gap_us_;
  std::uint32_t response_us_;
  heard_bytes held_;
  std::vector<std::uint8_t> request_;
  bool pending_ = false;
  std::uint32_t pending_time_ = 0;
  tally t_;
};

class modbus_monitor : public line_monitor<modbus_monitor> {
 public:
  modbus_monitor(mo::report_id_format fc11, std::uint32_t gap_us, std::uint32_t byte_us,
                 std::uint32_t response_us)
      : line_monitor(gap_us, byte_us, response_us), fc11_(fc11) {}

 private:
  friend class line_monitor<modbus_monitor>;

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
};

class tformat_monitor : public line_monitor<tformat_monitor> {
 public:
  using line_monitor::line_monitor;

 private:
  friend class line_monitor<tformat_monitor>;

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
};

}  // namespace bus_monitor

#endif
