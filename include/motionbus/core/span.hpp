// motionbus — non-owning views over caller-owned memory.
//
// `motionbus::span<T>` is `std::span<T>` (dynamic extent) under C++20 and a minimal
// equivalent under C++17 with the same member names, so code written against it compiles
// under both. A view never owns what it points at: it is valid only while the caller's
// buffer is.
#ifndef MOTIONBUS_CORE_SPAN_HPP
#define MOTIONBUS_CORE_SPAN_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "motionbus/core/config.hpp"

#if MOTIONBUS_HAS_STD_SPAN
#include <span>
#endif

namespace motionbus {

#if MOTIONBUS_HAS_STD_SPAN

template <class T>
using span = std::span<T>;

#else

/// Minimal C++17 stand-in for std::span<T> (dynamic extent only).
/// Preconditions as for std::span: first/last/subspan/operator[] need in-range arguments;
/// motionbus's own decoders check lengths before calling them.
template <class T>
class span {
 public:
  using element_type = T;
  using value_type = std::remove_cv_t<T>;
  using size_type = std::size_t;
  using pointer = T*;
  using reference = T&;
  using iterator = T*;

  constexpr span() noexcept = default;
  constexpr span(T* data, std::size_t size) noexcept : data_(data), size_(size) {}
  template <std::size_t N>
  // NOLINTNEXTLINE(google-explicit-constructor): an array converts, as to std::span
  constexpr span(T (&array)[N]) noexcept : data_(array), size_(N) {}
  template <class U, std::size_t N,
            class = std::enable_if_t<std::is_convertible<U (*)[], T (*)[]>::value>>
  constexpr span(std::array<U, N>& array) noexcept  // NOLINT(google-explicit-constructor)
      : data_(array.data()), size_(N) {}
  template <class U, std::size_t N,
            class = std::enable_if_t<std::is_convertible<const U (*)[], T (*)[]>::value>>
  constexpr span(const std::array<U, N>& array) noexcept  // NOLINT(google-explicit-constructor)
      : data_(array.data()), size_(N) {}
  template <class U, class = std::enable_if_t<!std::is_same<U, T>::value &&
                                              std::is_convertible<U (*)[], T (*)[]>::value>>
  constexpr span(const span<U>& other) noexcept  // NOLINT(google-explicit-constructor)
      : data_(other.data()), size_(other.size()) {}

  constexpr T* data() const noexcept { return data_; }
  constexpr std::size_t size() const noexcept { return size_; }
  constexpr std::size_t size_bytes() const noexcept { return size_ * sizeof(T); }
  constexpr bool empty() const noexcept { return size_ == 0; }
  constexpr T& operator[](std::size_t i) const noexcept { return data_[i]; }
  constexpr T* begin() const noexcept { return data_; }
  constexpr T* end() const noexcept { return data_ + size_; }
  constexpr T& front() const noexcept { return data_[0]; }
  constexpr T& back() const noexcept { return data_[size_ - 1]; }
  constexpr span first(std::size_t n) const noexcept { return span(data_, n); }
  constexpr span last(std::size_t n) const noexcept { return span(data_ + (size_ - n), n); }
  constexpr span subspan(std::size_t offset,
                         std::size_t count = static_cast<std::size_t>(-1)) const noexcept {
    return span(data_ + offset, count == static_cast<std::size_t>(-1) ? size_ - offset : count);
  }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

#endif

/// Read-only bytes (input to decoders).
using byte_view = span<const std::uint8_t>;
/// Writable bytes (output of encoders).
using mutable_byte_view = span<std::uint8_t>;

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_SPAN_HPP
