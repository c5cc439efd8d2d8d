// motionbus — Modbus RTU timing as plain computations the user's timers apply
// (Modbus over Serial Line V1.02 §2.5.1.1; docs/modbus.md §4).
//
// A character is 11 bits (start, 8 data, parity, stop — or 2 stop bits without parity; the
// spec asks for 11 bits in every case). Inside a frame the line must not stay silent for more
// than 1.5 characters (t1.5); frames are separated by at least 3.5 characters (t3.5). Above
// 19200 baud fixed values are recommended: 750 us and 1750 us.
#ifndef MOTIONBUS_MODBUS_TIMING_HPP
#define MOTIONBUS_MODBUS_TIMING_HPP

#include <cstdint>

namespace motionbus {
namespace modbus {

enum class parity : std::uint8_t { none = 0, even = 1, odd = 2 };

/// Bits per character on the line: start + 8 data + parity (if any) + stop bits.
constexpr unsigned bits_per_character(parity p, unsigned stop_bits) noexcept {
  return 1U + 8U + (p == parity::none ? 0U : 1U) + stop_bits;
}

/// Time of `characters_x2 / 2` characters in microseconds, rounded up (characters_x2: 3 for
/// t1.5, 7 for t3.5). A baud rate of 0 gives 0.
constexpr std::uint32_t character_time_us(std::uint32_t baud, parity p, unsigned stop_bits,
                                          unsigned characters_x2 = 2) noexcept {
  if (baud == 0U) {
    return 0U;
  }
  const std::uint64_t bit_us_x2 =
      std::uint64_t{characters_x2} * bits_per_character(p, stop_bits) * 1000000U;
  return static_cast<std::uint32_t>((bit_us_x2 + std::uint64_t{2} * baud - 1U) /
                                    (std::uint64_t{2} * baud));
}

/// t1.5: the longest silence allowed inside a frame (750 us above 19200 baud).
constexpr std::uint32_t t15_us(std::uint32_t baud, parity p = parity::even,
                               unsigned stop_bits = 1) noexcept {
  return baud > 19200U ? 750U : character_time_us(baud, p, stop_bits, 3);
}

/// t3.5: the shortest silence between frames (1750 us above 19200 baud).
constexpr std::uint32_t t35_us(std::uint32_t baud, parity p = parity::even,
                               unsigned stop_bits = 1) noexcept {
  return baud > 19200U ? 1750U : character_time_us(baud, p, stop_bits, 7);
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_TIMING_HPP
