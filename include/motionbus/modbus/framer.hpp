// motionbus — Modbus RTU stream framing, both directions (PROTOCOL_NOTES §3.1).
//
// USB adapters and OS buffering blur the t3.5 silence, so the dependable frame boundary is the
// length predicted from the function code and counts, confirmed by the CRC; the user's t3.5
// timer is an optional hint (end_of_frame()). A server frames requests and keeps those for its
// address and broadcasts; a client frames the response to its outstanding request. After
// garbage or a bad CRC the framer drops one byte at a time and rescans (at most 256 bytes are
// ever held). No heap, no I/O.
//
//   rtu_framer rx(framer_role::server, 0x11);
//   for (;;) {
//     auto r = rx.feed(in);
//     if (r.is_incomplete()) break;   // all of `in` taken
//     in = in.subspan(r.consumed());
//     if (r) handle(r.value());       // r->pdu points into rx: use it before the next feed()
//   }
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

class rtu_framer {
 public:
  /// `address`: a server's own address (1..247; it also takes broadcasts), or for a client the
  /// slave it talks to (0: accept any).
  /// `unknown_by_silence`: frame functions without a length rule (custom functions) by the
  /// user's end_of_frame() signal. Off by default: such bytes are treated as garbage, so that a
  /// resynchronising framer never waits on noise.
  constexpr rtu_framer(framer_role role, std::uint8_t address,
                       report_id_format fc11 = report_id_format::standard,
                       bool unknown_by_silence = false) noexcept
      : role_(role), address_(address), fc11_(fc11), unknown_by_silence_(unknown_by_silence) {}

  /// Client: records the request just sent (its function selects the response layout).
  constexpr void sent(std::uint8_t slave, std::uint8_t function) noexcept {
    address_ = slave;
    function_ = function;
    size_ = 0;
    want_ = 2;
  }

  /// Takes bytes from `in` until a frame or an error. Complete: a CRC-checked frame for this
  /// node; consumed() = bytes of `in` taken; its pdu view is valid until the next call.
  /// Failed: crc_mismatch (expected/received) or modbus_pdu_length (length rule gives more than
  /// 256 bytes); the framer rescans from the next byte on the next call. Incomplete: all of `in`
  /// was taken. Frames for other addresses are skipped silently (skipped()).
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

  /// The user's t3.5 timer expired: the bytes held end a frame. Complete: a CRC-valid frame
  /// (with unknown_by_silence, of any function). Failed: truncated or crc_mismatch. Either way
  /// the framer is empty afterwards. Incomplete: nothing was held.
  constexpr decode_result<rtu_frame> end_of_frame() noexcept {
    if (size_ == 0U) {
      return need_input{1};
    }
    const decode_result<rtu_frame> r = scan(0, true);
    // The silence ends whatever is held: the framer starts the next frame empty.
    dropped_ += size_;
    size_ = 0;
    want_ = 2;
    if (r.is_incomplete()) {
      return decode_failure{errc::truncated, 0};
    }
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
  }

  constexpr bool for_us(std::uint8_t slave) const noexcept {
    if (role_ == framer_role::server) {
      return slave == address_ || slave == broadcast_address;
    }
    return address_ == 0U || slave == address_;
  }

  // Decides on the bytes held. Incomplete: want_ (> size_) is how many to hold before the next
  // decision.
  constexpr decode_result<rtu_frame> scan(std::size_t used, bool at_end) noexcept {
    for (;;) {
      want_ = 2;
      if (size_ < 2U) {
        return need_input{2U - size_};
      }
      const byte_view held(buffer_, size_);
      std::size_t total = role_ == framer_role::server
                              ? predict_request_size(held)
                              : predict_response_size(held, function_, fc11_);
      if (total == unknown_length) {
        if (at_end) {
          total = size_;  // the t3.5 silence says where it ends
        } else if (!unknown_by_silence_) {
          drop_front(1);  // no length rule: garbage unless framed by silence
          ++dropped_;
          continue;
        } else if (size_ == max_rtu_size) {
          drop_front(1);  // no frame ends here: resynchronise
          ++dropped_;
          continue;
        } else {
          want_ = size_ + 1U;
          return need_input{1};
        }
      }
      if (total == 0U) {  // a count byte is still missing
        want_ = size_ + 1U;
        return need_input{1};
      }
      if (total > max_rtu_size || total < min_rtu_size) {
        drop_front(1);
        ++dropped_;
        return decode_failure{errc::modbus_pdu_length, used};
      }
      if (size_ < total) {
        want_ = total;
        return need_input{total - size_};
      }
      const decode_result<rtu_frame> f = decode_rtu(byte_view(buffer_, total));
      if (f.is_failed()) {
        drop_front(1);  // resynchronise: a frame may start at the next byte
        ++dropped_;
        return decode_failure{f.error(), used, f.expected(), f.received()};
      }
      if (!for_us(f.value().slave)) {
        drop_front(total);
        ++skipped_;
        continue;
      }
      // The frame handed out lives in out_ until the next call; the rest stays buffered.
      for (std::size_t i = 0; i < total; ++i) {
        out_[i] = buffer_[i];
      }
      rtu_frame frame = f.value();
      frame.pdu = byte_view(out_ + 1, total - 3U);
      drop_front(total);
      return decode_result<rtu_frame>::complete(frame, used);
    }
  }

  framer_role role_;
  std::uint8_t address_;
  report_id_format fc11_;
  bool unknown_by_silence_;
  std::uint8_t function_ = 0;
  std::uint8_t buffer_[max_rtu_size] = {};
  std::uint8_t out_[max_rtu_size] = {};
  std::size_t size_ = 0;
  std::size_t want_ = 2;
  std::size_t dropped_ = 0;
  std::size_t skipped_ = 0;
};

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_FRAMER_HPP
