// motionbus — the bounded frame buffer under the stream objects (the T-format receiver and
// line listener, the Modbus RTU framer): bytes are appended at the end and dropped from the front
// by moving an index, never by shifting what is held; the held bytes are moved to the front only
// when the end reaches the capacity, or when the bytes wanted would not fit (at most once per
// frame). The bytes held are always contiguous, so a frame is handed over as a view into the
// buffer.
//
// The buffer also keeps its owner's decision point: want(n) says that the owner decides
// nothing until `n` bytes are held. push_before() is the per-byte step of a stream object
// (a byte inside a frame whose length is known): two loads, a compare, two stores; it refuses
// exactly the byte that makes `n` held, so an owner that wanted a whole frame may take a
// refusal for the frame's last byte. The bytes are the first member, so that the store is one
// instruction from the object's address when the buffer is the owner's first member too (the
// receiver and the framer put it first).
//
// Its public operations are those both protocols' stream objects use; a step only one owner
// takes lives in that owner, on the protected members (modbus::detail::rtu_buffer).
//
// A default-constructed buffer is all zeros: a stream object that holds one can be a `static`
// in .bss. No heap, no I/O.
#ifndef MOTIONBUS_CORE_FRAME_BUFFER_HPP
#define MOTIONBUS_CORE_FRAME_BUFFER_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "motionbus/core/config.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {

template <std::size_t N>
class frame_buffer {
  static_assert(N >= 1U && N <= 65535U, "frame_buffer: 1 to 65535 bytes");

 protected:
  // holds 0..N (want_ and stop_ reach N)
  using index = std::conditional_t<(N < 256U), std::uint8_t, std::uint16_t>;

 public:
  static constexpr std::size_t capacity = N;

  /// Bytes held.
  constexpr std::size_t size() const noexcept { return static_cast<std::size_t>(end_ - start_); }
  constexpr bool empty() const noexcept { return end_ == start_; }
  /// Byte `i` of those held (i < size()).
  constexpr std::uint8_t operator[](std::size_t i) const noexcept { return bytes_[start_ + i]; }
  /// The bytes held (a frame handed over: `view().first(n)`), valid until a byte is appended
  /// (push, push_before, put_last, fill_and_decide).
  constexpr byte_view view() const noexcept { return byte_view(bytes_ + start_, size()); }

  /// Appends one byte; false (nothing appended) when N bytes are held.
  constexpr bool push(std::uint8_t b) noexcept {
    const index end = end_;
    if (end == N) {
      return push_at_capacity(b);
    }
    end_ = static_cast<index>(end + 1U);
    bytes_[end] = b;
    return true;
  }
  /// The per-byte step of a stream object: appends `b` when, with it, fewer than wanted()
  /// bytes are held, and returns true. False (nothing appended) when a decision is due: the
  /// byte would make wanted() held (or more).
  constexpr bool push_before(std::uint8_t b) noexcept {
    const index end = end_;
    if (end >= stop_) {
      return false;
    }
    bytes_[end] = b;
    end_ = static_cast<index>(end + 1U);
    return true;
  }
  /// Appends `b` where there is room for it at the end, unchecked: the byte push_before()
  /// refused (with it, wanted() bytes are held: see want()), or the first byte after restart().
  constexpr void put_last(std::uint8_t b) noexcept {
    bytes_[end_] = b;
    end_ = static_cast<index>(end_ + 1U);
  }

  /// The owner decides when `n` (<= N) bytes are held: push_before() refuses the byte that
  /// would make `n` (or more) held, and no earlier byte (room is made at the end first where
  /// `n` bytes from the front would not fit), so that the owner may take a refusal inside a
  /// frame of `n` bytes for its last byte.
  // inline: called at every decision of both stream objects; a call costs more than the body.
  MOTIONBUS_INLINE constexpr void want(std::size_t n) noexcept {
    want_ = static_cast<index>(n);
    const std::size_t stop = static_cast<std::size_t>(start_) + n;
    if (stop > N) {
      make_room();  // sets the stop from the front
      return;
    }
    stop_ = static_cast<index>(stop - (stop != 0U ? 1U : 0U));
  }
  /// The `n` of the last want() (0: decide at every byte).
  constexpr std::size_t wanted() const noexcept { return want_; }

  /// The feed loop of a stream object, written once: whenever wanted() bytes are held, asks
  /// `decide()` (true: something settled, stop); else appends from `in`, at `used` (advanced),
  /// what wanted() still needs. True when decide() settled; false when `in` is used up.
  template <class Decide>
  constexpr bool fill_and_decide(byte_view in, std::size_t& used, Decide&& decide) noexcept {
    for (;;) {
      if (size() >= wanted() && decide()) {
        return true;
      }
      if (used >= in.size()) {
        return false;
      }
      used += append(in.subspan(used), wanted() - size());
    }
  }

  /// Drops the first `n` bytes held (n <= size()); wanted() then counts from the front left.
  constexpr void drop(std::size_t n) noexcept { drop(n, want_); }
  /// drop(n) and want(next_want) in one step.
  // inline: the step after every frame and every rejected byte; a call costs more than the body.
  MOTIONBUS_INLINE constexpr void drop(std::size_t n, std::size_t next_want) noexcept {
    const auto start = static_cast<index>(start_ + n);
    if (start == end_) {  // all of it: back to the front
      restart(next_want);
      return;
    }
    start_ = start;
    want(next_want);
  }
  /// Drops everything held, whose bytes stay readable in view() until the next push (a frame
  /// handed over), and want(n) from the front.
  constexpr void restart(std::size_t n) noexcept {
    start_ = 0;
    end_ = 0;
    want_ = static_cast<index>(n);
    stop_ = static_cast<index>(n - (n != 0U ? 1U : 0U));
  }

 private:
  // Appends up to `n` bytes of `in` (as many as fit); returns how many.
  constexpr std::size_t append(byte_view in, std::size_t n) noexcept {
    if (n > in.size()) {
      n = in.size();
    }
    // coverage-branch: never true, as the region below says
    if (end_ + n > N) {
      // coverage-begin: want() and drop() keep start + wanted() <= N, so what fill_and_decide asks
      make_room();
      if (end_ + n > N) {
        n = N - end_;
      }
      // coverage-end
    }
    for (std::size_t i = 0; i < n; ++i) {
      bytes_[end_ + i] = in[i];
    }
    end_ = static_cast<index>(end_ + n);
    return n;
  }

  constexpr bool push_at_capacity(std::uint8_t b) noexcept {
    if (!make_room()) {
      return false;
    }
    bytes_[end_] = b;
    ++end_;
    return true;
  }

 protected:
  // For an owner's own steps on its buffer (the RTU framer's server path, modbus/framer.hpp).
  // Moves the bytes held to the front; false when there is no room to make. Out of line: the
  // rare path (at most once per frame) of the inline steps.
  MOTIONBUS_NOINLINE constexpr bool make_room() noexcept {
    if (start_ == 0U) {
      return false;
    }
    const std::size_t n = size();
    for (std::size_t i = 0; i < n; ++i) {
      bytes_[i] = bytes_[start_ + i];
    }
    start_ = 0;
    end_ = static_cast<index>(n);
    stop_ = static_cast<index>(want_ - (want_ != 0U ? 1U : 0U));
    return true;
  }

  std::uint8_t bytes_[N] = {};  // first: see the comment at the top
  index start_ = 0;
  index end_ = 0;
  index stop_ = 0;  // start_ + want_ - 1 (0 for none): push_before() refuses at end_ >= stop_
  index want_ = 0;
};

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_FRAME_BUFFER_HPP
