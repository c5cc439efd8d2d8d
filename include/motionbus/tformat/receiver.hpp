// motionbus — T-format stream receiver for UART-style byte streams (master side).
//
// Give it bytes as they arrive: one at a time with put() (a receive interrupt), or in chunks
// with feed(). It knows each response's length from its CF, skips the echo of the master's own
// request on half-duplex adapters whose receiver is always on (and tells a response that comes
// without the echo expected: echo_missed()), drops garbage until a valid CF,
// and after a corrupted frame rescans from the next byte so that no valid frame behind it is
// lost. Holds at most one frame (11 bytes, in a frame_buffer: garbage is dropped by moving an
// index); no heap, no I/O. The same shape as the Modbus RTU framer: built from an options
// struct, given bytes by put() and feed(), told of the line's silence by idle().
//
//   receiver rx({echo::expected});
//   rx.sent(request);                         // before writing the request to the UART
//   on_rx_interrupt(byte):                    // one byte: true when something is settled
//     if (rx.put(byte)) {
//       const auto& r = rx.result();          // a response, or a rejected frame
//       if (r) use(r.value()); else log(r.error());
//     }
//   on_chunk(in):                             // or a DMA buffer: every result for `in`
//     feed_all(rx, in, [](const auto& r) { ...; return true; });   // (core/stream.hpp)
//   on_idle():                                // the line went quiet: a cut-short frame?
//     if (rx.idle().is_failed()) log_truncated();
//
// Both forms report the same results in the same order (the fuzz target and the tests check
// it), put() with one proviso: after a rejected frame, a frame found among the bytes held is
// reported by the next put() (put_each() in core/stream.hpp, or feed() of an empty chunk,
// reports it at once).
//
// Firmware contract (Cortex-M4; sizes checked by the test command, stack and instructions by
// the meter at -Os: docs/footprint.md):
//   receiver size: 68 bytes (the frame buffer, the request, the options and put()'s result).
//     A default-constructed `static` receiver is all zeros: .bss, no start-up code, no flash
//     copied to RAM.
//   put(byte): 12 instructions for a byte inside a frame, the call included (inline: the byte
//     and its index stored, nothing else written). An ID3 response: 26.4 a byte, decode and
//     check included, 143 at its last byte; an ID0 response (the short layouts' path): 52.8 a
//     byte, 230 at its last byte; the last byte of a response with a bad CRC (the bytes held
//     rescanned): 600, the worst measured. 168 bytes of stack at worst (the last byte of an
//     ID0 response; measured with the receiver alone in its translation unit, as in a receive
//     interrupt's file, where the compiler inlines more than beside other code).
//   Interrupts: put() or feed() may run in the UART receive interrupt, idle() in the
//     idle-line timer's; sent() runs before the request's first byte goes out. None of them
//     may run while another runs on the same receiver (one interrupt priority, or mask one).
//     What examples/firmware/tformat_master_irq.cpp does on the three cores under QEMU: put()
//     in the UART receive interrupt, idle() in a one-shot timer's (one priority), sent() with
//     interrupts masked, each response copied out in the interrupt; the
//     firmware.tformat_master_irq tests check every transaction and a hundred requests back to
//     back (none lost, none rejected).
//   feed() returns a copy; result() is valid until the next put() that returns true.
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
  constexpr receiver() noexcept = default;  // defaulted: every member zero
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
    request_size_ = static_cast<std::uint8_t>(
        request_frame.size() < max_request_size ? request_frame.size() : max_request_size);
    for (std::size_t i = 0; i < request_size_; ++i) {
      request_[i] = request_frame[i];
    }
    echo_pending_ = echo_ && request_size_ > 0U;
    echo_missed_ = false;
    check_ = !skip_check_ && detail::valid_request(request_frame);
    framing_ = false;
    buf_.restart(0);
  }

  /// Processes bytes from `in` until a frame or an error is found.
  /// Complete: a response; consumed() = bytes of `in` taken. Failed: a candidate frame was
  /// rejected (CRC, reserved bits, check against the request); consumed() = bytes of `in`
  /// taken; the receiver rescans from the frame's second byte on the next call (call again,
  /// even with an empty `in`, until it reports incomplete). Incomplete: all of `in` was taken.
  /// Each byte is copied once; a frame is decoded only when its last byte has arrived.
  constexpr decode_result<response> feed(byte_view in) noexcept {
    decode_result<response> r;
    std::size_t used = 0;
    if (!decide(r, in, used)) {
      r = need_input{buf_.wanted() - buf_.size()};
    }
    return r;
  }

  /// The per-byte step (a UART receive interrupt's call): takes `byte`; true when it settles
  /// something, which result() then holds: a response (complete) or a rejected frame (failed,
  /// as feed() would report it). False: nothing to report yet. A byte inside a frame is stored
  /// here, inline at the call site, with nothing written but the byte and its index.
  /// After a failure the bytes held are rescanned by the next put() (which then reports at most
  /// one result: a frame found among the bytes held is reported before the byte's own), or at
  /// once by feed() with an empty `in`.
  // inline: a byte inside a frame costs its store and index at the call site, no call.
  MOTIONBUS_INLINE constexpr bool put(std::uint8_t byte) noexcept {
    if (buf_.push_before(byte)) {
      return false;
    }
    if (framing_) {  // push_before() refuses a frame's last byte only (frame_buffer::want)
      return last_byte(byte);
    }
    return put_other(byte);
  }
  /// What the last put() that returned true settled (complete or failed); incomplete before
  /// any. Valid until the next put() that returns true.
  constexpr const decode_result<response>& result() const noexcept { return result_; }

  /// The line went idle (end of frame): what is held is dropped. Failed (truncated, with the
  /// bytes dropped as consumed()) when part of a frame was held; else incomplete (nothing to
  /// report). The same signal, and the same return type, as the Modbus framer's idle().
  /// An echo held whole (waiting to tell it from a response without echo) is skipped here.
  constexpr decode_result<response> idle() noexcept {
    std::size_t held = buf_.size();
    if (echo_pending_ && held == request_size_) {
      std::size_t match = 0;
      // coverage-branch: no byte differs: settle_echo clears echo_pending_ at the first one
      while (match < held && buf_[match] == request_[match]) {
        ++match;
      }
      // coverage-branch: always the whole echo (above)
      if (match == held) {
        echoes_ += held;
        held = 0;
      }
    }
    dropped_ += held;
    buf_.restart(0);
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
  /// echo::expected, and the response to the last request came without the echo: it was
  /// delivered (the line does not echo: configure echo::none). See answers_request() for how
  /// it is told; an ID6 response cannot be told from the echo and is taken as the echo.
  /// Exactly: set only where the bytes held repeat the whole request and then read as its
  /// response (answers_request()); an IDD response matches the request's three bytes only when
  /// its EDF equals the request's CRC, so an IDD read is usually decoded as the response with
  /// the flag left false (bytes that differ from the request are parsed as a response, which
  /// does not tell a missing echo from a corrupted one).
  constexpr bool echo_missed() const noexcept { return echo_missed_; }
  /// Bytes held for an unfinished frame.
  constexpr std::size_t pending() const noexcept { return buf_.size(); }

 private:
  // put() of the last byte of a frame whose CF was checked: decoded and checked in place.
  MOTIONBUS_NOINLINE constexpr bool last_byte(std::uint8_t byte) noexcept {
    buf_.put_last(byte);
    finish(1, result_);
    return true;
  }

  // put() of a byte that decides something but is not the last of a frame: a first byte (a CF
  // or garbage), or anything decide() must sort out, with the byte taken first.
  MOTIONBUS_NOINLINE constexpr bool put_other(std::uint8_t byte) noexcept {
    if (buf_.empty() && !echo_pending_) {  // the first byte: a CF, or garbage
      const std::uint8_t code = data_id_code(byte);
      if (byte != valid_control_fields[code]) {
        ++dropped_;
        return false;
      }
      const std::uint8_t frame_size = response_layouts[code].size;
      buf_.restart(frame_size);  // empty: the frame starts at the front, where it fits
      buf_.put_last(byte);
      framing_ = true;
      return false;
    }
    return put_held(byte);
  }

  // put() of a byte that decide() must sort out with the bytes held. Fewer than 11 bytes are
  // held after every decision (a frame is decided when complete, a rejected one drops its first
  // byte), so the byte fits, and is taken first.
  // result_ keeps the last settled result when nothing is settled (the contract of result()):
  // decide() writes it only when something is settled, in place (no local result: the stack
  // of put() is that of a fixed-role receiver before result() kept anything).
  MOTIONBUS_NOINLINE constexpr bool put_held(std::uint8_t byte) noexcept {
    buf_.push(byte);
    std::size_t used = 1;
    return decide(result_, byte_view(), used);
  }

  // feed() of anything else: takes bytes from `in` (`used` of them already taken) and decides
  // as often as needed. True when something is settled, into `out` (nothing else writes it);
  // false when all of `in` was taken (wanted() bytes are then to be held).
  constexpr bool decide(decode_result<response>& out, byte_view in, std::size_t& used) noexcept {
    return buf_.fill_and_decide(in, used, [&] {
      // enough held to decide something: a frame's last byte, or scan() found a frame held
      if (framing_ || scan() == 0U) {
        finish(used, out);
        return true;
      }
      return false;
    });
  }

  // Decides on the bytes held (at least wanted()): skips an echo, drops garbage, finds a
  // frame. 0: a complete frame is held at the front (framing_, for finish()); else the bytes
  // wanted were raised to those needed before the next decision (at least the count returned).
  constexpr std::size_t scan() noexcept {
    for (;;) {
      buf_.want(1);
      const std::size_t held = buf_.size();
      if (held == 0U) {
        return 1;
      }
      if (echo_pending_) {
        const std::size_t more = settle_echo(held);
        if (more != 0U) {
          return more;
        }
        continue;  // the echo skipped, or none: parse the bytes held as a response
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
        return frame_size - held;
      }
      return 0;
    }
  }

  // The frame held at the front (wanted() bytes, its CF checked) is complete: decodes it into
  // `r`, and checks it against the request. A rejected frame is rescanned from its second byte.
  constexpr void finish(std::size_t used, decode_result<response>& r) noexcept {
    const std::size_t n = buf_.wanted();
    framing_ = false;
    // The default options are constants here (the common case: no options to rebuild).
    emplace_result(r, [&] {
      return custom_decode_ ? decode_response(buf_.view().first(n), decode_opts())
                            : decode_response(buf_.view().first(n), decode_options{});
    });
    r.set_consumed(used);
    // (n bytes: complete or failed; r is read before the buffer is written, which could alias)
    if (r.is_complete()) {
      std::uint32_t want = 0;
      std::uint32_t got = 0;
      const errc e = check_ ? detail::check_against(request_, r.value(), want, got) : errc::ok;
      buf_.drop(n, 0);
      if (e != errc::ok) {
        r = decode_failure{e, used, want, got};
      }
    } else {
      buf_.drop(1, 0);  // rescan from the next byte: a valid frame may start inside
      ++dropped_;
    }
  }

  // The echo awaited (echo_pending_) and `held` bytes: skips the whole echo; or tells that the
  // bytes held are no echo (the response: echo_pending_ cleared, nothing dropped). Returns the
  // bytes still needed to tell (0: told). Out of line: the
  // rare path (only after sent() with echo::expected).
  MOTIONBUS_NOINLINE constexpr std::size_t settle_echo(std::size_t held) noexcept {
    std::size_t match = 0;
    while (match < held && match < request_size_ && buf_[match] == request_[match]) {
      ++match;
    }
    if (match == request_size_) {  // the whole echo, or the response without one
      const std::size_t n = response_layouts[data_id_code(request_[0])].size;
      if (n > match) {
        if (held < n) {
          buf_.want(n);
          return n - held;
        }
        if (answers_request(n)) {  // no echo after all: the response
          echo_pending_ = false;
          echo_missed_ = true;
          return 0;
        }
      }
      echo_missed_ = false;
      buf_.drop(match);
      echoes_ += match;
      echo_pending_ = false;
      return 0;
    }
    if (match == held) {
      buf_.want(request_size_);
      return request_size_ - match;
    }
    echo_pending_ = false;  // not an echo after all: parse as a response
    return 0;
  }

  // An adapter that does not echo (echo::expected by mistake) hands over the response at once,
  // whose CF is the request's. Where the response is longer than the request, the first `n`
  // bytes held (the response's size) tell: without an echo they are a frame whose CRC matches
  // and whose second byte is an SF (bits 0..3 clear; T-format spec §6.3.2) or, for IDD, the
  // request's ADF; with the echo, the echoed CF stands where the SF is (a CF's bit 1 is the
  // sync code's 1), or for IDD the request's CRC stands where EDF is and the next CF where the
  // CRC is (their CRC is 0, the CF is not). The response is then decoded and checked as any.
  // ID6's response repeats the request: an ID6 echo and an ID6 response cannot be told apart,
  // the echo is assumed.
  constexpr bool answers_request(std::size_t n) const noexcept {
    const std::uint8_t second = buf_[1];
    const bool eeprom = response_layouts[data_id_code(request_[0])].eeprom();
    const bool fits = eeprom ? ((second ^ request_[1]) & adf_address_mask) == 0U
                             : (second & sf::reserved_mask) == 0U;
    return fits && crc_of(buf_.view().first(n - 1U)) == buf_[n - 1U];
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

  frame_buffer<max_response_size> buf_;  // first: put() stores at the object's address
  // The options, each stored so that its default is 0: a default receiver is all zeros, a
  // `static` one in .bss (stored as given, it is in .data: its image in flash, copied at boot).
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
  bool framing_ = false;      // buf_ starts with a checked CF and wanted() is its frame's size
  bool check_ = false;        // check responses against request_ (a valid request, and the option)
  bool echo_missed_ = false;  // see echo_missed() (in the padding before dropped_)
  std::size_t dropped_ = 0;
  std::size_t echoes_ = 0;
  decode_result<response> result_;  // put()'s
};

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_RECEIVER_HPP
