// motionbus — typed values over Modbus registers: std::uint32_t, std::int32_t and float over
// two registers, std::uint64_t, std::int64_t and double over four, in the four word orders
// devices use. Modbus defines only 16-bit registers, big-endian on the wire (MODBUS Application
// Protocol V1.1b3 §4.2); how a wider value spreads over several is the device's choice, named
// here by its bytes: A is the most significant byte of the value, B the next, and so on
// (A..D for 32 bits, A..H for 64). Register 0 is the one at the lowest address (first on the
// wire); "AB" is a register whose high byte is A.
//
//   word_order   32-bit registers 0,1   64-bit registers 0..3   pymodbus 3.0 (byteorder, wordorder)
//   abcd         AB CD                  AB CD EF GH             Endian.Big,    Endian.Big
//   cdab         CD AB                  GH EF CD AB             Endian.Big,    Endian.Little
//   badc         BA DC                  BA DC FE HG             Endian.Little, Endian.Big
//   dcba         DC BA                  HG FE DC BA             Endian.Little, Endian.Little
//
// Two independent swaps: badc swaps the bytes of each register, cdab reverses the order of the
// registers (all four of a 64-bit value, as pymodbus does: not the two halves), dcba both. The
// enumerators' values say so: bit 0 byte swap, bit 1 register reversal.
//
// Integers are constant expressions in C++17. Floats are IEEE 754 binary32/binary64 reinterpreted
// bit for bit (a NaN keeps its payload and sign, -0.0 its sign, subnormals their bits): with
// std::bit_cast a constant expression (C++20), through std::memcpy otherwise (C++17; not a
// constant expression, same result). No heap, no exceptions.
//   client:  value_at<float>(response, index, order)  the value at register `index` of a read
//   server:  put_value(image, index, v, order)         into a register image (uint16_t or the
//                                                       big-endian bytes of the PDU)
//   both:    to_registers(v, order) / from_registers<T>(registers, order)  std::array forms
#ifndef MOTIONBUS_MODBUS_VALUES_HPP
#define MOTIONBUS_MODBUS_VALUES_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "motionbus/core/config.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu.hpp"

#if defined(__cpp_lib_bit_cast) && __cpp_lib_bit_cast >= 201806L
#include <bit>
/// 1 when float values convert in constant expressions (std::bit_cast, C++20).
#define MOTIONBUS_CONSTEXPR_FLOAT_VALUES 1
#else
#define MOTIONBUS_CONSTEXPR_FLOAT_VALUES 0
#endif

namespace motionbus {
namespace modbus {

/// How a 32- or 64-bit value lies in registers (table above): A is its most significant byte.
enum class word_order : std::uint8_t { abcd = 0, badc = 1, cdab = 2, dcba = 3 };

namespace detail {

static_assert(std::numeric_limits<float>::is_iec559 && sizeof(float) == 4U,
              "motionbus values: float must be IEEE 754 binary32");
static_assert(std::numeric_limits<double>::is_iec559 && sizeof(double) == 8U,
              "motionbus values: double must be IEEE 754 binary64");

// The unsigned type of a value's bits; void for a type this header does not convert.
template <class T>
struct value_bits {
  using type = void;
};
template <>
struct value_bits<std::uint32_t> {
  using type = std::uint32_t;
};
template <>
struct value_bits<std::int32_t> {
  using type = std::uint32_t;
};
template <>
struct value_bits<float> {
  using type = std::uint32_t;
};
template <>
struct value_bits<std::uint64_t> {
  using type = std::uint64_t;
};
template <>
struct value_bits<std::int64_t> {
  using type = std::uint64_t;
};
template <>
struct value_bits<double> {
  using type = std::uint64_t;
};
template <class T>
using value_bits_t = typename value_bits<T>::type;

template <class T>
struct checked_value {
  static_assert(!std::is_void<value_bits_t<T>>::value,
                "motionbus values: T must be std::uint32_t, std::int32_t, float, std::uint64_t, "
                "std::int64_t or double");
  using bits = value_bits_t<T>;
};

template <class To, class From>
#if MOTIONBUS_CONSTEXPR_FLOAT_VALUES
constexpr
#endif
    To
    bit_copy(const From& from) noexcept {
#if MOTIONBUS_CONSTEXPR_FLOAT_VALUES
  return std::bit_cast<To>(from);
#else
  To to{};
  std::memcpy(&to, &from, sizeof(To));
  return to;
#endif
}

template <class T>
constexpr value_bits_t<T> to_bits(T v) noexcept {
  using U = typename checked_value<T>::bits;
  if constexpr (std::is_floating_point<T>::value) {
    return bit_copy<U>(v);
  } else {
    return static_cast<U>(v);  // signed: modulo 2^N, two's complement (well defined)
  }
}

template <class T>
constexpr T from_bits(value_bits_t<T> b) noexcept {
  using U = typename checked_value<T>::bits;
  if constexpr (std::is_floating_point<T>::value) {
    return bit_copy<T>(b);
  } else if constexpr (std::is_signed<T>::value) {
    // two's complement without the implementation-defined conversion of C++17
    constexpr auto max = static_cast<U>(std::numeric_limits<T>::max());
    return b <= max ? static_cast<T>(b) : static_cast<T>(-static_cast<T>(~b) - 1);
  } else {
    return b;
  }
}

constexpr std::uint16_t swap16(std::uint16_t w) noexcept {
  return static_cast<std::uint16_t>((w << 8U) | (w >> 8U));
}
constexpr bool swaps_bytes(word_order o) noexcept {
  return (static_cast<unsigned>(o) & 1U) != 0U;
}
constexpr bool swaps_words(word_order o) noexcept {
  return (static_cast<unsigned>(o) & 2U) != 0U;
}
// Register k (0 = lowest address) of N that holds big-endian word i (0 = the most significant)
// and the other way round: the same mapping, it is its own inverse.
constexpr std::size_t word_slot(std::size_t i, std::size_t n, word_order o) noexcept {
  return swaps_words(o) ? n - 1U - i : i;
}
// Big-endian word i of the value's bits, as it lies in a register in order `o`.
template <class U>
constexpr std::uint16_t word_of(U bits, std::size_t i, word_order o) noexcept {
  constexpr std::size_t n = sizeof(U) / 2U;
  const auto w = static_cast<std::uint16_t>(bits >> (16U * (n - 1U - i)));
  return swaps_bytes(o) ? swap16(w) : w;
}
// The value's bits from `reg(k)`, register k of the value.
template <class U, class Reg>
constexpr U bits_from(Reg&& reg, word_order o) noexcept {
  constexpr std::size_t n = sizeof(U) / 2U;
  U bits = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t w = reg(word_slot(i, n, o));
    bits = static_cast<U>((bits << 16U) | (swaps_bytes(o) ? swap16(w) : w));
  }
  return bits;
}

}  // namespace detail

/// Registers a value of type T takes: 2 for 32-bit types, 4 for 64-bit ones.
template <class T>
inline constexpr std::size_t registers_of = sizeof(typename detail::checked_value<T>::bits) / 2U;

/// `v` as registers in order `o` (element 0: the lowest address).
template <class T>
constexpr std::array<std::uint16_t, registers_of<T>> to_registers(T v, word_order o) noexcept {
  const auto bits = detail::to_bits(v);
  std::array<std::uint16_t, registers_of<T>> r{};
  for (std::size_t i = 0; i < registers_of<T>; ++i) {
    r[detail::word_slot(i, registers_of<T>, o)] = detail::word_of(bits, i, o);
  }
  return r;
}

/// The value of type T that registers `r` (element 0: the lowest address) hold in order `o`.
template <class T>
constexpr T from_registers(const std::array<std::uint16_t, registers_of<T>>& r,
                           word_order o) noexcept {
  using U = detail::value_bits_t<T>;
  return detail::from_bits<T>(detail::bits_from<U>([&](std::size_t k) { return r[k]; }, o));
}

/// The value of type T at registers [index, index + registers_of<T>) of `regs`, in order `o`.
/// errc::out_of_range when they are not all in `regs`.
template <class T>
constexpr result<T> value_at(span<const std::uint16_t> regs, std::size_t index,
                             word_order o) noexcept {
  using U = detail::value_bits_t<T>;
  if (index > regs.size() || regs.size() - index < registers_of<T>) {
    return errc::out_of_range;
  }
  return detail::from_bits<T>(
      detail::bits_from<U>([&](std::size_t k) { return regs[index + k]; }, o));
}

/// The same from big-endian register bytes (a read response's data, a device's FC10 write
/// data): register i is bytes 2i, 2i+1.
template <class T>
constexpr result<T> value_at(byte_view be_registers, std::size_t index, word_order o) noexcept {
  using U = detail::value_bits_t<T>;
  const std::size_t count = be_registers.size() / 2U;
  if (index > count || count - index < registers_of<T>) {
    return errc::out_of_range;
  }
  return detail::from_bits<T>(
      detail::bits_from<U>([&](std::size_t k) { return register_at(be_registers, index + k); }, o));
}

/// Client: the value of type T at register `index` (0: the first register read) of a checked
/// read response (FC03, FC04, FC17). errc::out_of_range when its registers are not all in the
/// response (an exception response holds none).
template <class T>
constexpr result<T> value_at(const response& r, std::size_t index, word_order o) noexcept {
  return value_at<T>(r.data, index, o);
}

/// Server: writes `v` in order `o` to registers [index, index + registers_of<T>) of `image`;
/// returns the registers written. errc::out_of_range (nothing written) when they do not fit.
template <class T>
constexpr result<std::size_t> put_value(span<std::uint16_t> image, std::size_t index, T v,
                                        word_order o) noexcept {
  if (index > image.size() || image.size() - index < registers_of<T>) {
    return errc::out_of_range;
  }
  const auto regs = to_registers(v, o);
  for (std::size_t k = 0; k < registers_of<T>; ++k) {
    image[index + k] = regs[k];
  }
  return registers_of<T>;
}

/// The same into big-endian register bytes (the response area a read_registers_be accessor
/// fills, a request's FC10 data).
template <class T>
constexpr result<std::size_t> put_value(mutable_byte_view be_image, std::size_t index, T v,
                                        word_order o) noexcept {
  const std::size_t count = be_image.size() / 2U;
  if (index > count || count - index < registers_of<T>) {
    return errc::out_of_range;
  }
  const auto regs = to_registers(v, o);
  for (std::size_t k = 0; k < registers_of<T>; ++k) {
    store_be16(be_image, 2U * (index + k), regs[k]);
  }
  return registers_of<T>;
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_VALUES_HPP
