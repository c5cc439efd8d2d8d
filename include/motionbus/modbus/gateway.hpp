// motionbus — the core of a Modbus TCP to RTU gateway: MBAP requests in from client
// connections, RTU requests out on one serial line, one at a time; the line's responses, its
// silence or the response timeout in, MBAP responses out to the connection that asked
// (MODBUS Messaging on TCP/IP Implementation Guide V1.0b §3.1.3, §4.4.2: the unit identifier
// of a request to a gateway is the serial slave address, 0 a broadcast; MODBUS over Serial
// Line V1.02 §2.1, §2.4.1: one request on the line at a time, broadcasts are writes, never
// answered, and followed by a turnaround delay; MODBUS Application Protocol V1.1b3 §7:
// exceptions 0A and 0B). A state machine: no I/O, no heap, no clock of its own; the I/O hands
// it bytes and the time, and does what each call's gateway_step says (docs/modbus.md §12).
//
//   modbus::gateway gw(options);                 // 8 connections, 16 queued requests
//   auto act = [&](const gateway_step& s) {       // what the I/O does for each step
//     if (s.action == gateway_action::to_client) send(s.connection, s.bytes);
//     if (s.action == gateway_action::to_line) write_line(s.bytes);
//     if (s.action == gateway_action::close) close_socket(s.connection);
//   };
//   on_client_bytes(c, in):   feed_client(gw, c, in, act);   // slot c, a chunk of its stream
//   on_client_closed(c), or its idle timeout:   gw.close(c); // its bytes, its queued requests
//   on_line_bytes(in):        feed_line(gw, in, now_us(), act);  // with the time they came
//   after any of these, and when gw.wait_us(now) has passed (the poll()/select() timeout):
//                             poll_all(gw, now_us(), act);
//
// Timing is data and events in one style: every call that depends on time is given the time
// (microseconds of a free-running clock, wrapping: differences only), and the core keeps its
// deadlines: the response timeout (from the end of the request on the line, its bytes at the
// line's character time), the t3.5 silence at the line's rate (it ends a response whose length
// the bytes do not give, and separates the next request from the last frame), the turnaround
// delay after a broadcast. poll() acts on whatever is due; wait_us() says when the next is.
//
// Checks before the line (a request that fails one is answered at once, nothing is sent):
//   unit not allowed (gateway_options::units), or above 247   exception 0A (no path)
//   function not allowed (gateway_options::functions), or a write under read_only   01
//   the PDU's own checks (decode_request)                     01, 03 or 02, as a server's
//   a broadcast (unit 0) of a function that is no write       0A (Serial Line §2.1)
//   the queue full                                            0A (App. Protocol §7: "the
//                                              gateway is misconfigured or overloaded")
// 06 (server busy) is left to the devices: it says a device is busy with a long program
// command, which a full queue in front of them is not. A connection whose stream breaks the
// MBAP framing (protocol id not 0, a length field outside 2..254: an ADU over 260 bytes, or a
// length the PDU's own length rule contradicts) is closed: gateway_action::close, the core
// has dropped it; the other connections and the line go on.
//
// Responses: the first CRC-valid frame from the addressed slave with the request's function
// (or its exception) is the response, forwarded as it is (the gateway is transparent: the
// client checks the response against its request); other frames on the line are discarded
// (discarded()). No response by the timeout: exception 0B to the client; the deadline wins
// (a response that begins after it is not taken, even if poll() has not run yet: from_line
// answers the 0B then). After a 0B the line takes the next request only once t3.5 of
// silence has followed it (bytes heard on a free line start that t3.5 again), so that a slow
// slave's late response is discarded, not taken for the next request's; a slave that stays
// silent for longer than t3.5 past the timeout and then answers cannot be told from a
// response to the next request. A response for a connection closed meanwhile is dropped (a
// connection slot reused after close() is another connection).
#ifndef MOTIONBUS_MODBUS_GATEWAY_HPP
#define MOTIONBUS_MODBUS_GATEWAY_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/file_record.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/pdu_server.hpp"
#include "motionbus/modbus/rtu.hpp"
#include "motionbus/modbus/tcp.hpp"
#include "motionbus/modbus/timing.hpp"

namespace motionbus {
namespace modbus {

/// A set of unit identifiers (0..255; 0 is the broadcast): 256 bits, no table elsewhere.
struct unit_set {
  std::uint32_t bits[8] = {~0U, ~0U, ~0U, ~0U, ~0U, ~0U, ~0U, ~0U};  ///< all, by default
  static constexpr unit_set none() noexcept { return unit_set{{0, 0, 0, 0, 0, 0, 0, 0}}; }
  constexpr unit_set& add(std::uint8_t unit) noexcept {
    bits[unit / 32U] |= std::uint32_t{1} << (unit % 32U);
    return *this;
  }
  constexpr unit_set& remove(std::uint8_t unit) noexcept {
    bits[unit / 32U] &= ~(std::uint32_t{1} << (unit % 32U));
    return *this;
  }
  constexpr bool contains(std::uint8_t unit) const noexcept {
    return ((bits[unit / 32U] >> (unit % 32U)) & 1U) != 0U;
  }
};

/// The serial line's character time and t3.5 (modbus/timing.hpp), as the gateway uses them.
struct line_timing {
  std::uint32_t char_us = 573;  ///< one character: 19200 baud, 8E1 (11 bits)
  std::uint32_t t35_us = 2006;  ///< t3.5 at 19200 baud
};
/// The timing of a line at `baud`, parity `p`, `stop_bits` (Serial Line §2.5.1.1).
constexpr line_timing serial_line_timing(std::uint32_t baud, parity p = parity::even,
                                         unsigned stop_bits = 1) noexcept {
  return line_timing{character_time_us(baud, p, stop_bits), t35_us(baud, p, stop_bits)};
}

/// The longest response timeout the gateway keeps: 2^30 us (about 17.9 min).
constexpr std::uint32_t max_response_timeout_us = std::uint32_t{1} << 30U;

/// What the gateway is given: its policy and its timing (microseconds).
struct gateway_options {
  /// From the end of a request on the line (its last byte written, at line.char_us a byte)
  /// to its response; a response still arriving then (a byte within t3.5) is waited for, up
  /// to the time of the longest RTU frame more. At most max_response_timeout_us (larger
  /// values are taken as that: the deadlines live on a wrapping clock's half range).
  std::uint32_t response_timeout_us = 1000000;
  /// After a broadcast is on the line, before the next request (Serial Line §2.4.1).
  std::uint32_t turnaround_us = 100000;
  line_timing line{};
  /// The units requests may address (0: broadcast); others are answered with 0A.
  unit_set units{};
  /// The functions forwarded (1..63; 64..127 only with all_functions); others: 01.
  function_set functions = all_functions;
  /// Only reads are forwarded (01-04, 07, 0B, 0C, 11, 14, 18, 08 Return Query Data, 2B/0E);
  /// anything else is refused with 01, so that no unknown function writes either.
  bool read_only = false;
  /// A broadcast write is answered, once it is on the line, with the normal response a
  /// server would give (the request echoed, or its address and quantity); by default a
  /// broadcast is never answered (Serial Line §2.1), as on the line.
  bool answer_broadcasts = false;
  /// The layout of the line's FC11 (Report Server ID) responses: the specification's byte
  /// count and data, or a device's own (report_id_format::two_bytes_no_count: the SM unit).
  report_id_format fc11 = report_id_format::standard;
};

/// What the I/O is to do after a call (gateway_step::action).
enum class gateway_action : std::uint8_t {
  none = 0,       ///< nothing (bytes taken, nothing due yet)
  queued = 1,     ///< from_client: a request was queued for the line (transaction: its id)
  to_client = 2,  ///< send `bytes` (an MBAP response) to `connection`
  to_line = 3,    ///< write `bytes` (an RTU request) to the serial line, now
  close = 4,      ///< close `connection` (`error` says why); the core has dropped it
};

/// The result of one call. `bytes` points into the gateway: use it before the next call.
struct gateway_step {
  gateway_action action = gateway_action::none;
  std::uint8_t connection = 0;
  /// to_client: the exception the gateway answered itself (01, 02, 03, 0A, 0B), 0 for the
  /// line's response or a broadcast's answer.
  std::uint8_t exception = 0;
  errc error = errc::ok;          ///< close: why (invalid_argument, modbus_pdu_length)
  std::uint16_t transaction = 0;  ///< queued, to_client: the client's transaction id
  byte_view bytes{};
  std::size_t consumed = 0;  ///< from_client, from_line: the bytes of `in` taken
};

/// The gateway core for `Connections` client connections (slots 0..Connections-1, the I/O's
/// choice) and one serial line with a queue of `Queue` requests in front of it.
/// Size: each connection a buffer of max_tcp_size and its state, each queued request its PDU
/// (max_pdu_size) and ids; an RTU framer, a line buffer and a reply buffer besides
/// (basic_gateway<1, 1> on a 32-bit core: about 1.5 KiB).
template <std::size_t Connections, std::size_t Queue, crc_table_size Table = default_crc_table>
class basic_gateway {
  static_assert(Connections >= 1U && Connections <= 255U, "1..255 connections");
  static_assert(Queue >= 1U && Queue <= 255U, "a queue of 1..255 requests");

 public:
  constexpr explicit basic_gateway(const gateway_options& options = {}) noexcept
      : options_(options), framer_(framer_options{0, frame_end::silence, options.fc11}) {
    if (options_.response_timeout_us > max_response_timeout_us) {
      options_.response_timeout_us = max_response_timeout_us;
    }
  }

  /// Takes bytes of connection `c`'s stream, up to the end of one MBAP ADU: queued (a request
  /// for the line), to_client (the gateway's own exception to it), close (its MBAP framing
  /// broke; the rest of `in` is taken too), or none (all of `in` taken, an ADU not yet whole:
  /// a half header is kept until more comes or close()). `c` out of range: close, with
  /// connection 255 when `c` is above it (no slot is 255: the step names no connection).
  constexpr gateway_step from_client(std::size_t c, byte_view in) noexcept {
    gateway_step s;
    if (c >= Connections) {
      s.action = gateway_action::close;
      s.connection = static_cast<std::uint8_t>(c < 255U ? c : 255U);
      s.error = errc::invalid_argument;
      s.consumed = in.size();
      return s;
    }
    connection& k = clients_[c];
    std::size_t used = 0;
    for (;;) {
      const std::size_t target = k.size != 0U ? k.size : 6U;  // the header's fixed part first
      while (k.held < target && used < in.size()) {
        k.buf[k.held++] = in[used++];
      }
      if (k.size == 0U) {
        const decode_result<std::size_t> size = tcp_adu_size(byte_view(k.buf, k.held));
        if (size.is_failed()) {
          return closed(c, size.error(), in.size());
        }
        if (size.is_incomplete()) {
          s.consumed = used;
          return s;
        }
        k.size = static_cast<std::uint16_t>(size.value());
        continue;
      }
      if (k.held < k.size) {
        s.consumed = used;
        return s;
      }
      const std::size_t size = k.size;
      k.held = 0;
      k.size = 0;
      s = accept(c, byte_view(k.buf, size));
      s.consumed = s.action == gateway_action::close ? in.size() : used;
      return s;
    }
  }

  /// Connection `c` is gone (closed by its client, or by the I/O on an idle timeout): its
  /// bytes and its queued requests are dropped; a request of it already on the line runs to
  /// its end (the line's timing is kept) and its response goes to no one.
  constexpr void close(std::size_t c) noexcept {
    if (c >= Connections) {
      return;
    }
    connection& k = clients_[c];
    k.held = 0;
    k.size = 0;
    ++k.generation;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < count_; ++i) {
      const entry& e = queue_[(head_ + i) % Queue];
      if (e.who.connection == c) {
        ++dropped_;
      } else {
        queue_[(head_ + kept) % Queue] = e;  // in order: kept <= i
        ++kept;
      }
    }
    count_ = kept;
  }

  /// Bytes from the serial line, received at `now_us`. to_client: the response to the request
  /// on the line, for its connection, or its 0B when `now_us` is past the response timeout
  /// (the deadline wins over bytes that began after it); none: bytes taken (`consumed`),
  /// nothing settled. Bytes while no response is awaited are discarded, and the line takes
  /// the next request t3.5 after them at the earliest.
  constexpr gateway_step from_line(byte_view in, std::uint32_t now_us) noexcept {
    gateway_step s;
    s.consumed = in.size();
    if (state_ == line_state::awaiting &&
        (reached(now_us, last_call_us()) ||
         (framer_.pending() == 0U && reached(now_us, deadline_us_)))) {
      s = expire(now_us);
      s.consumed = in.size();
    }
    if (state_ != line_state::awaiting) {
      if (!in.empty()) {
        ++discarded_;
        quiet(now_us, options_.line.t35_us);  // a busy line: not yet free for a request
      }
      return s;
    }
    last_byte_us_ = in.empty() ? last_byte_us_ : now_us;  // a read that found no byte: none
    const decode_result<rtu_frame> r = framer_.feed(in);
    if (!r.is_complete()) {
      // all taken: the framer (frame_end::silence) holds what it cannot frame until the t3.5
      // silence, which poll() sees: its failures come from idle() there, but for a full
      // buffer with no frame in it (256 bytes held), which feed() reports as it drops them
      s.consumed = r.is_failed() ? r.consumed() : in.size();
      return s;
    }
    gateway_step answer = response(r.value(), now_us);
    answer.consumed = r.consumed();
    return answer;
  }

  /// What is due at `now_us`, one step at a time (call it until none): the t3.5 silence that
  /// ends a response, the response timeout (to_client: exception 0B), the answer to a
  /// broadcast (answer_broadcasts), the next request for the line (to_line) once the line is
  /// free: no request awaiting its response, t3.5 after the last frame, the turnaround after
  /// a broadcast.
  constexpr gateway_step poll(std::uint32_t now_us) noexcept {
    gateway_step s;
    if (broadcast_answer_ != 0U) {
      broadcast_answer_ = 0;
      // built now, from the request still in line_: reply_ is another answer's until here
      const decode_result<request> q = decode_request(byte_view(line_ + 1, line_size_ - 3U));
      std::uint8_t answer[8] = {};  // a write's normal response: 5 or 7 bytes
      const std::size_t size = encode_write_response(q.value(), answer).value_or(0);
      reply_size_ =
          encode_tcp(on_line_.transaction, 0, byte_view(answer, size), reply_).value_or(0);
      // its connection may have gone since; FC15's answer: none the codec builds
      if (current(on_line_) && size != 0U) {
        return to_client_step(on_line_, reply_size_, 0);
      }
    }
    // A response still arriving at the timeout is waited for, as long as the longest frame
    // takes (last_call_us): a line that never falls silent does not hold the gateway.
    const bool late = reached(now_us, last_call_us());
    if (state_ == line_state::awaiting && framer_.pending() != 0U &&
        (late || reached(now_us, last_byte_us_ + options_.line.t35_us))) {
      const decode_result<rtu_frame> r = framer_.idle();  // the silence ends what is held
      if (late || !r.is_complete()) {
        ++discarded_;  // a failure, or too late: the timeout answers if nothing better comes
      } else if (const gateway_step a = response(r.value(), now_us);
                 a.action != gateway_action::none) {
        return a;
      }
    }
    if (state_ == line_state::awaiting) {
      if (!reached(now_us, deadline_us_) || framer_.pending() != 0U) {
        return s;
      }
      if (const gateway_step a = expire(now_us); a.action != gateway_action::none) {
        return a;
      }
    }
    if (quiet_len_ != 0U && quiet_left(now_us) == 0U) {
      quiet_len_ = 0;  // over: it cannot come back on a clock that wraps
    }
    if (count_ == 0U || quiet_len_ != 0U) {
      return s;
    }
    return send(now_us);
  }

  /// How long the I/O may wait before poll() has something timed to do: 0 when something is
  /// due now, 0xFFFFFFFF when nothing is (until the next from_client or from_line).
  constexpr std::uint32_t wait_us(std::uint32_t now_us) const noexcept {
    if (broadcast_answer_ != 0U) {
      return 0;
    }
    if (state_ == line_state::awaiting) {
      if (framer_.pending() == 0U) {
        return until(now_us, deadline_us_);
      }
      const std::uint32_t silence = until(now_us, last_byte_us_ + options_.line.t35_us);
      const std::uint32_t last = until(now_us, last_call_us());
      return silence < last ? silence : last;
    }
    if (count_ == 0U) {
      return ~std::uint32_t{0};
    }
    return quiet_left(now_us);
  }

  /// Requests queued (not yet on the line); whether one is on the line awaiting its response.
  constexpr std::size_t queued() const noexcept { return count_; }
  constexpr bool awaiting() const noexcept { return state_ == line_state::awaiting; }
  /// Responses that never came (0B answered); frames and bytes on the line that were no
  /// awaited response; queued requests dropped by close().
  constexpr std::size_t timeouts() const noexcept { return timeouts_; }
  constexpr std::size_t discarded() const noexcept { return discarded_; }
  constexpr std::size_t dropped() const noexcept { return dropped_; }

 private:
  struct connection {
    std::uint8_t buf[max_tcp_size] = {};
    std::uint16_t held = 0;
    std::uint16_t size = 0;  // the ADU's size once its header told, else 0
    std::uint32_t generation = 0;
  };
  // Whose request it is (and what the gateway answers with itself).
  struct ticket {
    std::uint32_t generation = 0;
    std::uint16_t transaction = 0;
    std::uint8_t connection = 0;
    std::uint8_t unit = 0;
    std::uint8_t function = 0;
  };
  struct entry {
    ticket who{};
    std::uint8_t size = 0;  // of the PDU, 1..253
    std::uint8_t pdu[max_pdu_size] = {};
  };
  enum class line_state : std::uint8_t { free = 0, awaiting = 1 };

  // Whether `now` is at or past `t`, on a wrapping clock (differences under 2^31 us).
  static constexpr bool reached(std::uint32_t now, std::uint32_t t) noexcept {
    return now - t < 0x80000000U;
  }
  static constexpr std::uint32_t until(std::uint32_t now, std::uint32_t t) noexcept {
    return reached(now, t) ? 0U : t - now;
  }

  // The functions read_only lets through (MODBUS Application Protocol V1.1b3 §6).
  static constexpr bool reads_only(byte_view pdu) noexcept {
    const std::uint8_t f = pdu[0];
    if (f == 0x08U) {  // Diagnostics: Return Query Data only (the others change counters, modes)
      return pdu.size() >= 3U && pdu[1] == 0U && pdu[2] == 0U;
    }
    if (f == 0x2BU) {  // MEI: Read Device Identification only
      return pdu.size() >= 2U && pdu[1] == mei_read_device_identification;
    }
    return in_function_set<functions_of(0x01, 0x02, 0x03, 0x04, 0x07, 0x0B, 0x0C, 0x11, 0x14,
                                        0x18)>(f);
  }
  // The writes a broadcast may carry (Serial Line §2.1: broadcasts are writes; 17 also reads).
  static constexpr bool broadcast_write(std::uint8_t f) noexcept {
    return in_function_set<functions_of(0x05, 0x06, 0x0F, 0x10, 0x15, 0x16)>(f);
  }
  constexpr bool function_allowed(std::uint8_t f) const noexcept {
    if (options_.functions == all_functions) {
      return true;
    }
    return f < 64U && ((options_.functions >> f) & 1U) != 0U;
  }

  constexpr bool current(const ticket& e) const noexcept {
    return clients_[e.connection].generation == e.generation;
  }

  constexpr gateway_step closed(std::size_t c, errc e, std::size_t consumed) noexcept {
    close(c);
    gateway_step s;
    s.action = gateway_action::close;
    s.connection = static_cast<std::uint8_t>(c);
    s.error = e;
    s.consumed = consumed;
    return s;
  }

  constexpr gateway_step to_client_step(const ticket& e, std::size_t size,
                                        std::uint8_t exception) const noexcept {
    gateway_step s;
    s.action = gateway_action::to_client;
    s.connection = e.connection;
    s.exception = exception;
    s.transaction = e.transaction;
    s.bytes = byte_view(reply_, size);
    return s;
  }

  // The gateway's own exception `code` to request `e`.
  constexpr gateway_step own_answer(const ticket& e, std::uint8_t code) noexcept {
    std::uint8_t pdu[2] = {};
    (void)encode_exception(e.function, code, pdu);
    reply_size_ = encode_tcp(e.transaction, e.unit, pdu, reply_).value_or(0);
    return to_client_step(e, reply_size_, code);
  }

  // One whole MBAP ADU from connection `c` (its protocol id and length checked).
  constexpr gateway_step accept(std::size_t c, byte_view adu) noexcept {
    const decode_result<tcp_frame> d = decode_tcp(adu);
    const tcp_frame& t = d.value();  // complete: tcp_adu_size checked its header
    const byte_view pdu = t.pdu;
    const std::uint8_t f = pdu[0];
    // The MBAP length must agree with the PDU's own length rule (its function's fixed size or
    // its byte count; FC08 and FC2B have none that is exact): else the stream is not framed
    // where its length says, and the connection is closed.
    const std::size_t rule = predict_request_size(adu.subspan(6));  // unit, then the PDU
    if (f != 0x08U && f != 0x2BU && rule != unknown_length && rule != 0U &&
        rule != pdu.size() + 3U) {
      return closed(c, errc::modbus_pdu_length, 0);
    }
    ticket e;
    e.generation = clients_[c].generation;
    e.transaction = t.transaction;
    e.connection = static_cast<std::uint8_t>(c);
    e.unit = t.unit;
    e.function = f;
    std::uint8_t code = 0;
    if (t.unit > max_unicast_address || !options_.units.contains(t.unit)) {
      code = static_cast<std::uint8_t>(exception_code::gateway_path_unavailable);
    } else if (!function_allowed(f) || (options_.read_only && !reads_only(pdu))) {
      code = static_cast<std::uint8_t>(exception_code::illegal_function);
    } else {
      const decode_result<request> q = decode_request(pdu);
      // FC14/15: decode_request leaves their sub-requests to decode_file_record_request
      const errc fr = f == read_file_record_function || f == write_file_record_function
                          ? decode_file_record_request(pdu).error()
                          : errc::ok;
      if (!q.is_complete()) {
        code = static_cast<std::uint8_t>(exception_for(q.error()));
      } else if (fr != errc::ok) {
        code = static_cast<std::uint8_t>(exception_for(fr));
      } else if ((t.unit == broadcast_address && !broadcast_write(f)) || count_ == Queue) {
        code = static_cast<std::uint8_t>(exception_code::gateway_path_unavailable);
      }
    }
    if (code != 0U) {
      return own_answer(e, code);
    }
    entry& slot = queue_[(head_ + count_) % Queue];  // built in place: no copy of the PDU
    slot.who = e;
    slot.size = static_cast<std::uint8_t>(pdu.size());
    for (std::size_t i = 0; i < pdu.size(); ++i) {
      slot.pdu[i] = pdu[i];
    }
    ++count_;
    gateway_step s;
    s.action = gateway_action::queued;
    s.connection = e.connection;
    s.transaction = e.transaction;
    return s;
  }

  // The next queued request onto the line.
  constexpr gateway_step send(std::uint32_t now_us) noexcept {
    const entry& e = queue_[head_];  // read before anything is queued again
    const byte_view pdu(e.pdu, e.size);
    on_line_ = e.who;
    head_ = (head_ + 1U) % Queue;
    --count_;
    const std::size_t n = encode_rtu<Table>(on_line_.unit, pdu, line_).value_or(0);
    line_size_ = n;
    framer_.sent(byte_view(line_, n));
    const std::uint32_t sending = static_cast<std::uint32_t>(n) * options_.line.char_us;
    const std::uint32_t end = now_us + sending;
    last_byte_us_ = end;
    if (on_line_.unit == broadcast_address) {
      quiet(now_us, sending + options_.turnaround_us);
      // its answer is built and its connection checked in poll() (answer_broadcasts)
      broadcast_answer_ = options_.answer_broadcasts ? 1U : 0U;
    } else {
      state_ = line_state::awaiting;
      deadline_us_ = end + options_.response_timeout_us;
    }
    gateway_step s;
    s.action = gateway_action::to_line;
    s.connection = on_line_.connection;
    s.transaction = on_line_.transaction;
    s.bytes = byte_view(line_, n);
    return s;
  }

  // A frame from the line while a response is awaited: the response (its function, or its
  // exception) ends the wait; anything else is discarded.
  constexpr gateway_step response(const rtu_frame& frame, std::uint32_t now_us) noexcept {
    // (a frame's PDU is never empty: decode_rtu wants one byte at least)
    if ((frame.pdu[0] & static_cast<std::uint8_t>(~exception_flag)) != on_line_.function) {
      ++discarded_;
      return gateway_step{};
    }
    free_line(now_us);
    if (!current(on_line_)) {
      return gateway_step{};  // its connection was closed meanwhile
    }
    reply_size_ = encode_tcp(on_line_.transaction, on_line_.unit, frame.pdu, reply_).value_or(0);
    return to_client_step(on_line_, reply_size_, 0);
  }

  // The response timeout's end, extended by the time of the longest frame.
  constexpr std::uint32_t last_call_us() const noexcept {
    return deadline_us_ + static_cast<std::uint32_t>(max_rtu_size) * options_.line.char_us;
  }

  // The wait is over: the next request t3.5 after the last byte heard (or now).
  constexpr void free_line(std::uint32_t now_us) noexcept {
    state_ = line_state::free;
    const std::uint32_t quiet_for = now_us - last_byte_us_;  // (last_byte_us_: at or before)
    if (quiet_for < options_.line.t35_us) {
      quiet(now_us, options_.line.t35_us - quiet_for);
    }
  }

  // The response timeout is over: 0B to the request's connection (none: it has gone), and
  // the line is quiet for t3.5 from now, so that a late response is not the next request's.
  constexpr gateway_step expire(std::uint32_t now_us) noexcept {
    ++timeouts_;
    if (framer_.pending() != 0U) {  // from_line past the last call: too late
      (void)framer_.idle();
      ++discarded_;
    }
    state_ = line_state::free;
    quiet(now_us, options_.line.t35_us);
    if (!current(on_line_)) {
      return gateway_step{};
    }
    return own_answer(on_line_, static_cast<std::uint8_t>(exception_code::gateway_target_failed));
  }

  // The line takes no request for `len_us` from `now_us` (or longer, if it was so already).
  constexpr void quiet(std::uint32_t now_us, std::uint32_t len_us) noexcept {
    const std::uint32_t left = quiet_left(now_us);
    quiet_from_ = now_us;
    quiet_len_ = left > len_us ? left : len_us;
  }

  // The quiet period's time left at `now_us`. It is kept as its start and its length, not as
  // a deadline, so that it does not go stale while the gateway is idle: a time is inside it
  // from its start to its end, or before its start by one transaction's time at most (the
  // I/O's clock read before the bytes it reports: poll_all's `now_us`); any other is past it.
  constexpr std::uint32_t quiet_left(std::uint32_t now_us) const noexcept {
    const std::uint32_t left = quiet_len_ - (now_us - quiet_from_);  // its end - now
    const std::uint64_t slack = std::uint64_t{options_.response_timeout_us} +
                                options_.turnaround_us +
                                2U * std::uint64_t{max_rtu_size} * options_.line.char_us;
    return quiet_len_ != 0U && left <= quiet_len_ + slack ? left : 0U;  // 0: none (as at the start)
  }

  gateway_options options_;
  connection clients_[Connections] = {};
  entry queue_[Queue] = {};
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  ticket on_line_{};  // the request on the line (or the last one)
  basic_rtu_framer<Table, framer_role::client> framer_{};
  std::uint8_t line_[max_rtu_size] = {};
  std::size_t line_size_ = 0;  // of the request in line_ (the last one sent)
  std::uint8_t reply_[max_tcp_size] = {};
  std::size_t reply_size_ = 0;
  line_state state_ = line_state::free;
  std::uint8_t broadcast_answer_ = 0;  // a broadcast's answer is due (answer_broadcasts)
  std::uint32_t quiet_from_ = 0;       // the line takes no request for quiet_len_ from then
  std::uint32_t quiet_len_ = 0;        // (0: the line is free as far as its silence goes)
  std::uint32_t deadline_us_ = 0;      // the response timeout's end
  std::uint32_t last_byte_us_ = 0;     // the last byte on the line (heard, or sent)
  std::size_t timeouts_ = 0;
  std::size_t discarded_ = 0;
  std::size_t dropped_ = 0;
};

/// The gateway for a host: 8 client connections, 16 requests queued.
using gateway = basic_gateway<8, 16>;

// The loops of the I/O, written once (as feed_all for the stream objects, core/stream.hpp):
// each calls `each(step)` for every step that is not none, in order.

namespace detail {
// `take(rest)` (from_client or from_line) until every byte of `in` is taken.
template <class Take, class Each>
constexpr void each_step(byte_view in, Take&& take, Each&& each) {
  while (!in.empty()) {
    const gateway_step s = take(in);
    in = in.subspan(s.consumed);
    if (s.action != gateway_action::none) {
      each(s);
    }
  }
}
}  // namespace detail

/// Connection `c`'s bytes `in`: from_client until every byte is taken (or `c` is closed).
template <class Gateway, class Each>
constexpr void feed_client(Gateway& gw, std::size_t c, byte_view in, Each&& each) {
  detail::each_step(
      in, [&](byte_view rest) { return gw.from_client(c, rest); }, each);
}

/// The line's bytes `in`, received at `now_us`: from_line until every byte is taken.
template <class Gateway, class Each>
constexpr void feed_line(Gateway& gw, byte_view in, std::uint32_t now_us, Each&& each) {
  detail::each_step(
      in, [&](byte_view rest) { return gw.from_line(rest, now_us); }, each);
}

/// What is due at `now_us`: poll until none.
template <class Gateway, class Each>
constexpr void poll_all(Gateway& gw, std::uint32_t now_us, Each&& each) {
  for (gateway_step s = gw.poll(now_us); s.action != gateway_action::none; s = gw.poll(now_us)) {
    each(s);
  }
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_GATEWAY_HPP
