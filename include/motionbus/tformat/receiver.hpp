// motionbus — T-format stream receiver for UART-style byte streams (master side).
//
// Feed it bytes as they arrive, one at a time or in chunks. It knows each response's length
// from its CF, skips the echo of the master's own request on half-duplex adapters whose
// receiver is always on, drops garbage until a valid CF, and after a corrupted frame rescans
// from the next byte so that no valid frame behind it is lost. Holds at most one frame
// (11 bytes); no heap, no I/O.
//
//   receiver rx({echo::expected});
//   rx.sent(request);                         // after writing the request to the UART
//   while (!in.empty()) {
//     auto r = rx.feed(in);
//     if (r.is_incomplete()) break;           // every byte was taken; wait for more
//     in = in.subspan(r.consumed());
//     if (r) use(r.value()); else log(r.error());
//   }
#ifndef MOTIONBUS_TFORMAT_RECEIVER_HPP
#define MOTIONBUS_TFORMAT_RECEIVER_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
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
  constexpr explicit receiver(receiver_options opt = {}) noexcept : opt_(opt) {}

  /// Records the request just sent (up to 4 bytes): its echo is skipped when echo::expected,
  /// and responses are checked against it. Drops any partial frame.
  constexpr void sent(byte_view request_frame) noexcept {
    want_ = 1;
    request_size_ =
        request_frame.size() < max_request_size ? request_frame.size() : max_request_size;
    for (std::size_t i = 0; i < request_size_; ++i) {
      request_[i] = request_frame[i];
    }
    echo_pending_ = opt_.echo_mode == echo::expected && request_size_ > 0U;
    size_ = 0;
  }

  /// Processes bytes from `in` until a frame or an error is found.
  /// Complete: a response; consumed() = bytes of `in` taken. Failed: a candidate frame was
  /// rejected (CRC, reserved bits, check against the request); consumed() = bytes of `in`
  /// taken; the receiver rescans from the frame's second byte on the next call (call again,
  /// even with an empty `in`, until it reports incomplete). Incomplete: all of `in` was taken.
  /// Each byte is copied once; a frame is decoded only when its last byte has arrived.
  constexpr decode_result<response> feed(byte_view in) noexcept {
    if (in.size() == 1U && size_ + 1U < want_) {
      // The common case of a byte-by-byte feed (a UART interrupt): a byte inside a frame
      // whose length is known, no decision to make.
      buffer_[size_] = in[0];
      ++size_;
      return need_input{want_ - size_};
    }
    std::size_t used = 0;
    for (;;) {
      if (size_ >= want_) {  // enough buffered to decide something
        const decode_result<response> r = scan(used);
        if (!r.is_incomplete()) {
          return r;
        }
        continue;  // scan() raised want_
      }
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

  /// The line went idle (end of frame): an incomplete frame is dropped. Returns errc::truncated
  /// when one was, else errc::ok.
  constexpr errc idle() noexcept {
    const bool partial = size_ > 0U;
    dropped_ += size_;
    size_ = 0;
    want_ = 1;
    echo_pending_ = false;
    return partial ? errc::truncated : errc::ok;
  }

  /// Bytes skipped as garbage (no valid CF) or dropped by idle(), since construction.
  constexpr std::size_t dropped() const noexcept { return dropped_; }
  /// Echo bytes skipped since construction.
  constexpr std::size_t echoes_skipped() const noexcept { return echoes_; }
  /// Bytes held for an unfinished frame.
  constexpr std::size_t pending() const noexcept { return size_; }

 private:
  constexpr void drop_front(std::size_t n) noexcept {
    for (std::size_t i = n; i < size_; ++i) {
      buffer_[i - n] = buffer_[i];
    }
    size_ -= n;
  }

  // Decides on the buffer (size_ >= want_): skips an echo, drops garbage, decodes a complete
  // frame. Incomplete: want_ was raised to the bytes needed before the next decision.
  constexpr decode_result<response> scan(std::size_t used) noexcept {
    for (;;) {
      want_ = 1;
      if (size_ == 0U) {
        return need_input{1};
      }
      if (echo_pending_) {
        std::size_t match = 0;
        while (match < size_ && match < request_size_ && buffer_[match] == request_[match]) {
          ++match;
        }
        if (match == request_size_) {  // the whole echo: skip it
          drop_front(match);
          echoes_ += match;
          echo_pending_ = false;
          continue;
        }
        if (match == size_) {
          want_ = request_size_;
          return need_input{request_size_ - match};
        }
        echo_pending_ = false;  // not an echo after all: parse as a response
      }
      const std::uint8_t code = data_id_code(buffer_[0]);
      if (buffer_[0] != valid_control_fields[code]) {
        drop_front(1);  // garbage: no valid CF here
        ++dropped_;
        continue;
      }
      const std::size_t frame_size = response_sizes[code];
      if (size_ < frame_size) {
        want_ = frame_size;
        return need_input{frame_size - size_};
      }
      const decode_result<response> r =
          decode_response(byte_view(buffer_, frame_size), opt_.decode);
      if (r.is_failed()) {
        const errc e = r.error();
        drop_front(1);  // rescan from the next byte: a valid frame may start inside
        ++dropped_;
        return decode_failure{e, used, r.expected(), r.received()};
      }
      const std::size_t n = r.consumed();
      if (opt_.check_against_request && request_size_ > 0U) {
        std::uint32_t want = 0;
        std::uint32_t got = 0;
        const errc e = check_response(byte_view(request_, request_size_), r.value(), &want, &got);
        if (e != errc::ok) {
          drop_front(n);
          return decode_failure{e, used, want, got};
        }
      }
      drop_front(n);
      return decode_result<response>::complete(r.value(), used);
    }
  }

  receiver_options opt_;
  std::uint8_t buffer_[max_response_size] = {};
  std::size_t size_ = 0;
  std::size_t want_ = 1;  // bytes to hold before the next decision (1..11)
  std::uint8_t request_[max_request_size] = {};
  std::size_t request_size_ = 0;
  bool echo_pending_ = false;
  std::size_t dropped_ = 0;
  std::size_t echoes_ = 0;
};

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_RECEIVER_HPP
