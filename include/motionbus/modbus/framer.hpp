// motionbus — Modbus RTU stream framing, both directions (Modbus over Serial Line V1.02
// §2.5.1.1: frames separated by a silence of 3.5 character times; docs/modbus.md §3).
//
// A frame is handed over as soon as the length predicted from the function code and counts is
// confirmed by the CRC. By default (frame_end::silence) the user's UART driver also reports the
// t3.5 silence (idle()): bytes the length rule cannot frame (an unknown function, counts that
// disagree with the length) are held until then, and the silence ends the frame, so a server
// answers such requests with the exception the specification requires. Where no silence can be
// observed (frame_end::length), the length rule alone frames and everything else is garbage.
// A server keeps frames for its address and broadcasts; a client frames the response to its
// outstanding request; a listener (rtu_listener: a bus monitor, a capture decoder) frames both
// directions of a tapped line (framer_role::listener). After garbage or a bad CRC the framer drops
// one byte at a time and rescans (at most 256 bytes are ever held, in a frame_buffer: a dropped
// byte moves an index, nothing is shifted; a frame is handed over as a view into it, not copied).
// The same shape as the T-format receiver: built from an options struct, given bytes by put() (one
// byte, from a UART interrupt) and feed() (a chunk), told of the line's silence by idle(). `Table`
// selects the CRC table. No heap, no I/O.
//
//   rtu_server_framer rx({0x11});
//   on_rx_interrupt(b):                 // one byte: true when something is settled
//     if (rx.put(b) && rx.result()) handle(rx.result().value());
//   on_bytes(in):                       // or a chunk (core/stream.hpp: the feed loop)
//     feed_all(rx, in, [](const auto& r) {
//       if (r) handle(r.value());       // r->pdu points into rx: use it before the next call
//       return true;
//     });
//   on_t35():                           // the UART's idle-line timer
//     if (auto r = rx.idle()) handle(r.value());
//
// Both forms report the same results in the same order (the fuzz target and the tests check
// it), put() with one proviso: after a failure, a frame found among the bytes held is reported
// by the next put() or idle() (put_each() in core/stream.hpp, or feed() of an empty chunk,
// reports it at once).
//
// Firmware contract (Cortex-M4; sizes checked by the test command, stack and instructions by
// the meter at -Os: docs/footprint.md):
//   rtu_framer size: 308 bytes (a 256-byte frame buffer, its state and put()'s result; the
//     same for rtu_server_framer and rtu_client_framer). A default-constructed `static` framer
//     is all zeros: .bss, no start-up code, no flash copied to RAM.
//   put(byte), rtu_server_framer: 12 instructions for a byte inside a frame, the call included
//     (inline: the byte and its index stored, nothing else written); a server's function code
//     is sized inline too. An FC01-FC06 request: 24.9 a byte, CRC included (25.2 with the
//     run-time role of rtu_framer), 97 at its last byte (CRC, address), 56 bytes of stack. An
//     FC0F, FC10 or FC17 request (its byte count: the length rule reads the bytes held at each
//     byte until it has it): up to 128.0 a byte (the shortest), 1648 at its last byte at worst
//     (FC10 of 123 registers: the CRC over 253 bytes). FC08 Return Query Data (no count: one
//     CRC pass over the bytes held as they arrive finds its end): 74.1 a byte with 4 data
//     bytes, 122.4 a byte and 1668 at its last byte with 250 (the longest ADU: the worst case
//     of put()). 200 bytes of stack at worst (any request but FC01-FC06).
//   Interrupts: put() or feed() may run in the UART receive interrupt, idle() in the t3.5
//     timer's; sent() (client) runs before the request's first byte goes out. None of them may
//     run while another runs on the same framer. A frame handed over (rtu_frame::pdu) points
//     into the framer: use it, or copy it, before the next call. What
//     examples/firmware/modbus_server_irq.cpp does on the three cores under QEMU: put() in the
//     UART receive interrupt, idle() in a one-shot timer's armed at t3.5 after each byte (both
//     at one priority), each frame copied out in the interrupt and served by the main loop;
//     the firmware.modbus_server_irq tests check it with the polled image's peers and with
//     requests back to back (none lost, none answered twice).
#ifndef MOTIONBUS_MODBUS_FRAMER_HPP
#define MOTIONBUS_MODBUS_FRAMER_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "motionbus/core/bytes.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/frame_buffer.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/core/stream.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/rtu.hpp"

namespace motionbus {
namespace modbus {

/// Predicted size of the RTU frame at the start of `in` (address, function, ...): the total
/// size in bytes, 0 when more bytes are needed to tell, or `unknown_length` when the function
/// has no length rule here (the user's t3.5 signal then ends the frame).
inline constexpr std::size_t unknown_length = static_cast<std::size_t>(-1);

namespace detail {
// The request size that the function code alone gives (address, function, fields, CRC); 0: a
// count tells (0F, 10, 17), the sub-function does (08: 8 bytes but for Return Query Data, see
// basic_rtu_framer::query_data), or no length rule here. 01-06 (8 bytes) first, the common
// requests: one compare; then one bit per function code 0x00-0x1F for each other size: a few
// instructions and no table.
// inline: put()'s function code path, at the caller's receive interrupt.
MOTIONBUS_INLINE constexpr std::size_t fixed_request_size(std::uint8_t function) noexcept {
  constexpr std::uint32_t size4 = 0x21880U;  // 07, 0B, 0C, 11
  constexpr std::uint32_t size10 = std::uint32_t{1} << 0x16U;
  constexpr std::uint32_t size6 = std::uint32_t{1} << 0x18U;
  if (function - 1U < 6U) {
    return 8U;
  }
  if (function >= 32U) {
    return 0;
  }
  const std::uint32_t bit = std::uint32_t{1} << function;
  return (bit & size4) != 0U ? 4U : (bit & size10) != 0U ? 10U : (bit & size6) != 0U ? 6U : 0U;
}
}  // namespace detail

constexpr std::size_t predict_request_size(byte_view in) noexcept {
  if (in.size() < 2U) {
    return 0;
  }
  const std::uint8_t f = in[1];
  const std::size_t fixed = detail::fixed_request_size(f);
  if (fixed != 0U) {
    return fixed;
  }
  switch (f) {
    case 0x08: return 8;  // Return Query Data may be longer: the framer's scan checks the CRC
    case 0x0F:
    case 0x10: return in.size() < 7U ? 0 : 9U + in[6];
    case 0x17: return in.size() < 11U ? 0 : 13U + in[10];
    case 0x2B: return 7;  // MEI type, read device ID code, object ID
    default:              // FC14/15 (file records): their byte count / data length
      return (f | 1U) != 0x15U ? unknown_length : in.size() < 3U ? 0 : 5U + in[2];
  }
}

constexpr std::size_t predict_response_size(
    byte_view in, std::uint8_t request_function,
    report_id_format fc11 = report_id_format::standard) noexcept {
  if (in.size() < 2U) {
    return 0;
  }
  const std::uint8_t f = in[1];
  if ((f & exception_flag) != 0U) {
    return 5;
  }
  if (f != request_function) {
    return unknown_length;
  }
  switch (f) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04:
    case 0x0C:
    case 0x14:
    case 0x15:
    case 0x17: return in.size() < 3U ? 0 : 5U + in[2];
    case 0x05:
    case 0x06:
    case 0x08:
    case 0x0B:
    case 0x0F:
    case 0x10: return 8;
    case 0x07: return 5;
    case 0x16: return 10;
    case 0x11:
      return fc11 == report_id_format::two_bytes_no_count ? 6 : (in.size() < 3U ? 0 : 5U + in[2]);
    case 0x18: return in.size() < 4U ? 0 : 6U + std::size_t{load_be16(in, 2)};
    case 0x2B: {  // read device identification: walk the objects as they arrive
      if (in.size() < 8U) {
        return 0;
      }
      const detail::object_walk w = detail::walk_objects(in, 8, in[7]);
      if (w.inside) {
        return w.end + 2U;
      }
      // too long (the caller rejects it); objects still arriving in a full frame's worth of
      // bytes: too long too (never want more than 256 bytes); else wait
      return w.end > max_rtu_size ? w.end : in.size() >= max_rtu_size ? max_rtu_size + 1U : 0;
    }
    default: return unknown_length;
  }
}

/// How the frames on a line end (Modbus over Serial Line V1.02 §2.5.1.1).
enum class frame_end : std::uint8_t {
  /// The user's UART driver reports the t3.5 silence by calling idle(). A frame whose length
  /// rule and CRC agree is handed over at once; any other bytes wait for the silence, which
  /// then ends the frame: whatever the length rule said, a CRC-valid frame is handed over
  /// (a request whose counts disagree with its length, an unknown function), so that a server
  /// can answer it with the exception the specification requires.
  silence = 0,
  /// No t3.5 signal (e.g. a USB adapter that blurs the silences), or no silence at all: RTU
  /// over TCP, the RTU ADU with its CRC on a byte stream, both roles. A frame ends where the
  /// length rule says, confirmed by the CRC; bytes without a length rule are garbage, dropped
  /// one at a time while the framer resynchronises. idle() still clears what is held (on a
  /// socket: the user's timer for a quiet connection).
  length = 1,
};

/// The framer's run-time choices.
struct framer_options {
  /// A server's own address (1..247; it also takes broadcasts), or for a client the slave it
  /// talks to until the first sent() (0: accept any).
  std::uint8_t address = 0;
  frame_end ends = frame_end::silence;
  report_id_format fc11 = report_id_format::standard;  ///< client: FC11 response layout
  /// A server on several addresses (one port, several slaves): it takes every address from
  /// `address` to `last_address` (1..247 for every address: a gateway, a sniffer-server).
  /// A range, not a table: the framer stays the size it was, and the test is one subtraction
  /// and one compare. 0 (or anything not above `address`): `address` alone. Other sets: the
  /// range that covers them, and serve_units() answers only the units it has a device for.
  std::uint8_t last_address = 0;

  /// Whether a server with these options takes a frame for `slave` (a broadcast aside).
  constexpr bool serves(std::uint8_t slave) const noexcept {
    const unsigned width = last_address > address ? unsigned{last_address} - address : 0U;
    return static_cast<std::uint8_t>(slave - address) <= width;
  }
};

namespace detail {
// The framer's buffer: frame_buffer and the steps of a server's put() alone. A request's
// function code sizes it (up to 10 bytes): room for those is made at its first byte, so that
// its second byte sets the size with no room check, and its last byte is stored at once but
// counted only where the frame is not handed over.
class rtu_buffer : public frame_buffer<max_rtu_size> {
 public:
  static constexpr std::size_t max_fixed_request = 10;  // fixed_request_size's largest
  /// Makes room for max_fixed_request bytes from the front: moves the bytes held if needed.
  constexpr void reserve_fixed() noexcept {
    // true only 247+ bytes into the buffer, as the line below says
    if (static_cast<std::size_t>(start_) + max_fixed_request > max_rtu_size) {
      // a frame handed over 247+ bytes into the buffer with a byte behind it (length mode)
      make_room();
    }
  }
  /// want(n) for n <= max_fixed_request after reserve_fixed(), nothing dropped since.
  constexpr void want_within(std::size_t n) noexcept {
    want_ = static_cast<index>(n);
    const std::size_t stop = static_cast<std::size_t>(start_) + n;
    // coverage-branch: put() calls it with n = 4..10 (a function code's size): stop is never 0
    stop_ = static_cast<index>(stop - (stop != 0U ? 1U : 0U));
  }
  /// put_last() in two steps: the byte stored, then (unless restart() drops it all) counted.
  constexpr void place_last(std::uint8_t b) noexcept { bytes_[end_] = b; }
  constexpr void count_last() noexcept { end_ = static_cast<index>(end_ + 1U); }
};
}  // namespace detail

/// A framer's role, the template parameter of basic_rtu_framer: fixed by the type, so that a
/// server links only the request length rule (no client code) and a client only the
/// response's; or `either`, the one type whose role is chosen at run time (its constructor's
/// first argument: server or client).
///
/// listener: a passive node on a tapped line (a bus monitor, a capture decoder) that frames the
/// requests and the responses of every node. After a request, a frame is tried as that
/// request's response first (the response rule of its function, from its slave; an exception
/// from any slave), else as a request (the request rule); the first length at which a rule and
/// the CRC agree ends the frame (a shorter request read in a response's bytes needs a CRC
/// match by chance, 1 in 65536). A frame no rule and CRC confirm fails (crc_mismatch,
/// modbus_pdu_length) and the listener drops one byte and rescans, so that no valid frame
/// behind a bad one is lost; bytes no rule sizes (an unknown function, garbage) are dropped
/// one at a time (dropped()) whatever options.ends says: on a tapped line the silence is a
/// hint (idle()), never the only delimiter. heard_response() tells which rule framed the last
/// frame. options.address is not used.
enum class framer_role : std::uint8_t { server = 0, client = 1, listener = 2, either = 3 };

template <crc_table_size Table = default_crc_table, framer_role Role = framer_role::either>
class basic_rtu_framer {
 public:
  /// The role the type fixes (`either`: a server).
  constexpr explicit basic_rtu_framer(framer_options options = {}) noexcept
      : options_(options), slave_(options.address) {}
  /// The `either` type: the role chosen at run time (server or client).
  template <framer_role R = Role, std::enable_if_t<R == framer_role::either, int> = 0>
  constexpr explicit basic_rtu_framer(framer_role role, framer_options options = {}) noexcept
      : options_(options), slave_(options.address), role_(role) {}

  /// Client: records the request just sent, the RTU ADU written to the line (address,
  /// function, ...): the response is expected from its slave (any, for 0) and in the layout of
  /// its function. The configured options.address is kept. Drops any partial frame.
  constexpr void sent(byte_view request_adu) noexcept {
    slave_ = request_adu.size() > 0U ? request_adu[0] : std::uint8_t{0};
    function_ = request_adu.size() > 1U ? request_adu[1] : std::uint8_t{0};
    buf_.restart(0);
    waiting_ = 0;
    phase_ = phase::scanning;
  }

  /// Takes bytes from `in` until a frame or an error. Complete: a CRC-checked frame for this
  /// node; consumed() = bytes of `in` taken; its pdu view is valid until the next call.
  /// Failed: crc_mismatch (expected/received) or modbus_pdu_length (length rule gives more than
  /// 256 bytes); the framer rescans from the next byte on the next call. Incomplete: all of `in`
  /// was taken. Frames for other addresses are skipped silently (skipped()).
  /// With frame_end::silence, bytes the length rule cannot frame are held (never more than
  /// 256) until idle() instead of failing here.
  constexpr decode_result<rtu_frame> feed(byte_view in) noexcept {
    decode_result<rtu_frame> r;
    std::size_t used = 0;
    if (!decide(r, in, used)) {
      r = need_input{buf_.wanted() - buf_.size()};
    }
    return r;
  }

  /// The per-byte step (a UART receive interrupt's call): takes `byte`; true when it settles
  /// something, which result() then holds: a frame for this node (complete) or a failure, as
  /// feed() would report them. False: nothing to report yet. A byte inside a frame is stored
  /// here, inline at the call site, with nothing written but the byte and its index.
  /// After a failure the bytes held are rescanned by the next put() (which then reports at most
  /// one result: a frame found among the bytes held is reported before the byte's own), by
  /// idle(), or at once by feed() with an empty `in`.
  // inline: a byte inside a frame costs its store and index at the call site, no call.
  MOTIONBUS_INLINE constexpr bool put(std::uint8_t byte) noexcept {
    if (buf_.push_before(byte)) {
      return false;
    }
    const phase ph = phase_;
    if (ph == phase::framing) {  // push_before() refuses a frame's last byte only (see want())
      return last_byte(byte);
    }
    if (ph == phase::function_code) {  // a server's request: the function code gives its size
      const std::size_t total = detail::fixed_request_size(byte);
      if (total != 0U) {
        buf_.put_last(byte);      // the second byte of two wanted: it fits
        buf_.want_within(total);  // room was made with the first (put_other)
        phase_ = phase::framing;
        return false;
      }
    }
    return put_other(byte);
  }
  /// What the last put() that returned true settled (complete or failed); incomplete before
  /// any. Valid until the next put() that returns true: what it holds by value (status, error
  /// and evidence, slave, CRC) is kept; a frame's pdu is a view into the buffer, valid only
  /// until the next call of any kind (after it, the view may show the next frame's bytes).
  constexpr const decode_result<rtu_frame>& result() const noexcept { return result_; }

  /// The user's t3.5 timer expired: the bytes held end a frame. Complete: the bytes held as
  /// one CRC-valid frame for this node (frame_end::silence), else the first frame the length
  /// rule finds in them (past garbage, a bad CRC, or bytes whose rule wants more than the
  /// silence left: a frame cut short). Failed: truncated, crc_mismatch or modbus_pdu_length
  /// (the first met). Either way the framer is empty afterwards. Incomplete: nothing was held,
  /// or only a frame for another address (counted in skipped()). The same signal, and the
  /// same return type, as the T-format receiver's idle().
  /// The listener's idle() settles one result at a time, like feed(): the first frame or
  /// failure in the bytes held, a frame's bytes cut short by the silence being truncated (one
  /// byte dropped); call it again until it reports incomplete (the framer is then empty), so
  /// that a frame behind a failure is still reported.
  constexpr decode_result<rtu_frame> idle() noexcept {
    if (buf_.empty()) {
      return need_input{1};
    }
    if constexpr (Role == framer_role::listener) {
      phase_ = phase::scanning;
      const decode_result<rtu_frame> r = listen(0, true);
      if (buf_.empty()) {
        buf_.want(0);
      }
      return r;
    }
    decode_result<rtu_frame> r = need_input{1};
    bool settled = false;
    if (options_.ends == frame_end::silence) {
      const decode_result<rtu_frame> whole = decode_rtu<Table>(buf_.view());
      if (whole.is_complete()) {
        settled = true;
        if (for_us(whole.value().slave)) {
          r = hand_over(whole.value(), buf_.size(), 0);
        } else {
          ++skipped_;
          buf_.restart(0);
        }
      }
    }
    if (!settled) {
      // the first frame the length rule finds in the bytes held, past any garbage; else the
      // first failure met on the way
      decode_result<rtu_frame> first = need_input{1};
      std::uint32_t valid[max_rtu_size / 32U] = {};
      std::size_t marked = 0;  // the bytes held when `valid` was marked (0: not yet)
      for (;;) {
        // Past the first failure (the one reported), a start with no length rule whose bytes
        // to the end fail the CRC fails in scan() as here, one byte dropped: the marks say so
        // without scan()'s CRC over the rest at each start (quadratic in the bytes held). Here,
        // not in scan(): there the check would cost every put() that scans.
        if (first.is_failed() && buf_.size() >= 2U) {
          if (marked == 0U) {
            marked = buf_.size();
            mark_valid_suffixes(buf_.view(), valid);
          }
          const std::size_t at = marked - buf_.size();
          if (((valid[at / 32U] >> (at % 32U)) & 1U) == 0U &&
              predict(buf_.view()) == unknown_length) {
            drop_front(1);
            ++dropped_;
            continue;
          }
        }
        if (!scan(r, 0, true)) {
          r = need_input{1};
          if (buf_.size() >= 2U) {
            // a rule wants more bytes than the silence left (a frame cut short, or garbage
            // that reads as the start of a long one): a frame may start at the next byte.
            // 2 wanted, not the cut frame's total: with a total near 256 each later drop would
            // move the bytes held to the front (quadratic again)
            buf_.drop(1, 2);
            waiting_ = 0;
            ++dropped_;
            r = decode_failure{errc::truncated, 0};
          }
        }
        // coverage-branch: a failing scan drops one of 2+ bytes held: never empty after one
        if (!r.is_failed() || buf_.empty()) {
          break;
        }
        if (first.is_incomplete()) {
          first = r;
        }
      }
      if (!r.is_complete()) {
        // coverage-branch: r is never failed: the loop above ends on a scan that did not fail
        r = first.is_failed() ? first : (r.is_failed() ? r : decode_failure{errc::truncated, 0});
      }
    }
    // The silence ends whatever is held: the framer starts the next frame empty (a frame
    // handed over stays readable in the buffer until the next call).
    dropped_ += buf_.size();
    buf_.restart(0);
    waiting_ = 0;
    phase_ = phase::scanning;
    return r;
  }

  /// Bytes dropped while resynchronising, frames skipped for other addresses.
  constexpr std::size_t dropped() const noexcept { return dropped_; }
  constexpr std::size_t skipped() const noexcept { return skipped_; }
  constexpr std::size_t pending() const noexcept { return buf_.size(); }
  /// listener: whether the last frame handed over was framed as the response to the request
  /// before it (else it was a request). A request other than a broadcast makes the listener
  /// expect its response; a response, or a broadcast, makes it expect a request.
  constexpr bool heard_response() const noexcept { return listening() && heard_response_ != 0U; }

 private:
  // Bit i of `valid` (valid[i / 32], bit i % 32) set: the bytes held from i to their end are
  // one CRC-valid frame. One pass back from the end (crc::value_before), 8 bit steps a byte.
  static constexpr void mark_valid_suffixes(byte_view held,
                                            std::uint32_t (&valid)[max_rtu_size / 32U]) noexcept {
    std::uint16_t c = 0;  // a frame followed by its CRC: the CRC of it all is 0
    for (std::size_t i = held.size(); i > 0U; --i) {
      c = crc16_modbus<Table>::value_before(c, held[i - 1U]);
      if (c == crc16_modbus_spec::init) {  // the CRC of nothing: a frame starts here
        valid[(i - 1U) / 32U] |= std::uint32_t{1} << ((i - 1U) % 32U);
      }
    }
  }

  // put() of the last byte of a frame whose size the length rule gave: a frame for this node
  // whose CRC matches is handed over; anything else goes to scan().
  MOTIONBUS_NOINLINE constexpr bool last_byte(std::uint8_t byte) noexcept {
    buf_.place_last(byte);                  // counted by end_frame() unless handed over
    return end_frame(result_) || settle();  // else a bad CRC or another address
  }

  // put() of a byte that decides something but is not the last of a frame: the first byte, the
  // function code (the length rule gives the frame's size), or anything scan() must sort out.
  MOTIONBUS_NOINLINE constexpr bool put_other(std::uint8_t byte) noexcept {
    const std::size_t size = buf_.size();
    if (!listening() && waiting_ == 0U && size < 2U) {
      buf_.push(byte);  // fewer than 2 held: it fits
      if (size == 0U) {
        buf_.want(2);
        if (server()) {
          buf_.reserve_fixed();  // for put()'s function code path
          phase_ = phase::function_code;
        }
        return false;
      }
      // a request whose function code alone gives its size (4 to 10 bytes: a valid PDU): a
      // few bit tests; else the rule
      const std::size_t total = server() ? detail::fixed_request_size(byte) : predict(buf_.view());
      if (server() ? total != 0U : (total >= 3U && pdu_size_ok(total - 3U) && byte != 0x08U)) {
        buf_.want(total);
        phase_ = phase::framing;
        return false;
      }
      return settle();  // no plain length: scan() decides
    }
    return put_held(byte);
  }
  // put() of a byte that scan() must sort out with the bytes held. Fewer than 256 bytes are
  // held after every decision (scan() drops one of a full buffer), so the byte fits, and is
  // taken first.
  MOTIONBUS_NOINLINE constexpr bool put_held(std::uint8_t byte) noexcept {
    buf_.push(byte);
    return settle();
  }
  // put()'s decision on the bytes held (the byte taken): scan() decides.
  // result_ keeps the last settled result when nothing is settled (the contract of result()):
  // decide() writes it only when something is settled, in place (no local result: a
  // fixed-role framer's stack is what it was before result() kept anything).
  MOTIONBUS_NOINLINE constexpr bool settle() noexcept {
    std::size_t used = 1;
    return decide(result_, byte_view(), used);
  }

  // The last byte of a frame whose size the length rule gave (wanted(), all held) was taken:
  // true, and `out` complete, for a frame for this node whose CRC matches; else false.
  constexpr bool end_frame(decode_result<rtu_frame>& out) noexcept {
    const std::size_t total = buf_.wanted();
    const std::uint8_t* const frame = buf_.view().data();
    const std::uint16_t received = load_le16(byte_view(frame, total), total - 2U);
    const std::uint8_t slave = frame[0];
    if (crc16_modbus<Table>::compute(byte_view(frame, total - 2U)) != received ||
        slave > max_unicast_address || !for_us(slave)) {
      buf_.count_last();
      phase_ = phase::scanning;
      return false;
    }
    typename decode_result<rtu_frame>::outcome(out).complete_value(
        1, rtu_frame{slave, byte_view(frame + 1, total - 3U), received});
    // The frame was all that was held (put() decides at its last byte), and the framer was
    // not waiting for a silence (it would not be framing): hand_over() for this case.
    buf_.restart(2);
    phase_ = server() ? phase::function_code : phase::scanning;
    return true;
  }

  // feed() beyond a byte inside a frame: takes bytes from `in` (`used` of them already taken)
  // and decides as often as needed. True when something is settled, into `out` (nothing else
  // writes it); false when all of `in` was taken (wanted() bytes are then to be held).
  constexpr bool decide(decode_result<rtu_frame>& out, byte_view in, std::size_t& used) noexcept {
    return buf_.fill_and_decide(in, used, [&] { return scan(out, used, false); });
  }

  // `out` = `r` (or the failure `f`), built in place; true.
  static constexpr bool settled(decode_result<rtu_frame>& out,
                                const decode_result<rtu_frame>& r) noexcept {
    emplace_result(out, [&] { return r; });
    return true;
  }
  static constexpr bool settled(decode_result<rtu_frame>& out, const decode_failure& f) noexcept {
    emplace_result(out, [&] { return decode_result<rtu_frame>(f); });
    return true;
  }

  constexpr void drop_front(std::size_t n) noexcept {
    buf_.drop(n);
    waiting_ = 0;
  }

  static constexpr bool listening() noexcept { return Role == framer_role::listener; }

  // Responses whose length their own bytes give (a count, FC2B's objects): the listener frames
  // them with no request pending (MODBUS Application Protocol V1.1b3 §6).
  static constexpr bool self_sized_response(std::uint8_t f) noexcept {
    return (f >= 0x01U && f <= 0x04U) || f == 0x0CU || f == 0x11U || f == 0x14U || f == 0x15U ||
           f == 0x17U || f == 0x18U || f == 0x2BU;
  }

  constexpr bool server() const noexcept {
    if constexpr (Role == framer_role::either) {
      return role_ == framer_role::server;
    } else {
      return Role == framer_role::server;
    }
  }

  // The frame size the length rule gives for the bytes held (see predict_request_size).
  constexpr std::size_t predict(byte_view held) const noexcept {
    return server() ? predict_request_size(held)
                    : predict_response_size(held, function_, options_.fc11);
  }

  // inline: a compare or two in the CRC check of every frame's last byte.
  MOTIONBUS_INLINE constexpr bool for_us(std::uint8_t slave) const noexcept {
    // coverage-branch: true in the listener only, which never calls it (the line below)
    if (listening()) {
      return true;  // coverage: the listener frames in listen(), which never asks
    }
    if (server()) {
      // the one address first: a single-address server pays nothing for the range
      return slave == options_.address || slave == broadcast_address || options_.serves(slave);
    }
    return slave_ == 0U || slave == slave_;
  }

  // FC08 sub-function 00 (Return Query Data) carries any even number of data bytes and no
  // count (Modbus over Serial Line §6.1.1): its frame is 8 + 2k bytes, the CRC tells which.
  constexpr bool query_data(std::size_t held) const noexcept {
    return held >= 8U && buf_[1] == 0x08U && buf_[2] == 0U && buf_[3] == 0U;
  }

  // The first length 8 + 2k (from `from`, up to `to`) at which the CRC ends a frame, or the
  // first length past `to` (not yet held). `c`: the CRC of the bytes before `from`'s CRC field
  // on entry, of those before the returned length's on return; two bytes a step, so that a
  // caller that keeps `c` goes on from where it left: O(1) a byte, however long the data.
  static constexpr std::size_t query_data_end(byte_view held, std::size_t from, std::size_t to,
                                              std::uint16_t& c) noexcept {
    std::size_t at = from;
    for (; at <= to; at += 2U) {
      if (c == load_le16(held, at - 2U)) {
        return at;
      }
      // two more bytes from register c: for this reflected CRC (no final XOR), the same as
      // from the initial register 0xFFFF with c ^ 0xFFFF folded into the two bytes
      const std::uint8_t two[2] = {static_cast<std::uint8_t>(held[at - 2U] ^ ~c),
                                   static_cast<std::uint8_t>(held[at - 1U] ^ ~(c >> 8U))};
      c = crc16_modbus<Table>::compute(byte_view(two, 2));
    }
    return at;
  }
  // While a server or client waits for the rest of a Return Query Data (phase::query_data),
  // the CRC so far is kept in the bytes of waiting_ (false during that wait) and
  // heard_response_ (the listener's only): no byte added to the object.
  constexpr void keep_query_crc(std::uint16_t c) noexcept {
    waiting_ = static_cast<std::uint8_t>(c);
    heard_response_ = static_cast<std::uint8_t>(c >> 8U);
  }
  constexpr std::uint16_t take_query_crc() noexcept {
    const auto c = static_cast<std::uint16_t>(waiting_ | (heard_response_ << 8U));
    waiting_ = 0;
    heard_response_ = 0;
    return c;
  }

  // Hands `frame` (a view of the first `total` bytes held) over and drops those bytes from the
  // buffer, where they stay readable until the next call. The next frame's first byte takes
  // the inline path.
  constexpr decode_result<rtu_frame> hand_over(const rtu_frame& frame, std::size_t total,
                                               std::size_t used) noexcept {
    hand_over_bytes(total);
    return decode_result<rtu_frame>::complete(frame, used);
  }
  // inline: the step after every frame handed over, a few stores.
  MOTIONBUS_INLINE constexpr void hand_over_bytes(std::size_t total) noexcept {
    buf_.drop(total, 2);
    waiting_ = 0;
    // a server's next function code takes put()'s inline path when it is the next byte but one
    if (server() && buf_.size() < 2U) {
      buf_.reserve_fixed();
      phase_ = phase::function_code;
    } else {
      phase_ = phase::scanning;
    }
  }

  // The length rule cannot frame the bytes held. With frame_end::silence (and room to hold
  // more) they wait for idle(): true, the bytes wanted set. Otherwise the oldest byte is dropped:
  // false.
  constexpr bool wait_for_silence(bool at_end) noexcept {
    if (options_.ends == frame_end::silence && !at_end && buf_.size() < max_rtu_size) {
      buf_.want(buf_.size() + 1U);
      waiting_ = 1;  // no more length decisions on these bytes until idle() or a full buffer
      return true;
    }
    drop_front(1);
    ++dropped_;
    return false;
  }

  // Decides on the bytes held. True: settled, into `out` (built there: no local result). False
  // (`out` untouched): wanted() (> size) is how many to hold before the next decision. Out of
  // line: the chunk loop that calls it stays small and fast when the scan is not inlined into it.
  MOTIONBUS_NOINLINE constexpr bool scan(decode_result<rtu_frame>& out, std::size_t used,
                                         bool at_end) noexcept {
    // the last decision waited for Return Query Data: its CRC so far, up to wanted() - 2
    std::size_t resume_at = 0;
    std::uint16_t query_crc = 0;
    if (phase_ == phase::query_data) {
      resume_at = buf_.wanted();
      query_crc = take_query_crc();
    }
    phase_ = phase::scanning;
    if constexpr (Role == framer_role::listener) {
      const decode_result<rtu_frame> r = listen(used, at_end);
      // coverage-branch: settled() always returns true (it only stores the result)
      return !r.is_incomplete() && settled(out, r);
    }
    if (waiting_ != 0U) {
      if (!at_end && buf_.size() < max_rtu_size) {
        buf_.want(buf_.size() + 1U);
        return false;
      }
      waiting_ = 0;
      resume_at = 0;
      if (!at_end) {
        drop_front(1);  // a full buffer and still no silence: resynchronise
        ++dropped_;
      }
    }
    for (;; resume_at = 0) {  // a byte dropped: the bytes held changed
      buf_.want(2);
      const std::size_t size = buf_.size();
      if (size < 2U) {
        return false;
      }
      const byte_view held = buf_.view();
      std::size_t total = predict(held);
      if (total == unknown_length) {
        if (at_end) {
          total = size;  // the t3.5 silence says where it ends
        } else if (wait_for_silence(false)) {
          return false;  // no length rule: the silence will tell
        } else {
          continue;  // garbage: resynchronise
        }
      }
      // coverage-branch: never true, as the line below says
      if (total == 0U && size >= max_rtu_size) {
        // coverage: defensive; with 256 bytes held every rule gives a size (FC2B: too long)
        total = max_rtu_size + 1U;  // a rule never wants more than 256 bytes: too long
      }
      if (total == 0U) {  // a count byte is still missing
        buf_.want(size + 1U);
        return false;
      }
      if (total < 3U || !pdu_size_ok(total - 3U)) {  // address, PDU, CRC
        if (wait_for_silence(at_end)) {
          return false;
        }
        return settled(out, decode_failure{errc::modbus_pdu_length, used});
      }
      if (size < total) {
        buf_.want(total);
        return false;
      }
      if (query_data(total)) {
        const bool resume = resume_at > total;
        std::uint16_t c = resume ? query_crc : crc16_modbus<Table>::compute(held.first(total - 2U));
        const std::size_t at = query_data_end(held, resume ? resume_at : total, size, c);
        if (at <= size) {
          total = at;  // the CRC confirms this length
        } else if (at <= max_rtu_size && !at_end) {
          buf_.want(at);
          keep_query_crc(c);
          phase_ = phase::query_data;
          return false;
        }
      }
      const decode_result<rtu_frame> f = decode_rtu<Table>(held.first(total));
      if (f.is_failed()) {
        // resynchronise (a frame may start at the next byte), or wait for the silence
        if (wait_for_silence(at_end)) {
          return false;
        }
        return settled(out, decode_failure{f.error(), used, f.expected(), f.received()});
      }
      if (!for_us(f.value().slave)) {
        drop_front(total);
        ++skipped_;
        continue;
      }
      emplace_result(out, [&] { return hand_over(f.value(), total, used); });
      return true;
    }
  }

  // The listener's decision on the bytes held (framer_role::listener). The response rule
  // (after a request, from its slave; an exception from any slave) is tried before the request
  // rule; the first rule whose length is held and whose CRC matches frames. Incomplete: the
  // bytes the nearest rule still needs are wanted. Neither: the first failure met, one byte
  // dropped. At a silence (at_end) a rule still waiting is cut short: truncated.
  // (A Return Query Data is searched from its first length at each decision: a host's tool.)
  constexpr decode_result<rtu_frame> listen(std::size_t used, bool at_end) noexcept {
    for (;;) {
      const std::size_t size = buf_.size();
      if (size < 2U) {
        // At a silence the bytes held go one at a time (at one, below) or with a frame:
        // coverage-branch: at a silence (at_end) size is 1 here, never 0
        if (at_end && size != 0U) {  // one byte starts no frame: garbage
          drop_front(size);
          dropped_ += size;
        }
        buf_.want(2);
        return need_input{2U - size};
      }
      const byte_view held = buf_.view();
      // The response rule: the pending request's function from its slave; with no request
      // pending (it was lost, e.g. corrupted), a response that carries its own length, its own
      // function read as the request's (the CRC decides); an exception from any slave.
      const std::uint8_t asked = function_ != 0U ? (held[0] == slave_ ? function_ : 0U)
                                 : self_sized_response(held[1]) ? held[1]
                                                                : 0U;
      const bool response_possible = asked != 0U || (held[1] & exception_flag) != 0U;
      std::size_t need = 0;       // the smallest frame size still to be held
      std::size_t query_end = 0;  // FC08 Return Query Data: see query_data_end()
      decode_failure failure{errc::ok, used};
      // With a request pending its response is tried first; with none (the last frame was a
      // response, or a broadcast) a request is what comes next, and the response rule is the
      // fallback for a response whose request was lost: an FC01-04 request whose address's
      // high byte is 3 is also, byte for byte, a response with a byte count of 3 and the same
      // CRC (issue 28's soak: such requests were reported as unpaired responses).
      const unsigned first_rule = response_possible && function_ != 0U ? 0U : 1U;
      const unsigned rules = response_possible ? 2U : 1U;
      for (unsigned k = 0; k < rules; ++k) {
        const unsigned rule = k == 0U ? first_rule : 1U - first_rule;
        std::size_t total = rule == 0U ? predict_response_size(held, asked, options_.fc11)
                                       : predict_request_size(held);
        if (total == unknown_length) {
          continue;
        }
        if (total == 8U && query_data(size)) {  // the request, or its echo: 8 + 2k bytes
          if (query_end == 0U) {
            std::uint16_t c = crc16_modbus<Table>::compute(held.first(total - 2U));
            query_end = query_data_end(held, total, size, c);
          }
          if (query_end <= max_rtu_size) {
            total = query_end;  // held: the CRC confirms this length; else wanted below
          }
        }
        if (total == 0U || total > size) {
          const std::size_t at_least = total == 0U ? size + 1U : total;
          if (at_least > max_rtu_size) {  // never more than 256 bytes wanted: too long
            if (failure.code == errc::ok) {
              failure = decode_failure{errc::modbus_pdu_length, used};
            }
          } else if (need == 0U || at_least < need) {
            need = at_least;
          }
          continue;
        }
        const decode_result<rtu_frame> f = decode_rtu<Table>(held.first(total));
        if (f.is_failed()) {
          if (failure.code == errc::ok) {
            failure = decode_failure{f.error(), used, f.expected(), f.received()};
          }
          continue;
        }
        heard_response_ = rule == 0U ? 1U : 0U;
        if (rule == 0U || f.value().slave == broadcast_address) {
          function_ = 0;  // a request comes next
        } else {
          slave_ = f.value().slave;
          function_ = f.value().pdu[0];
        }
        return hand_over(f.value(), total, used);
      }
      if (need != 0U && !at_end) {
        buf_.want(need);
        return need_input{need - size};
      }
      drop_front(1);  // resynchronise: a frame may start at the next byte
      ++dropped_;
      buf_.want(2);  // rescan what is held at the next decision
      if (failure.code != errc::ok) {
        return failure;
      }
      if (need != 0U) {
        return decode_failure{errc::truncated, used};
      }
    }
  }

  detail::rtu_buffer buf_;  // first: put() stores at the object's address
  framer_options options_;
  // client: the slave of the request sent (options.address until sent(); 0: any); listener:
  // the slave of the request heard
  std::uint8_t slave_ = 0;
  std::uint8_t function_ = 0;
  // A bool (the length rule failed on the bytes held: only idle() decides), or the CRC's low
  // byte while a Return Query Data is awaited (keep_query_crc())
  std::uint8_t waiting_ = 0;
  // What put() decides at the next byte push_before() refuses.
  enum class phase : std::uint8_t {
    scanning = 0,       // put_other(): anything
    function_code = 1,  // a server's function code (one byte held, two wanted)
    framing = 2,        // the last byte of a frame whose size the length rule gave (wanted())
    query_data = 3,     // scanning, FC08 Return Query Data awaited: see keep_query_crc()
  };
  phase phase_ = phase::scanning;
  // listener: a bool, see heard_response(); else the CRC's high byte (keep_query_crc())
  std::uint8_t heard_response_ = 0;
  framer_role role_ = framer_role::server;  // the `either` type's (run-time) role
  std::size_t dropped_ = 0;
  std::size_t skipped_ = 0;
  decode_result<rtu_frame> result_;  // put()'s
};

/// The framer with the default CRC table, either role (chosen at run time).
using rtu_framer = basic_rtu_framer<>;
/// A server's framer (links no client code) and a client's, default CRC table.
using rtu_server_framer = basic_rtu_framer<default_crc_table, framer_role::server>;
using rtu_client_framer = basic_rtu_framer<default_crc_table, framer_role::client>;
/// A bus monitor's framer: both directions of a tapped line (framer_role::listener).
using rtu_listener = basic_rtu_framer<default_crc_table, framer_role::listener>;

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_FRAMER_HPP
