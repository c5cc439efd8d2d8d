// motionbus — result types, usable in C++17 without exceptions and in constant expressions.
//
//  * `result<T>`        a value or an error code (encoders, field readers, builders).
//  * `decode_result<T>` the three outcomes of a decoder: complete (value plus units consumed),
//                       incomplete (need more input, with a lower bound on how much), or failed
//                       (an error code, the units the caller may drop, and evidence such as the
//                       expected and received CRC). Units are bytes unless the type says
//                       bits (decode_result<T, input_unit::bits>: consumed_bits(), needed_bits()).
//
// Both are [[nodiscard]]. Accessing the value of a failed result yields a value-initialised T,
// never undefined behaviour.
#ifndef MOTIONBUS_CORE_RESULT_HPP
#define MOTIONBUS_CORE_RESULT_HPP

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>

#include "motionbus/core/config.hpp"
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
/// (Incomplete is 0: a default-constructed result, all zeros, is incomplete.)
enum class decode_status : std::uint8_t { incomplete = 0, complete = 1, failed = 2 };

/// The unit a decoder counts its input in: bytes (T-format and Modbus byte codecs, the
/// default) or bits (BiSS-C captures and T-format line streams, whose results say so by name:
/// consumed_bits(), needed_bits()).
enum class input_unit : std::uint8_t { bytes = 0, bits = 1 };

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

/// Outcome of decoding a T from bytes or bits. Only the outcome's own fields are written:
/// an incomplete result is two stores (status and units), whatever the size of T, so that a
/// stream object fed one byte at a time pays nothing for the value it has not decoded yet.
/// The value and the failure's evidence share storage; value() of a result that is not
/// complete returns a value-initialised T held in read-only storage (never undefined
/// behaviour, never a copy).
template <class T, input_unit Unit = input_unit::bytes>
class [[nodiscard]] decode_result {
  static_assert(std::is_default_constructible<T>::value,
                "decode_result<T> needs a default-constructible T");
  static_assert(std::is_trivially_copyable<T>::value && std::is_trivially_destructible<T>::value,
                "decode_result<T> needs a trivially copyable, trivially destructible T");

  struct evidence {
    errc code;
    std::uint32_t expected;
    std::uint32_t received;
  };
  // The active member while no value and no evidence is held. Its constructor is user-provided
  // and empty, so that making it active writes no bytes (an empty aggregate, value-initialised,
  // would let a compiler clear the whole union).
  struct nothing {
    constexpr nothing() noexcept {}  // NOLINT(modernize-use-equals-default)
  };
  union storage {
    nothing none;
    T value;
    evidence failure;
    constexpr storage() noexcept : none() {}
    // inline (both): a copy of the value or evidence, which a call moves through the stack.
    MOTIONBUS_INLINE constexpr explicit storage(const T& v) noexcept : value(v) {}
    MOTIONBUS_INLINE constexpr explicit storage(const evidence& f) noexcept : failure(f) {}
  };

 public:
  using value_type = T;

  /// A complete value that used `consumed` units of input.
  static constexpr decode_result complete(const T& value, std::size_t consumed) noexcept {
    return decode_result(value, consumed);
  }
  /// Settles a decode_result in place (a stream object's own result, framer.hpp): call one
  /// of need, fail, complete_in_place or complete_value once; the other fields are not written.
  class outcome {
   public:
    constexpr explicit outcome(decode_result& r) noexcept : r_(r) {}
    /// Incomplete, whatever the result held: at least `at_least` more units (1 if 0).
    constexpr void need(std::size_t at_least) noexcept {
      r_.status_ = decode_status::incomplete;
      r_.count_ = at_least == 0 ? 1 : at_least;
    }
    /// Failed as decode_failure{e, consumed} (an ok `e`: invalid_argument).
    constexpr void fail(errc e, std::size_t consumed) noexcept { fail(e, consumed, 0, 0); }
    /// Failed as decode_failure{e, consumed, expected, received}.
    constexpr void fail(errc e, std::size_t consumed, std::uint32_t expected,
                        std::uint32_t received) noexcept {
      r_.status_ = decode_status::failed;
      r_.count_ = consumed;
      r_.u_ = storage(evidence{e == errc::ok ? errc::invalid_argument : e, expected, received});
    }
    /// Complete using `consumed` units, the value returned for the caller to set every
    /// member of (a large T, such as a BiSS chain's frame, is then written once, in place).
    /// Its members hold no value until set: fail() afterwards replaces it.
    constexpr T& complete_in_place(std::size_t consumed) noexcept {
      r_.status_ = decode_status::complete;
      r_.count_ = consumed;
      if (MOTIONBUS_CONSTANT_EVALUATED()) {
        r_.u_ = storage(T{});  // the value becomes the active member (C++17 constexpr rules)
      } else {
        // Storage for the value, not initialised (the caller sets each member): a byte array
        // begun there creates the trivially copyable T implicitly.
        T& slot = r_.u_.value;
        ::new (static_cast<void*>(&slot)) unsigned char[sizeof(T)];
      }
      return r_.u_.value;
    }
    /// Complete using `consumed` units, with `value` (built whole, e.g. by aggregate
    /// initialisation, so that no field is written twice).
    // inline: the RTU framer's complete frame, stored in place at its last byte.
    MOTIONBUS_INLINE constexpr void complete_value(std::size_t consumed, const T& value) noexcept {
      r_.set_value(consumed, value);
    }

   private:
    decode_result& r_;
  };
  /// Incomplete, at least 1 unit needed: all zeros, so that an object holding one (a stream
  /// object's last result) can be a `static` in .bss.
  constexpr decode_result() noexcept : count_(0), status_(decode_status::incomplete) {}
  // NOLINTNEXTLINE(google-explicit-constructor): `return need_input{n};` from a decoder
  constexpr decode_result(need_input n) noexcept
      : count_(n.at_least == 0 ? 1 : n.at_least), status_(decode_status::incomplete) {}
  // inline: every decoder's failure, three stores into the caller's result.
  // NOLINTNEXTLINE(google-explicit-constructor): `return decode_failure{...};` likewise
  MOTIONBUS_INLINE constexpr decode_result(decode_failure f) noexcept
      : u_(evidence{f.code == errc::ok ? errc::invalid_argument : f.code, f.expected, f.received}),
        count_(f.consumed),
        status_(decode_status::failed) {}

  constexpr decode_status status() const noexcept { return status_; }
  constexpr bool is_complete() const noexcept { return status_ == decode_status::complete; }
  constexpr bool is_incomplete() const noexcept { return status_ == decode_status::incomplete; }
  constexpr bool is_failed() const noexcept { return status_ == decode_status::failed; }
  constexpr explicit operator bool() const noexcept { return is_complete(); }

  /// The decoded value; value-initialised unless complete.
  constexpr const T& value() const noexcept { return is_complete() ? u_.value : empty_; }
  constexpr const T& operator*() const noexcept { return value(); }
  constexpr const T* operator->() const noexcept { return &value(); }
  /// Complete: bytes used by the value. Failed: bytes the caller may drop. Else 0.
  template <input_unit U = Unit, std::enable_if_t<U == input_unit::bytes, int> = 0>
  constexpr std::size_t consumed() const noexcept {
    return is_incomplete() ? 0U : count_;
  }
  /// consumed() of a decoder counting bits.
  template <input_unit U = Unit, std::enable_if_t<U == input_unit::bits, int> = 0>
  constexpr std::size_t consumed_bits() const noexcept {
    return is_incomplete() ? 0U : count_;
  }
  /// Sets consumed() of a complete or failed result (a stream object reports the input it
  /// took rather than the frame's size); nothing for an incomplete one.
  constexpr void set_consumed(std::size_t n) noexcept {
    if (!is_incomplete()) {
      count_ = n;
    }
  }
  /// Incomplete: lower bound on the further bytes needed. Else 0.
  template <input_unit U = Unit, std::enable_if_t<U == input_unit::bytes, int> = 0>
  constexpr std::size_t needed() const noexcept {
    return needed_units();
  }
  /// needed() of a decoder counting bits.
  template <input_unit U = Unit, std::enable_if_t<U == input_unit::bits, int> = 0>
  constexpr std::size_t needed_bits() const noexcept {
    return needed_units();
  }
  /// Failed: the error. Else errc::ok.
  constexpr errc error() const noexcept { return is_failed() ? u_.failure.code : errc::ok; }
  /// Failed: the evidence (e.g. the CRC computed and the CRC received), 0 where the error has
  /// none. Else 0.
  constexpr std::uint32_t expected() const noexcept {
    return is_failed() ? u_.failure.expected : 0U;
  }
  constexpr std::uint32_t received() const noexcept {
    return is_failed() ? u_.failure.received : 0U;
  }

 private:
  // inline: complete()'s, every decoder's value built in the caller's result.
  MOTIONBUS_INLINE constexpr decode_result(const T& value, std::size_t consumed) noexcept
      : u_(value), count_(consumed), status_(decode_status::complete) {}

  constexpr std::size_t needed_units() const noexcept {
    return is_incomplete() ? (count_ == 0U ? 1U : count_) : 0U;  // 0: default-constructed
  }
  // inline: the stream objects' results, set in place.
  MOTIONBUS_INLINE constexpr void set_value(std::size_t consumed, const T& v) noexcept {
    status_ = decode_status::complete;
    count_ = consumed;
    u_ = storage(v);  // makes the value the union's active member (also in constant evaluation)
  }

  static constexpr T empty_{};

  storage u_;
  std::size_t count_;  ///< consumed (complete, failed) or needed (incomplete): one word
  decode_status status_;
};

/// Sets `slot` to what `make()` returns, built in the slot itself: C++17's guaranteed copy
/// elision constructs the returned result there (no temporary, no copy), which an assignment
/// from a call does not promise. In constant evaluation, an assignment.
// inline: so that the result is built in the slot (a call would build it on the stack).
template <class T, class Make>
MOTIONBUS_INLINE constexpr void emplace_result(decode_result<T>& slot, Make&& make) noexcept {
  if (MOTIONBUS_CONSTANT_EVALUATED()) {
    slot = make();  // coverage: constant evaluation only (tests/static/tformat_static.cpp)
  } else {
    ::new (static_cast<void*>(&slot)) decode_result<T>(make());  // trivially destructible
  }
}

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_RESULT_HPP
