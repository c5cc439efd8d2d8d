// motionbus — multi-byte loads from byte views, usable in constant expressions.
//
// `load_be16`, `load_le16`, `store_be16` and `store_le16` read and write the 16-bit fields of
// the byte protocols. `load_le<N>` and `load_be<N>` assemble N (1..8) bytes starting at `at` into
// an integer. In a constant expression they assemble byte by byte; at run time, on a little-endian
// GCC or clang target, they do one unaligned load (plus a byte swap for big-endian order), which
// some compilers do not derive from the byte-by-byte form on their own. The caller guarantees that
// `at + N <= in.size()`; these are building blocks for decoders that have checked lengths.
#ifndef MOTIONBUS_CORE_BYTES_HPP
#define MOTIONBUS_CORE_BYTES_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/config.hpp"
#include "motionbus/core/span.hpp"

#if (defined(__GNUC__) || defined(__clang__)) && defined(__BYTE_ORDER__) && \
    defined(__ORDER_LITTLE_ENDIAN__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define MOTIONBUS_DIRECT_LOADS 1
#else
#define MOTIONBUS_DIRECT_LOADS 0
#endif

namespace motionbus {

/// N bytes from `in[at]`, the first byte least significant.
template <unsigned N>
constexpr std::uint64_t load_le(byte_view in, std::size_t at) noexcept {
  static_assert(N >= 1U && N <= 8U, "load_le: 1 to 8 bytes");
#if MOTIONBUS_DIRECT_LOADS
  // coverage-branch: false in constant evaluation only, which gcov does not count
  if (!__builtin_is_constant_evaluated()) {
    std::uint64_t v = 0;
    __builtin_memcpy(&v, in.data() + at, N);
    return v;
  }
#endif
  // coverage-begin: runs in constant evaluation (not counted) and on big-endian or non-GCC
  // targets; the s390x configuration of the test command runs the suites through it
  std::uint64_t v = 0;
  for (unsigned k = 0; k < N; ++k) {
    v |= static_cast<std::uint64_t>(in[at + k]) << (8U * k);
  }
  return v;
  // coverage-end
}

/// N bytes from `in[at]`, the first byte most significant.
template <unsigned N>
constexpr std::uint64_t load_be(byte_view in, std::size_t at) noexcept {
  static_assert(N >= 1U && N <= 8U, "load_be: 1 to 8 bytes");
#if MOTIONBUS_DIRECT_LOADS
  // coverage-branch: false in constant evaluation only, which gcov does not count
  if (!__builtin_is_constant_evaluated()) {
    std::uint64_t v = 0;
    __builtin_memcpy(&v, in.data() + at, N);
    return __builtin_bswap64(v) >> (64U - 8U * N);
  }
#endif
  // coverage-begin: runs in constant evaluation (not counted) and on big-endian or non-GCC
  // targets; the s390x configuration of the test command runs the suites through it
  std::uint64_t v = 0;
  for (unsigned k = 0; k < N; ++k) {
    v = (v << 8U) | in[at + k];
  }
  return v;
  // coverage-end
}

/// The 16-bit big-endian value at `in[at]` (a Modbus register, a length field).
// inline: the Modbus server reads every register through it, and -Os calls it.
MOTIONBUS_INLINE constexpr std::uint16_t load_be16(byte_view in, std::size_t at) noexcept {
  return static_cast<std::uint16_t>((in[at] << 8U) | in[at + 1U]);
}
/// The 16-bit little-endian value at `in[at]` (a Modbus CRC as sent).
constexpr std::uint16_t load_le16(byte_view in, std::size_t at) noexcept {
  return static_cast<std::uint16_t>(in[at] | (in[at + 1U] << 8U));
}
/// Writes `v` big-endian at `out[at]` (at + 2 <= out.size(), checked by the caller).
constexpr void store_be16(mutable_byte_view out, std::size_t at, std::uint16_t v) noexcept {
  out[at] = static_cast<std::uint8_t>(v >> 8U);
  out[at + 1U] = static_cast<std::uint8_t>(v & 0xFFU);
}
/// Writes `v` little-endian at `out[at]` (at + 2 <= out.size(), checked by the caller).
constexpr void store_le16(mutable_byte_view out, std::size_t at, std::uint16_t v) noexcept {
  out[at] = static_cast<std::uint8_t>(v & 0xFFU);
  out[at + 1U] = static_cast<std::uint8_t>(v >> 8U);
}

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_BYTES_HPP
