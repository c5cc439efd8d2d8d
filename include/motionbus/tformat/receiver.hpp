// motionbus — T-format stream receiver for UART-style byte streams (master side).
//
// Feed it bytes as they arrive, one at a time or in chunks. It knows each response's length
// from its CF, skips the echo of the master's own request on half-duplex adapters whose
// receiver is always on, drops garbage until a valid CF, and after a corrupted frame rescans
// from the next byte so that no valid frame behind it is lost. Holds at most one frame
// (11 bytes, in a frame_buffer: garbage is dropped by moving an index); no heap, no I/O.
// The same shape as the Modbus RTU framer: built from an options struct, fed by feed(),
// told of the line's silence by idle(), each returning a decode_result.
//
//   receiver rx({echo::expected});
//   rx.sent(request);                         // after writing the request to the UART
//   feed_all(rx, in, [](const auto& r) {      // every result for the bytes `in`
//     if (r) use(r.value()); else log(r.error());
//     return true;
//   });                                       // (core/stream.hpp: the loop on feed() below)
//   on_idle():                                // the line went quiet: a cut-short frame?
//     if (rx.idle().is_failed()) log_truncated();
//
// Firmware contract (Cortex-M4; sizes checked by the test command, stack and instructions by
// the meter at -Os: docs/footprint.md):
//   receiver size: 40 bytes. A default-constructed `static` receiver is all zeros: .bss, no
//     start-up code, no flash copied to RAM.
//   feed(byte): 17 instructions for a byte inside a frame, the call included; 30.9 a byte over
//     an ID3 response; 92 bytes of stack at worst (the last byte: decode and check).
//   Interrupts: feed() may run in the UART receive interrupt, idle() in the idle-line timer's;
//     sent() runs before the request's first byte goes out. None of them may run while
//     another runs on the same receiver (one interrupt priority for both, or mask one).
//   The returned response is a copy: it stays valid whatever the receiver does next.
#ifndef MOTIONBUS_TFORMAT_RECEIVER_HPP
#define MOTIONBUS_TFORMAT_RECEIVER_HPP

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

/// Whether the line hands the master its own request before the response.
enum class echo : std::uint8_t {
  none = 0,      ///< full duplex, or the adapter disables its receiver while sending
  expected = 1,  ///< half duplex with an always-on receiver: skip the request's bytes
};

struct receiver_options {
  echo echo_mode = echo::none;
  decode_options decode{};
  /// Check each response against the last request passed to sent() (check_response).
  bool check_against_request = true;
};

class receiver {
 public:
  /// A default-constructed receiver is all zeros (its options are stored relative to the
  /// defaults): a `static` one lands in .bss, not .data.
  constexpr receiver() noexcept = default;  // coverage: defaulted, compiles to no code
  constexpr explicit receiver(const receiver_options& opt) noexcept
      : echo_(opt.echo_mode == echo::expected),
        skip_check_(!opt.check_against_request),
        single_turn_x_(static_cast<std::uint8_t>(opt.decode.res.single_turn_bits ^
                                                 resolution{}.single_turn_bits)),
        multi_turn_x_(static_cast<std::uint8_t>(opt.decode.res.multi_turn_bits ^
                                                resolution{}.multi_turn_bits)),
        skip_unused_check_(!opt.decode.check_unused_bits),
        resolution_from_enid_(opt.decode.resolution_from_enid),
        custom_decode_(single_turn_x_ != 0U || multi_turn_x_ != 0U || skip_unused_check_ ||
                       resolution_from_enid_) {}

  /// The options the receiver was built with.
  constexpr receiver_options options() const noexcept {
    receiver_options o;
    o.echo_mode = echo_ ? echo::expected : echo::none;
    o.check_against_request = !skip_check_;
    o.decode = decode_opts();
    return o;
  }

  /// Records the request just sent (up to 4 bytes): its echo is skipped when echo::expected,
  /// and responses are checked against it. Drops any partial frame.
  constexpr void sent(byte_view request_frame) noexcept {
    buf_.want(0);
    request_size_ = static_cast<std::uint8_t>(
        request_frame.size() < max_request_size ? request_frame.size() : max_request_size);
    for (std::size_t i = 0; i < request_size_; ++i) {
      request_[i] = request_frame[i];
    }
    echo_pending_ = echo_ && request_size_ > 0U;
    check_ = !skip_check_ && detail::valid_request(request_frame);
    framing_ = false;
    buf_.clear();
  }

  /// Processes bytes from `in` until a frame or an error is found.
  /// Complete: a response; consumed() = bytes of `in` taken. Failed: a candidate frame was
  /// rejected (CRC, reserved bits, check against the request); consumed() = bytes of `in`
  /// taken; the receiver rescans from the frame's second byte on the next call (call again,
  /// even with an empty `in`, until it reports incomplete). Incomplete: all of `in` was taken.
  /// Each byte is copied once; a frame is decoded only when its last byte has arrived.
  MOTIONBUS_INLINE constexpr decode_result<response> feed(byte_view in) noexcept {
    if (in.size() == 1U) {
      return feed(in[0]);
    }
    return decide(in);
  }
  /// feed() of one byte (a UART interrupt handler's call). A byte inside a frame whose length
  /// is known is stored here, inline at the call site; everything else is decided out of line.
  MOTIONBUS_INLINE constexpr decode_result<response> feed(std::uint8_t byte) noexcept {
    std::size_t at_least = 0;
    if (buf_.push_before(byte, at_least)) {
      return need_input{at_least};
    }
    return decide_byte(byte);
  }

  /// The line went idle (end of frame): what is held is dropped. Failed (truncated, with the
  /// bytes dropped as consumed()) when part of a frame was held; else incomplete (nothing to
  /// report). The same signal, and the same return type, as the Modbus framer's idle().
  constexpr decode_result<response> idle() noexcept {
    const std::size_t held = buf_.size();
    dropped_ += held;
    buf_.want(0);
    buf_.clear();
    framing_ = false;
    echo_pending_ = false;
    if (held > 0U) {
      return decode_failure{errc::truncated, held};
    }
    return need_input{1};
  }

  /// Bytes skipped as garbage (no valid CF) or dropped by idle(), since construction.
  constexpr std::size_t dropped() const noexcept { return dropped_; }
  /// Echo bytes skipped since construction.
  constexpr std::size_t echoes_skipped() const noexcept { return echoes_; }
  /// Bytes held for an unfinished frame.
  constexpr std::size_t pending() const noexcept { return buf_.size(); }

 private:
  // feed() of one byte that completes something: the last byte of a frame (decoded without a
  // stack frame of its own here: a tail call), or else a first byte.
  MOTIONBUS_NOINLINE constexpr decode_result<response> decide_byte(std::uint8_t byte) noexcept {
    if (framing_) {
      if (buf_.completes_want()) {  // the last byte of a frame whose CF was checked
        buf_.put_last(byte);
        return finish(1);
      }
    } else if (buf_.empty() && !echo_pending_) {  // the first byte: a CF, or garbage
      const std::uint8_t code = data_id_code(byte);
      if (byte != valid_control_fields[code]) {
        ++dropped_;
        return need_input{1};
      }
      const std::uint8_t frame_size = response_layouts[code].size;
      buf_.start_with(byte, frame_size);  // an empty buffer starts at its front
      framing_ = true;
      return need_input{frame_size - 1U};
    }
    return decide_one(byte);
  }

  // decide() of one byte, out of line: decide_byte() then needs no stack frame.
  MOTIONBUS_NOINLINE constexpr decode_result<response> decide_one(std::uint8_t byte) noexcept {
    return decide(byte_view(&byte, 1));
  }

  // feed() of anything else: takes bytes from `in` and decides as often as needed.
  constexpr decode_result<response> decide(byte_view in) noexcept {
    std::size_t used = 0;
    for (;;) {
      if (buf_.size() >= buf_.wanted()) {  // enough held to decide something
        if (framing_) {
          return finish(used);
        }
        const decode_result<response> r = scan(used);
        if (!r.is_incomplete()) {
          return r;
        }
        continue;  // scan() raised the bytes wanted
      }
      if (used >= in.size()) {
        return need_input{buf_.wanted() - buf_.size()};
      }
      used += buf_.append(in.subspan(used), buf_.wanted() - buf_.size());
    }
  }

  // Decides on the bytes held (at least wanted()): skips an echo, drops garbage, decodes a
  // complete frame. Incomplete: the bytes wanted were raised to those needed before the next
  // decision.
  constexpr decode_result<response> scan(std::size_t used) noexcept {
    for (;;) {
      buf_.want(1);
      const std::size_t held = buf_.size();
      if (held == 0U) {
        return need_input{1};
      }
      if (echo_pending_) {
        std::size_t match = 0;
        while (match < held && match < request_size_ && buf_[match] == request_[match]) {
          ++match;
        }
        if (match == request_size_) {  // the whole echo: skip it
          buf_.drop(match);
          echoes_ += match;
          echo_pending_ = false;
          continue;
        }
        if (match == held) {
          buf_.want(request_size_);
          return need_input{request_size_ - match};
        }
        echo_pending_ = false;  // not an echo after all: parse as a response
      }
      const std::uint8_t code = data_id_code(buf_[0]);
      if (buf_[0] != valid_control_fields[code]) {
        buf_.drop(1);  // garbage: no valid CF here
        ++dropped_;
        continue;
      }
      const std::uint8_t frame_size = response_layouts[code].size;
      buf_.want(frame_size);
      framing_ = true;
      if (held < frame_size) {
        return need_input{frame_size - held};
      }
      return finish(used);
    }
  }

  // The frame held at the front (wanted() bytes, its CF checked) is complete: decodes it, and
  // checks it against the request. A rejected frame is rescanned from its second byte.
  constexpr decode_result<response> finish(std::size_t used) noexcept {
    const std::size_t n = buf_.wanted();
    framing_ = false;
    // One result, returned from one place (built in the caller's slot: no copy).
    // The default options are constants here (the common case: no options to rebuild).
    decode_result<response> r = custom_decode_ ? decode_response(buf_.first(n), decode_opts())
                                               : decode_response(buf_.first(n), decode_options{});
    if (r.is_failed()) {
      buf_.drop(1, 0);  // rescan from the next byte: a valid frame may start inside
      ++dropped_;
    } else {
      buf_.drop(n, 0);
      if (check_) {
        std::uint32_t want = 0;
        std::uint32_t got = 0;
        const errc e = detail::check_against(request_, r.value(), want, got);
        if (e != errc::ok) {
          r = decode_failure{e, 0, want, got};
        }
      }
    }
    r.set_consumed(used);
    return r;
  }

  constexpr decode_options decode_opts() const noexcept {
    decode_options d;
    d.res.single_turn_bits =
        static_cast<std::uint8_t>(single_turn_x_ ^ resolution{}.single_turn_bits);
    d.res.multi_turn_bits = static_cast<std::uint8_t>(multi_turn_x_ ^ resolution{}.multi_turn_bits);
    d.check_unused_bits = !skip_unused_check_;
    d.resolution_from_enid = resolution_from_enid_;
    return d;
  }

  frame_buffer<max_response_size> buf_;  // first: feed(byte) stores at the object's address
  // The options, each stored so that its default is 0 (a default receiver is all zeros).
  bool echo_ = false;
  bool skip_check_ = false;
  std::uint8_t single_turn_x_ = 0;  // XOR the default resolution
  std::uint8_t multi_turn_x_ = 0;
  bool skip_unused_check_ = false;
  bool resolution_from_enid_ = false;
  bool custom_decode_ = false;  // any of the decode options above is not the default
  std::uint8_t request_[max_request_size] = {};
  std::uint8_t request_size_ = 0;
  bool echo_pending_ = false;
  bool framing_ = false;  // buf_ starts with a checked CF and wanted() is its frame's size
  bool check_ = false;    // check responses against request_ (a valid request, and the option)
  std::size_t dropped_ = 0;
  std::size_t echoes_ = 0;
};

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_RECEIVER_HPP
