// motionbus — result types, usable in C++17 without exceptions and in constant expressions.
//
//  * `result<T>`        a value or an error code (encoders, field readers, builders).
//  * `decode_result<T>` the three outcomes of a decoder: complete (value plus units consumed),
//                       incomplete (need more input, with a lower bound on how much), or failed
//                       (an error code, the units the caller may drop, and evidence such as the
//                       expected and received CRC). Units are bytes or bits, as the decoder says.
//
// Both are [[nodiscard]]. Accessing the value of a failed result yields a value-initialised T,
// never undefined behaviour.
#ifndef MOTIONBUS_CORE_RESULT_HPP
#define MOTIONBUS_CORE_RESULT_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "motionbus/core/errc.hpp"

namespace motionbus {

/// A value of type T, or an error code.
template <class T>
class [[nodiscard]] result {
  static_assert(!std::is_same<std::remove_cv_t<T>, errc>::value, "result<errc> is ambiguous");
  static_assert(std::is_default_constructible<T>::value,
                "result<T> needs a default-constructible T");

 public:
  using value_type = T;

  constexpr result(const T& value) noexcept(std::is_nothrow_copy_constructible<T>::value)  // NOLINT
      : value_(value) {}
  /// Precondition: e != errc::ok (an ok code without a value is stored as invalid_argument).
  constexpr result(errc e) noexcept  // NOLINT(google-explicit-constructor)
      : error_(e == errc::ok ? errc::invalid_argument : e) {}

  constexpr bool ok() const noexcept { return error_ == errc::ok; }
  constexpr explicit operator bool() const noexcept { return ok(); }
  constexpr errc error() const noexcept { return error_; }
  /// The value; value-initialised when !ok().
  constexpr const T& value() const noexcept { return value_; }
  constexpr const T& operator*() const noexcept { return value_; }
  constexpr const T* operator->() const noexcept { return &value_; }
  constexpr T value_or(const T& fallback) const noexcept { return ok() ? value_ : fallback; }

 private:
  T value_{};
  errc error_ = errc::ok;
};

/// The three outcomes of a decoder.
enum class decode_status : std::uint8_t { complete = 0, incomplete = 1, failed = 2 };

/// Returned (converted) by a decoder that needs more input: at least `at_least` more units.
struct need_input {
  std::size_t at_least = 1;
};

/// Returned (converted) by a decoder that rejects its input.
struct decode_failure {
  errc code = errc::invalid_argument;
  /// Units of input the caller may drop before trying again (0: unknown / drop nothing).
  std::size_t consumed = 0;
  /// Evidence, where the error has any: e.g. the CRC computed (expected) and the CRC received.
  std::uint32_t expected = 0;
  std::uint32_t received = 0;
};

/// Outcome of decoding a T from bytes or bits.
template <class T>
class [[nodiscard]] decode_result {
  static_assert(std::is_default_constructible<T>::value,
                "decode_result<T> needs a default-constructible T");

 public:
  using value_type = T;

  /// A complete value that used `consumed` units of input.
  static constexpr decode_result complete(const T& value, std::size_t consumed) noexcept {
    return decode_result(value, consumed);
  }
  /// A complete value built in place: `fill(T&)` sets the fields of a value-initialised T in
  /// the result itself (no temporary T to copy; some compilers copy it through memory).
  template <class Fill>
  static constexpr decode_result complete_with(std::size_t consumed, Fill&& fill) noexcept {
    decode_result r;
    r.count_ = consumed;
    fill(r.value_);
    return r;
  }
  /// The outcome of a decode_result being built in place by build(): call one of need, fail
  /// or complete once (none: complete, value-initialised, 0 units consumed).
  class outcome {
   public:
    constexpr explicit outcome(decode_result& r) noexcept : r_(r) {}
    /// Incomplete: at least `at_least` more units (1 if 0).
    constexpr void need(std::size_t at_least) noexcept {
      r_.status_ = decode_status::incomplete;
      r_.count_ = at_least == 0 ? 1 : at_least;
    }
    /// Failed as decode_failure{e, consumed} (an ok `e`: invalid_argument).
    constexpr void fail(errc e, std::size_t consumed) noexcept {
      r_.status_ = decode_status::failed;
      r_.error_ = e == errc::ok ? errc::invalid_argument : e;
      r_.count_ = consumed;  // the evidence stays 0, as built
    }
    /// Failed as decode_failure{e, consumed, expected, received}.
    constexpr void fail(errc e, std::size_t consumed, std::uint32_t expected,
                        std::uint32_t received) noexcept {
      fail(e, consumed);
      r_.expected_ = expected;
      r_.received_ = received;
    }
    /// Complete using `consumed` units: `fill(T&)` sets the fields of the value-initialised T.
    template <class Fill>
    constexpr void complete(std::size_t consumed, Fill&& fill) noexcept {
      r_.count_ = consumed;
      fill(r_.value_);
    }

   private:
    decode_result& r_;
  };
  /// A result built in place: `steps(outcome)` decodes and settles the outcome through it, so
  /// that every way out writes only its own fields into the one object returned (a decoder
  /// with several exits then needs no copy of T or of the result for any of them).
  template <class Steps>
  static constexpr decode_result build(Steps&& steps) noexcept {
    decode_result r;
    steps(outcome(r));
    return r;
  }
  constexpr decode_result(need_input n) noexcept  // NOLINT(google-explicit-constructor)
      : status_(decode_status::incomplete), count_(n.at_least == 0 ? 1 : n.at_least) {}
  constexpr decode_result(decode_failure f) noexcept  // NOLINT(google-explicit-constructor)
      : status_(decode_status::failed),
        error_(f.code == errc::ok ? errc::invalid_argument : f.code),
        count_(f.consumed),
        expected_(f.expected),
        received_(f.received) {}

  constexpr decode_status status() const noexcept { return status_; }
  constexpr bool is_complete() const noexcept { return status_ == decode_status::complete; }
  constexpr bool is_incomplete() const noexcept { return status_ == decode_status::incomplete; }
  constexpr bool is_failed() const noexcept { return status_ == decode_status::failed; }
  constexpr explicit operator bool() const noexcept { return is_complete(); }

  /// The decoded value; value-initialised unless complete.
  constexpr const T& value() const noexcept { return value_; }
  constexpr const T& operator*() const noexcept { return value_; }
  constexpr const T* operator->() const noexcept { return &value_; }
  /// Complete: units used by the value. Failed: units the caller may drop. Else 0.
  constexpr std::size_t consumed() const noexcept { return is_incomplete() ? 0U : count_; }
  /// Incomplete: lower bound on the further units needed. Else 0.
  constexpr std::size_t needed() const noexcept { return is_incomplete() ? count_ : 0U; }
  /// Failed: the error. Else errc::ok.
  constexpr errc error() const noexcept { return error_; }
  constexpr std::uint32_t expected() const noexcept { return expected_; }
  constexpr std::uint32_t received() const noexcept { return received_; }

 private:
  constexpr decode_result() noexcept = default;
  constexpr decode_result(const T& value, std::size_t consumed) noexcept
      : value_(value), count_(consumed) {}

  decode_status status_ = decode_status::complete;
  errc error_ = errc::ok;
  T value_{};
  std::size_t count_ = 0;  ///< consumed (complete, failed) or needed (incomplete): one word
  std::uint32_t expected_ = 0;
  std::uint32_t received_ = 0;
};

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_RESULT_HPP
