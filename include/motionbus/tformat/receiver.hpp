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
  constexpr decode_result<response> feed(byte_view in) noexcept {
    std::size_t used = 0;
    for (;;) {
      // Work on what is buffered first.
      const decode_result<response> r = scan(used);
      if (!r.is_incomplete()) {
        return r;
      }
      if (used >= in.size()) {
        return need_input{r.needed()};
      }
      if (size_ == max_response_size) {  // cannot happen: scan() decides on 11 bytes
        drop_front(1);
        ++dropped_;
      }
      buffer_[size_++] = in[used++];
    }
  }

  /// The line went idle (end of frame): an incomplete frame is dropped. Returns errc::truncated
  /// when one was, else errc::ok.
  constexpr errc idle() noexcept {
    const bool partial = size_ > 0U;
    dropped_ += size_;
    size_ = 0;
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

  // Tries to make progress on the buffer. Incomplete means "needs another byte".
  constexpr decode_result<response> scan(std::size_t used) noexcept {
    for (;;) {
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
          return need_input{request_size_ - match};
        }
        echo_pending_ = false;  // not an echo after all: parse as a response
      }
      const decode_result<response> r = decode_response(byte_view(buffer_, size_), opt_.decode);
      if (r.is_incomplete()) {
        return r;
      }
      if (r.is_failed()) {
        const errc e = r.error();
        if (e == errc::tformat_sync_code || e == errc::tformat_parity ||
            e == errc::tformat_unknown_data_id) {
          drop_front(1);  // garbage: no valid CF here
          ++dropped_;
          continue;
        }
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
  std::uint8_t request_[max_request_size] = {};
  std::size_t request_size_ = 0;
  bool echo_pending_ = false;
  std::size_t dropped_ = 0;
  std::size_t echoes_ = 0;
};

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_RECEIVER_HPP
