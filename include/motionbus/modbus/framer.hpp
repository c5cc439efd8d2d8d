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
// outstanding request. After garbage or a bad CRC the framer drops one byte at a time and
// rescans (at most 256 bytes are ever held). No heap, no I/O.
//
//   rtu_framer rx(framer_role::server, 0x11);
//   on_bytes(in):                       // from the UART
//     for (;;) {
//       auto r = rx.feed(in);
//       if (r.is_incomplete()) break;   // all of `in` taken
//       in = in.subspan(r.consumed());
//       if (r) handle(r.value());       // r->pdu points into rx: use it before the next feed()
//     }
//   on_t35():                           // the UART's idle-line timer
//     if (auto r = rx.idle()) handle(r.value());
#ifndef MOTIONBUS_MODBUS_FRAMER_HPP
#define MOTIONBUS_MODBUS_FRAMER_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/rtu.hpp"

namespace motionbus {
namespace modbus {

enum class framer_role : std::uint8_t { server = 0, client = 1 };

/// Predicted size of the RTU frame at the start of `in` (address, function, ...): the total
/// size in bytes, 0 when more bytes are needed to tell, or `unknown_length` when the function
/// has no length rule here (the user's t3.5 signal then ends the frame).
inline constexpr std::size_t unknown_length = static_cast<std::size_t>(-1);

constexpr std::size_t predict_request_size(byte_view in) noexcept {
  if (in.size() < 2U) {
    return 0;
  }
  switch (in[1]) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04:
    case 0x05:
    case 0x06:
    case 0x08: return 8;  // address, function, 4 bytes, CRC
    case 0x07:
    case 0x0B:
    case 0x0C:
    case 0x11: return 4;
    case 0x0F:
    case 0x10: return in.size() < 7U ? 0 : 9U + in[6];
    case 0x16: return 10;
    case 0x17: return in.size() < 11U ? 0 : 13U + in[10];
    case 0x18: return 6;
    case 0x2B: return 7;  // MEI type, read device ID code, object ID
    default: return unknown_length;
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
    case 0x18: return in.size() < 4U ? 0 : 6U + static_cast<std::size_t>((in[2] << 8U) | in[3]);
    case 0x2B: {  // read device identification: walk the objects as they arrive
      if (in.size() < 8U) {
        return 0;
      }
      std::size_t at = 8;
      for (unsigned k = 0; k < in[7]; ++k) {
        if (in.size() < at + 2U) {
          return 0;
        }
        at += 2U + in[at + 1U];
        if (at > max_rtu_size) {
          return at;  // the caller rejects it as too long
        }
      }
      return at + 2U;
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
  /// No t3.5 signal (e.g. a USB adapter that blurs the silences): a frame ends where the
  /// length rule says, confirmed by the CRC; bytes without a length rule are garbage, dropped
  /// one at a time while the framer resynchronises. idle() still clears what is held.
  length = 1,
};

/// The framer's run-time choices.
struct framer_options {
  frame_end ends = frame_end::silence;
  report_id_format fc11 = report_id_format::standard;  ///< client: FC11 response layout
};

class rtu_framer {
 public:
  /// `address`: a server's own address (1..247; it also takes broadcasts), or for a client the
  /// slave it talks to (0: accept any).
  constexpr rtu_framer(framer_role role, std::uint8_t address, framer_options options = {}) noexcept
      : role_(role), address_(address), options_(options) {}

  /// Client: records the request just sent (its function selects the response layout).
  constexpr void sent(std::uint8_t slave, std::uint8_t function) noexcept {
    address_ = slave;
    function_ = function;
    size_ = 0;
    want_ = 2;
    waiting_ = false;
  }

  /// Takes bytes from `in` until a frame or an error. Complete: a CRC-checked frame for this
  /// node; consumed() = bytes of `in` taken; its pdu view is valid until the next call.
  /// Failed: crc_mismatch (expected/received) or modbus_pdu_length (length rule gives more than
  /// 256 bytes); the framer rescans from the next byte on the next call. Incomplete: all of `in`
  /// was taken. Frames for other addresses are skipped silently (skipped()).
  /// With frame_end::silence, bytes the length rule cannot frame are held (never more than
  /// 256) until idle() instead of failing here.
  constexpr decode_result<rtu_frame> feed(byte_view in) noexcept {
    std::size_t used = 0;
    for (;;) {
      if (size_ >= want_) {
        const decode_result<rtu_frame> r = scan(used, false);
        if (!r.is_incomplete()) {
          return r;
        }
      }
      // here want_ > size_ and want_ <= 256
      if (used >= in.size()) {
        return need_input{want_ - size_};
      }
      std::size_t take = want_ - size_;
      if (take > in.size() - used) {
        take = in.size() - used;
      }
      for (std::size_t i = 0; i < take; ++i) {
        buffer_[size_ + i] = in[used + i];
      }
      size_ += take;
      used += take;
    }
  }

  /// The user's t3.5 timer expired: the bytes held end a frame. Complete: the bytes held as
  /// one CRC-valid frame for this node (frame_end::silence), else the first frame the length
  /// rule finds in them. Failed: truncated, crc_mismatch or modbus_pdu_length. Either way the
  /// framer is empty afterwards. Incomplete: nothing was held, or only a frame for another
  /// address (counted in skipped()).
  constexpr decode_result<rtu_frame> idle() noexcept {
    if (size_ == 0U) {
      return need_input{1};
    }
    decode_result<rtu_frame> r = need_input{1};
    bool settled = false;
    if (options_.ends == frame_end::silence) {
      const decode_result<rtu_frame> whole = decode_rtu(byte_view(buffer_, size_));
      if (whole.is_complete()) {
        settled = true;
        if (for_us(whole.value().slave)) {
          r = hand_over(whole.value(), size_, 0);
        } else {
          ++skipped_;
          size_ = 0;
        }
      }
    }
    if (!settled) {
      // the first frame the length rule finds in the bytes held, past any garbage; else the
      // first failure met on the way
      decode_result<rtu_frame> first = need_input{1};
      for (;;) {
        r = scan(0, true);
        if (!r.is_failed() || size_ == 0U) {
          break;
        }
        if (first.is_incomplete()) {
          first = r;
        }
      }
      if (!r.is_complete()) {
        r = first.is_failed() ? first : (r.is_failed() ? r : decode_failure{errc::truncated, 0});
      }
    }
    // The silence ends whatever is held: the framer starts the next frame empty.
    dropped_ += size_;
    size_ = 0;
    want_ = 2;
    waiting_ = false;
    return r;
  }

  /// Bytes dropped while resynchronising, frames skipped for other addresses.
  constexpr std::size_t dropped() const noexcept { return dropped_; }
  constexpr std::size_t skipped() const noexcept { return skipped_; }
  constexpr std::size_t pending() const noexcept { return size_; }

 private:
  constexpr void drop_front(std::size_t n) noexcept {
    for (std::size_t i = n; i < size_; ++i) {
      buffer_[i - n] = buffer_[i];
    }
    size_ -= n;
    waiting_ = false;
  }

  constexpr bool for_us(std::uint8_t slave) const noexcept {
    if (role_ == framer_role::server) {
      return slave == address_ || slave == broadcast_address;
    }
    return address_ == 0U || slave == address_;
  }

  // FC08 sub-function 00 (Return Query Data) carries any even number of data bytes and no
  // count (Modbus over Serial Line §6.1.1): its frame is 8 + 2k bytes, the CRC tells which.
  constexpr bool query_data(std::size_t held) const noexcept {
    return held >= 8U && buffer_[1] == 0x08U && buffer_[2] == 0U && buffer_[3] == 0U;
  }

  // The first length 8 + 2k (from `from`, up to `to`) at which the CRC ends a frame, or the
  // first length past `to` (not yet held). One CRC pass over the bytes held.
  constexpr std::size_t query_data_end(std::size_t from, std::size_t to) const noexcept {
    crc16 c;
    std::size_t fed = 0;
    std::size_t at = from;
    for (; at <= to; at += 2U) {
      c.update(byte_view(buffer_ + fed, at - 2U - fed));
      fed = at - 2U;
      if (c.value() == static_cast<std::uint16_t>(buffer_[at - 2U] | (buffer_[at - 1U] << 8U))) {
        break;
      }
    }
    return at;
  }

  // Hands `frame` (the first `total` bytes held) over from out_, keeps the rest buffered.
  constexpr decode_result<rtu_frame> hand_over(rtu_frame frame, std::size_t total,
                                               std::size_t used) noexcept {
    for (std::size_t i = 0; i < total; ++i) {
      out_[i] = buffer_[i];
    }
    frame.pdu = byte_view(out_ + 1, total - 3U);
    drop_front(total);
    return decode_result<rtu_frame>::complete(frame, used);
  }

  // The length rule cannot frame the bytes held. With frame_end::silence (and room to hold
  // more) they wait for idle(): true, want_ set. Otherwise the oldest byte is dropped: false.
  constexpr bool wait_for_silence(bool at_end) noexcept {
    if (options_.ends == frame_end::silence && !at_end && size_ < max_rtu_size) {
      want_ = size_ + 1U;
      waiting_ = true;  // no more length decisions on these bytes until idle() or a full buffer
      return true;
    }
    drop_front(1);
    ++dropped_;
    return false;
  }

  // Decides on the bytes held. Incomplete: want_ (> size_) is how many to hold before the next
  // decision.
  constexpr decode_result<rtu_frame> scan(std::size_t used, bool at_end) noexcept {
    if (waiting_) {
      if (!at_end && size_ < max_rtu_size) {
        want_ = size_ + 1U;
        return need_input{1};
      }
      waiting_ = false;
      if (!at_end) {
        drop_front(1);  // a full buffer and still no silence: resynchronise
        ++dropped_;
      }
    }
    for (;;) {
      want_ = 2;
      if (size_ < 2U) {
        return need_input{2U - size_};
      }
      const byte_view held(buffer_, size_);
      std::size_t total = role_ == framer_role::server
                              ? predict_request_size(held)
                              : predict_response_size(held, function_, options_.fc11);
      if (total == unknown_length) {
        if (at_end) {
          total = size_;  // the t3.5 silence says where it ends
        } else if (wait_for_silence(false)) {
          return need_input{1};  // no length rule: the silence will tell
        } else {
          continue;  // garbage: resynchronise
        }
      }
      if (total == 0U) {  // a count byte is still missing
        want_ = size_ + 1U;
        return need_input{1};
      }
      if (total > max_rtu_size || total < min_rtu_size) {
        if (wait_for_silence(at_end)) {
          return need_input{1};
        }
        return decode_failure{errc::modbus_pdu_length, used};
      }
      if (size_ < total) {
        want_ = total;
        return need_input{total - size_};
      }
      if (query_data(total)) {
        const std::size_t at = query_data_end(total, size_);
        if (at <= size_) {
          total = at;  // the CRC confirms this length
        } else if (at <= max_rtu_size && !at_end) {
          want_ = at;
          return need_input{at - size_};
        }
      }
      const decode_result<rtu_frame> f = decode_rtu(byte_view(buffer_, total));
      if (f.is_failed()) {
        // resynchronise (a frame may start at the next byte), or wait for the silence
        if (wait_for_silence(at_end)) {
          return need_input{1};
        }
        return decode_failure{f.error(), used, f.expected(), f.received()};
      }
      if (!for_us(f.value().slave)) {
        drop_front(total);
        ++skipped_;
        continue;
      }
      // The frame handed out lives in out_ until the next call; the rest stays buffered.
      return hand_over(f.value(), total, used);
    }
  }

  framer_role role_;
  std::uint8_t address_;
  framer_options options_;
  std::uint8_t function_ = 0;
  std::uint8_t buffer_[max_rtu_size] = {};
  std::uint8_t out_[max_rtu_size] = {};
  std::size_t size_ = 0;
  std::size_t want_ = 2;
  std::size_t dropped_ = 0;
  std::size_t skipped_ = 0;
  bool waiting_ = false;  // the length rule failed on the bytes held: only idle() decides
};

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_FRAMER_HPP
