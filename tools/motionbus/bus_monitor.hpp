// The bus monitors' framing, pairing and tally, fed by `monitor` (bytes from a port, with their
// arrival times) and by `decode ... capture` (bytes a UART decoder found in a recording, with
// their start times). Every frame is printed as it is settled (cli::print) with its time and
// direction; a summary record ends the output.
//
// Framing and pairing: the library's listeners (modbus::rtu_listener, tformat::line_listener):
// a frame is taken as soon as its length rule and CRC agree, after a request its response is
// tried first, and after a bad frame the listener rescans one byte on, so that no valid frame
// behind it is lost. The silence of the gap (the user's --gap-us) is a hint: it settles what
// is held, it is not the delimiter. A request is answered when its response arrives before the
// next request or within the response time. A byte with a UART error (a capture's parity or
// framing error) makes its frame fail, with the byte's index and the frame's bytes.
#ifndef MOTIONBUS_TOOLS_BUS_MONITOR_HPP
#define MOTIONBUS_TOOLS_BUS_MONITOR_HPP

#include <motionbus/modbus.hpp>
#include <motionbus/tformat.hpp>
#include <motionbus/tformat/listener.hpp>

#include <cstdint>
#include <deque>
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
        .add("frames", frames)
        .add("requests", requests)
        .add("responses", responses)
        .add("missing_responses", missing)
        .add("exceptions", exceptions)
        .add("crc_errors", crc_errors)
        .add("other_errors", other_errors)
        .add("garbage_bytes", garbage_bytes);
    for (const auto& k : by_key) {
      r.add(std::string(key_name) + "_" + std::to_string(k.first),
            std::vector<std::uint64_t>{k.second.requests, k.second.responses, k.second.errors});
    }
    return r;
  }
};

inline cli::record at(std::uint64_t time_us, const char* direction) {
  cli::record p;
  p.add("time_us", time_us).add("dir", direction);
  return p;
}

// A byte heard and not yet settled: its value, start time, and the UART error a capture's
// decoder found in it (parity_error, framing_error; nullptr: none).
struct heard_byte {
  std::uint8_t value;
  std::uint64_t start;
  const char* uart_error;
};

// What both monitors share: the bytes heard (given one at a time to the library's listener,
// rtu_listener or tformat::line_listener, which frames and pairs them: one framing
// implementation for the firmware, the library's users and the tools), the user's silence
// (the gap: a hint, idle() to the listener), the request waiting for its response, the tally.
// The bytes the listener drops (a rejected frame, garbage) are reported as one run when the
// next frame or the silence settles them. `Protocol` reports a frame (frame(result, bytes,
// time)) and a request left unanswered (missing(time)).
template <class Protocol, class Listener>
class line_monitor {
 public:
  line_monitor(Listener listener, std::uint32_t gap_us, std::uint32_t byte_us,
               std::uint64_t response_us)
      : listener_(listener), gap_us_(gap_us), byte_us_(byte_us), response_us_(response_us) {}

  /// Bytes read from a port, with their arrival time (microseconds since the watch began): each
  /// byte's start is moved back by the bytes' time on the wire (a driver hands bytes over after
  /// they arrived), never before the last byte's, nor before the watch began (bytes waiting in
  /// the driver when it began are timed 0).
  void bytes(const std::uint8_t* data, std::size_t n, std::uint64_t time_us) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t on_wire = std::uint64_t{n - i} * byte_us_;
      std::uint64_t start = time_us > on_wire ? time_us - on_wire : 0;
      if (!first_ && start < last_start_) {
        start = last_start_;
      }
      byte_at(data[i], start, nullptr);
    }
  }
  /// A byte a UART decoder found (its start), with the UART error it found, if any.
  void byte_at(std::uint8_t byte, std::uint64_t start_us, const char* uart_error) {
    first_ = false;
    last_start_ = start_us;
    heard_.push_back({byte, start_us, uart_error});
    mb::put_each(listener_, byte, [&](const auto& r) {
      settle(r);
      return true;
    });
  }
  /// Time passes: `silent_us` since the last byte. A silence of the gap settles what is held.
  /// A request's response is missing once the response time has passed since the request
  /// began, reported at that deadline; but bytes that began before the deadline are first
  /// settled (they may be the response, or a request that reports it missing at its own start),
  /// so that the records' times rise.
  void tick(std::uint64_t time_us, std::uint64_t silent_us) {
    settle_missing(time_us);
    if (!heard_.empty() && silent_us >= gap_us_) {
      silence();
    }
    settle_missing(time_us);
  }
  /// The line is no longer watched: what is held is settled.
  void end(std::uint64_t time_us) {
    silence();
    if (pending_) {
      self().missing(time_us);
    }
  }

  const tally& counts() const { return t_; }
  /// The bytes heard and not yet settled (none after end()).
  std::size_t held() const { return heard_.size(); }

 protected:
  Protocol& self() { return static_cast<Protocol&>(*this); }

  void settle_missing(std::uint64_t time_us) {
    if (!pending_ || time_us - pending_time_ < response_us_) {
      return;
    }
    const std::uint64_t deadline = pending_time_ + response_us_;
    // (bytes that began after the deadline may have been settled first)
    if (heard_.empty() || heard_.front().start >= deadline) {
      self().missing(deadline > printed_ ? deadline : printed_);
    }
  }

  void silence() {
    for (auto r = listener_.idle(); !r.is_incomplete(); r = listener_.idle()) {
      settle(r);
    }
    flush(heard_.size() - listener_.pending());
  }

  // A result of the listener: the bytes it no longer holds are settled.
  template <class Result>
  void settle(const Result& r) {
    const std::size_t settled = heard_.size() - listener_.pending();
    if (!r.is_complete()) {
      if (failure_.empty()) {
        failure_ = mb::to_string(r.error());
        expected_ = r.expected();
        received_ = r.received();
      }
      return;
    }
    const std::size_t n = self().size_of(r.value());
    flush(settled - n);
    std::vector<std::uint8_t> frame;
    const char* uart_error = nullptr;
    std::size_t error_at = 0;
    const std::uint64_t time = heard_.front().start;
    printed_ = time;
    for (std::size_t i = 0; i < n; ++i) {
      frame.push_back(heard_.front().value);
      if (uart_error == nullptr && heard_.front().uart_error != nullptr) {
        uart_error = heard_.front().uart_error;
        error_at = i;
      }
      heard_.pop_front();
    }
    ++t_.frames;
    if (uart_error != nullptr) {  // a byte the UART flagged: the frame fails, with the evidence
      ++t_.other_errors;
      cli::record e;
      e.add("byte_index", error_at).bytes("bytes", frame.data(), frame.size());
      cli::print(cli::outcome::failure(uart_error, e), at(time, "?"));
      self().rejected(r.value(), frame, time);
      return;
    }
    self().frame(r.value(), frame, time);
  }

  // The first `n` bytes heard, dropped by the listener: one failure (the first the listener
  // reported for them, else garbage), with the bytes.
  void flush(std::size_t n) {
    if (n == 0U) {
      failure_.clear();
      return;
    }
    std::vector<std::uint8_t> bad;
    const char* uart_error = nullptr;
    const std::uint64_t time = heard_.front().start;
    printed_ = time;
    for (std::size_t i = 0; i < n; ++i) {
      bad.push_back(heard_.front().value);
      if (uart_error == nullptr) {
        uart_error = heard_.front().uart_error;
      }
      heard_.pop_front();
    }
    ++t_.frames;
    cli::record e;
    if (failure_.empty()) {
      t_.garbage_bytes += n;
    } else {
      ++(failure_ == "crc_mismatch" ? t_.crc_errors : t_.other_errors);
      if (expected_ != received_) {
        e.hex("expected", expected_, self().crc_digits)
            .hex("received", received_, self().crc_digits);
      }
    }
    if (uart_error != nullptr) {
      e.add("uart_error", uart_error);
    }
    e.bytes("bytes", bad.data(), bad.size());
    cli::print(cli::outcome::failure(failure_.empty() ? "garbage" : failure_, e),
               at(time, self().rejected_run(!failure_.empty(), failure_ == "truncated", bad[0])));
    failure_.clear();
  }

  Listener listener_;
  std::uint32_t gap_us_;
  std::uint32_t byte_us_;
  std::uint64_t response_us_;  // ~0: none (a recording: the next request or the end settles)
  std::deque<heard_byte> heard_;
  bool first_ = true;
  std::uint64_t last_start_ = 0;
  std::uint64_t printed_ = 0;  // the time of the last frame or run of bytes settled
  std::string failure_;        // the first failure among the bytes dropped since the last frame
  std::uint32_t expected_ = 0;
  std::uint32_t received_ = 0;
  std::vector<std::uint8_t> request_;
  bool pending_ = false;
  std::uint64_t pending_time_ = 0;
  tally t_;
};

class modbus_monitor : public line_monitor<modbus_monitor, mo::rtu_listener> {
 public:
  modbus_monitor(mo::report_id_format fc11, std::uint32_t gap_us, std::uint32_t byte_us,
                 std::uint64_t response_us)
      : line_monitor(mo::rtu_listener(listener_options(fc11)), gap_us, byte_us, response_us),
        fc11_(fc11) {}

 private:
  friend class line_monitor<modbus_monitor, mo::rtu_listener>;
  static constexpr int crc_digits = 4;

  static mo::framer_options listener_options(mo::report_id_format fc11) {
    mo::framer_options o;
    o.fc11 = fc11;
    return o;
  }

  static std::size_t size_of(const mo::rtu_frame& f) { return f.pdu.size() + 3U; }
  // Bytes the listener dropped: a frame no rule and CRC confirmed, of either direction.
  const char* rejected_run(bool failed, bool /*truncated*/, std::uint8_t slave) {
    if (failed) {
      ++t_.by_key[slave].errors;
    }
    return "?";
  }

  // A frame that failed for a UART error: the pairing follows the listener's reading of it.
  void rejected(const mo::rtu_frame& f, const std::vector<std::uint8_t>& bytes,
                std::uint64_t time) {
    ++t_.by_key[f.slave].errors;
    if (listener_.heard_response()) {
      pending_ = false;
    } else {
      note_request(f, bytes, time);
    }
  }

  void note_request(const mo::rtu_frame& f, const std::vector<std::uint8_t>& bytes,
                    std::uint64_t time) {
    if (pending_) {
      missing(time);  // a request follows a request
    }
    if (f.slave != mo::broadcast_address) {  // a broadcast is never answered
      request_ = bytes;
      pending_ = true;
      pending_time_ = time;
    }
  }

  void frame(const mo::rtu_frame& f, const std::vector<std::uint8_t>& bytes, std::uint64_t time) {
    if (listener_.heard_response()) {
      const auto request = mo::decode_rtu(mb::byte_view(request_.data(), request_.size()));
      const bool paired = pending_ && request.is_complete();
      cli::outcome o = modbus_io::describe_response(f, paired ? &request.value() : nullptr, fc11_);
      ++t_.responses;
      ++t_.by_key[f.slave].responses;
      if (!o.ok) {
        ++t_.other_errors;
        ++t_.by_key[f.slave].errors;
      } else if (f.pdu[0] >= mo::exception_flag) {
        ++t_.exceptions;
        ++t_.by_key[f.slave].errors;
      }
      cli::record p = at(time, "response");
      if (paired) {
        p.add("latency_us", time - pending_time_);
      }
      cli::print(o, p);
      pending_ = false;
      return;
    }
    ++t_.requests;
    ++t_.by_key[f.slave].requests;
    const cli::outcome o = modbus_io::describe_request(f);
    if (pending_) {
      missing(time);
    }
    cli::print(o, at(time, "request"));
    note_request(f, bytes, time);
  }

  void missing(std::uint64_t time) {
    ++t_.missing;
    ++t_.by_key[request_[0]].errors;
    cli::record e;
    e.add("slave", request_[0]).hex("function", request_[1]);
    e.add("request_time_us", pending_time_);
    cli::print(cli::outcome::failure("no_response", e), at(time, "response"));
    pending_ = false;
  }

  mo::report_id_format fc11_;
};

class tformat_monitor : public line_monitor<tformat_monitor, tf::line_listener> {
 public:
  tformat_monitor(std::uint32_t gap_us, std::uint32_t byte_us, std::uint64_t response_us)
      : line_monitor(tf::line_listener(), gap_us, byte_us, response_us) {}

 private:
  friend class line_monitor<tformat_monitor, tf::line_listener>;
  static constexpr int crc_digits = 2;

  static std::size_t size_of(const tf::heard& h) { return h.bytes.size(); }
  // Bytes the listener dropped: a rejected response (the listener rejects only responses; it
  // answers the request before it), a request cut short (truncated, its CF no response's:
  // neither the request's nor ID3's, or no request pending), or garbage.
  const char* rejected_run(bool failed, bool truncated, std::uint8_t cf) {
    if (!failed) {
      return "?";
    }
    const bool response_start =
        pending_ && !request_.empty() && (cf == request_[0] || cf == tf::control_fields[3]);
    if (truncated && !response_start) {
      ++t_.by_key[tf::data_id_code(cf)].errors;
      return "request";
    }
    if (pending_) {
      ++t_.responses;
      ++t_.by_key[tf::data_id_code(request_[0])].errors;
      pending_ = false;
    }
    return "response";
  }

  void rejected(const tf::heard& h, const std::vector<std::uint8_t>& bytes, std::uint64_t time) {
    const unsigned id = tf::data_id_code(bytes[0]);
    ++t_.by_key[id].errors;
    if (h.is_response) {
      pending_ = false;
    } else {
      note_request(bytes, time);
    }
  }

  void note_request(const std::vector<std::uint8_t>& bytes, std::uint64_t time) {
    request_ = bytes;
    pending_ = true;
    pending_time_ = time;
  }

  void frame(const tf::heard& h, const std::vector<std::uint8_t>& bytes, std::uint64_t time) {
    if (!h.is_response) {
      if (pending_) {
        missing(time);  // another request: the last one went unanswered
      }
      const unsigned id = tf::data_id_code(h.req.cf);
      ++t_.requests;
      ++t_.by_key[id].requests;
      if (h.request_error != mb::errc::ok) {
        // an abnormal request (spec §8.4 Table 5, §9.4 Table 6): the encoder answers ID3 data
        ++t_.other_errors;
        ++t_.by_key[id].errors;
        cli::record e;
        e.hex("cf", h.req.cf).bytes("bytes", bytes.data(), bytes.size());
        cli::print(cli::outcome::failure(mb::to_string(h.request_error), e), at(time, "request"));
      } else {
        cli::print(cli::outcome::success(tformat_io::request_record(h.req)), at(time, "request"));
      }
      note_request(bytes, time);
      return;
    }
    const unsigned id = pending_ ? tf::data_id_code(request_[0]) : tf::data_id_code(bytes[0]);
    cli::record p = at(time, "response");
    if (pending_) {
      p.add("latency_us", time - pending_time_);
    }
    pending_ = false;
    ++t_.responses;
    ++t_.by_key[id].responses;
    cli::record fields = tformat_io::response_record(h.resp);
    const bool alarm = h.resp.layout().sf() && (h.resp.sf & (tf::sf::ca0 | tf::sf::ca1)) != 0U;
    if (h.id3_reply) {
      fields.add_bool("id3_reply", true);  // the request was abnormal (spec §6.3.2)
    }
    if (h.id3_reply || alarm ||
        ((h.resp.almc != 0U || h.resp.ea0() || h.resp.ea1()) && h.resp.layout().sf())) {
      ++t_.by_key[id].errors;  // the encoder reports an error or alarm: flagged in the fields
    }
    cli::print(cli::outcome::success(fields), p);
  }

  void missing(std::uint64_t time) {
    ++t_.missing;
    const unsigned id = tf::data_id_code(request_[0]);
    ++t_.by_key[id].errors;
    cli::record e;
    e.add("data_id", id).hex("cf", request_[0]);
    e.add("request_time_us", pending_time_);
    cli::print(cli::outcome::failure("no_response", e), at(time, "response"));
    pending_ = false;
  }
};

}  // namespace bus_monitor

#endif
