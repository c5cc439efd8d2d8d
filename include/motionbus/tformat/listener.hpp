// motionbus — T-format line listener: both directions of a tapped half-duplex line (a bus
// monitor, a capture decoder), framed and paired. The same shape as the receiver (master
// side) and the Modbus framer: built from an options struct, given bytes by put() (one byte)
// and feed() (a chunk, core/stream.hpp's feed_all), told of the line's silence by idle().
//
// Framing (T-format spec §8, §9; frame sizes from Table 2): a request is 1 byte (CF), 3 (IDD:
// CF ADF CRC) or 4 (ID6: CF ADF EDF CRC) by its CF's Data ID; after a request, the bytes are
// tried as its response first: a frame whose CF is the request's (the request's layout), or
// ID3 data (CF 0x1A, 11 bytes): the encoder answers an abnormal request with Data ID 3 data
// "in spite of any kind of Transmission request" (§6.3.2; §8.4 Table 5: parity or delimiter
// error, unknown Data ID; §9.4 Table 6: closed EEPROM address, bad CRC, busy bit). Bytes that
// are no response are read as a request (the response went missing). A response that fails
// (CRC, reserved bits, the EEPROM address or data not those of the request) is reported and
// the listener rescans from the next byte for a response, so that a frame behind it is not
// lost; until one is found or the line goes idle (idle()), the bytes of the rejected response
// are not read as requests. The silence ends the expectation of a response (idle()). Choice
// where the text is silent: without a silence between them, a request whose response is
// missing followed by the same CF-only request (or by an ID3 request: 0x1A is also the CF of
// the abnormal reply) reads as a rejected response (the bytes cannot tell them apart). A byte whose
// sync code is wrong starts no frame (the encoder does not reply to it): dropped, counted.
//
// An abnormal request is handed over like any request, with heard::request_error saying why
// the encoder answers it with ID3 data (tformat_parity, tformat_unknown_data_id, crc_mismatch,
// reserved_bits); a closed EEPROM address is no property of the request: its ID3 reply
// (heard::id3_reply) tells. A delimiter error is the UART's to report (a framing error): the
// byte read is framed as it reads. No heap, no I/O.
#ifndef MOTIONBUS_TFORMAT_LISTENER_HPP
#define MOTIONBUS_TFORMAT_LISTENER_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/frame_buffer.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/core/stream.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/frame.hpp"

namespace motionbus {
namespace tformat {

/// A frame heard on the line.
struct heard {
  bool is_response = false;
  /// The frame's bytes, a view into the listener: valid until its next call.
  byte_view bytes{};
  /// A request (is_response false): its fields where request_error is ok; id and cf always.
  request req{};
  /// ok, or why the encoder answers this request with ID3 data (see the top of the file).
  errc request_error = errc::ok;
  /// A response (is_response true), paired with the request before it.
  response resp{};
  /// The response is ID3 data answering a request that is not ID3 (an abnormal request).
  bool id3_reply = false;
};

struct listener_options {
  decode_options decode{};
};

class line_listener {
 public:
  constexpr line_listener() noexcept = default;
  constexpr explicit line_listener(const listener_options& opt) noexcept : opt_(opt) {}

  /// Takes bytes from `in` until a frame or a failure. Complete: a frame heard (consumed() =
  /// bytes of `in` taken). Failed: a response candidate was rejected (its error and evidence),
  /// the listener rescans from its second byte on the next call. Incomplete: all of `in` taken.
  constexpr decode_result<heard> feed(byte_view in) noexcept {
    decode_result<heard> r;
    std::size_t used = 0;
    const bool settled = buf_.fill_and_decide(in, used, [&] {
      r = scan(used, false);
      return !r.is_incomplete();
    });
    if (!settled) {
      r = need_input{buf_.wanted() - buf_.size()};
    }
    return r;
  }

  /// The per-byte step: takes `byte`; true when it settles something, which result() then
  /// holds (as feed() reports it); result() keeps it until the next put() that returns true:
  /// its status and decoded fields; heard::bytes is a view valid only until the next call.
  /// After a failure, frames among the bytes held are reported by feed() of an empty chunk
  /// (put_each() in core/stream.hpp does it).
  constexpr bool put(std::uint8_t byte) noexcept {
    const decode_result<heard> r = feed(byte_view(&byte, 1));
    if (r.is_incomplete()) {
      return false;
    }
    result_ = r;
    return true;
  }
  constexpr const decode_result<heard>& result() const noexcept { return result_; }

  /// The line went idle: what is held is settled, one result a call (call it again until it
  /// reports incomplete: the bytes held after a failure are rescanned). A frame cut short
  /// fails (truncated, one byte dropped). Once nothing is held, no response is expected any
  /// more: the encoder answers about 3 us after the request (T-format spec §8.2; docs/tformat.md),
  /// so the next frame after a silence is a request. Report a silence longer than the line's
  /// turnaround (and, on a host, than its delivery delays: the bus monitor's --gap-us). Bytes held
  /// while rescanning a rejected response (no response found in them yet) are the rest of that
  /// response: dropped (counted in dropped()), never read as requests.
  constexpr decode_result<heard> idle() noexcept {
    if (resync_) {
      resync_ = false;
      dropped_ += buf_.size();
      buf_.drop(buf_.size(), 1);
    }
    if (buf_.empty()) {
      expecting_ = false;  // the encoder answers at once (about 3 us): after a silence, a request
      return need_input{1};
    }
    const decode_result<heard> r = scan(0, true);
    if (r.is_incomplete()) {  // all settled (the last bytes dropped as garbage)
      expecting_ = false;
    }
    return r;
  }

  /// Bytes dropped (no sync code, or the first byte of a rejected frame).
  constexpr std::size_t dropped() const noexcept { return dropped_; }
  constexpr std::size_t pending() const noexcept { return buf_.size(); }
  /// Whether a response to the last request is expected.
  constexpr bool expecting_response() const noexcept { return expecting_; }

 private:
  static constexpr std::uint8_t id3_cf = control_fields[3];

  constexpr decode_result<heard> scan(std::size_t used, bool at_end) noexcept {
    for (;;) {
      const std::size_t held = buf_.size();
      buf_.want(1);
      if (held == 0U) {
        return need_input{1};
      }
      const std::uint8_t b0 = buf_[0];
      if (expecting_ && (b0 == request_[0] || b0 == id3_cf)) {
        const std::size_t n =
            b0 == request_[0] ? layout_of(id_of(request_[0])).size : std::size_t{max_response_size};
        if (held < n && !at_end) {
          buf_.want(n);
          return need_input{n - held};
        }
        decode_result<response> r =
            held < n ? decode_result<response>(decode_failure{errc::truncated, used})
                     : decode_response(buf_.view().first(n), opt_.decode);
        if (r.is_complete()) {
          std::uint32_t want = 0;
          std::uint32_t got = 0;
          errc e = errc::ok;
          if (b0 == request_[0] && request_error_ == errc::ok) {
            e = detail::check_against(request_, r.value(), want, got);
            if (e == errc::tformat_communication_alarm) {
              e = errc::ok;  // the alarm is the response's news (its SF), no mismatch
            }
          }
          if (e == errc::ok) {
            expecting_ = false;
            resync_ = false;
            heard h;
            h.is_response = true;
            h.bytes = buf_.view().first(n);
            h.resp = r.value();
            h.id3_reply = b0 == id3_cf && request_[0] != id3_cf;
            buf_.drop(n, 1);
            return decode_result<heard>::complete(h, used);
          }
          r = decode_failure{e, used, want, got};
        }
        buf_.drop(1, 1);  // rescan from the next byte: a frame may start inside
        ++dropped_;
        expecting_ = !at_end;
        resync_ = !at_end;
        return decode_failure{r.error(), used, r.expected(), r.received()};
      }
      if (resync_) {  // inside a rejected response: only a response starts here
        buf_.drop(1, 1);
        ++dropped_;
        continue;
      }
      if (!sync_ok(b0)) {
        buf_.drop(1, 1);  // no frame starts here
        ++dropped_;
        continue;
      }
      const data_id id = id_of(b0);
      heard h;
      h.req.id = id;
      h.req.cf = b0;
      std::size_t n = 1;
      // A parity error in an EEPROM request's CF (Table 6 No. 4): its Data ID as read still
      // sizes it (its address, data and CRC bytes come next), none starts a request.
      // Choice: an EEPROM ID read with a parity error is taken as that request (one bit flipped
      // in cc4); any other CF with a parity error is one byte.
      const bool eeprom = id == data_id::eeprom_write || id == data_id::eeprom_read;
      if (!parity_ok(b0) && !eeprom) {
        h.request_error = errc::tformat_parity;
      } else if (!is_known(id)) {
        h.request_error = errc::tformat_unknown_data_id;
      } else {
        n = request_size(id);
        if (held < n && !at_end) {
          buf_.want(n);
          return need_input{n - held};
        }
        if (held < n) {
          buf_.drop(1, 1);
          ++dropped_;
          return decode_failure{errc::truncated, used};
        }
        const decode_result<request> q = decode_request(buf_.view().first(n));
        if (q.is_complete()) {
          h.req = q.value();
        } else {
          h.request_error = parity_ok(b0) ? q.error() : errc::tformat_parity;
          h.req.crc = buf_[n - 1U];
          h.req.address = buf_[1];
          h.req.edf = n == 4U ? buf_[2] : std::uint8_t{0};
        }
      }
      for (std::size_t i = 0; i < n; ++i) {
        request_[i] = buf_[i];
      }
      request_error_ = h.request_error;
      expecting_ = true;
      h.bytes = buf_.view().first(n);
      buf_.drop(n, 1);
      return decode_result<heard>::complete(h, used);
    }
  }

  static constexpr data_id id_of(std::uint8_t cf) noexcept {
    return static_cast<data_id>(data_id_code(cf));
  }

  frame_buffer<max_response_size> buf_;
  listener_options opt_{};
  std::uint8_t request_[max_request_size] = {};
  errc request_error_ = errc::ok;
  bool expecting_ = false;
  bool resync_ = false;  // a response candidate failed: bytes until a response or idle() are its
  std::size_t dropped_ = 0;
  decode_result<heard> result_;
};

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_LISTENER_HPP
