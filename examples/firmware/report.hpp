// motionbus firmware examples — plain-text report lines on the board's UART (no printf: text,
// decimal and hexadecimal numbers), for the images that tell the host what they decoded.
#ifndef MOTIONBUS_FIRMWARE_REPORT_HPP
#define MOTIONBUS_FIRMWARE_REPORT_HPP

#include <cstddef>
#include <cstdint>

#include "board.hpp"

namespace report {

inline void text(const char* s) {
  std::size_t n = 0;
  while (s[n] != '\0') {
    ++n;
  }
  board::uart_write(reinterpret_cast<const std::uint8_t*>(s), n);
}

/// Writes `v` in decimal at `out` (room for 10 characters); returns the characters written.
inline std::size_t decimal(char* out, std::uint32_t v) {
  char digits[10];
  std::size_t n = 0;
  do {
    digits[n++] = static_cast<char>('0' + v % 10U);
    v /= 10U;
  } while (v != 0U);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = digits[n - 1U - i];
  }
  return n;
}

inline void dec(std::uint32_t v) {
  char out[10];
  const std::size_t n = decimal(out, v);
  board::uart_write(reinterpret_cast<const std::uint8_t*>(out), n);
}

/// `v` as 0x and `digits` hexadecimal digits.
inline void hex(std::uint32_t v, unsigned digits) {
  char out[10] = {'0', 'x'};
  for (unsigned i = 0; i < digits; ++i) {
    const unsigned nibble = (v >> (4U * (digits - 1U - i))) & 0xFU;
    out[2U + i] = static_cast<char>(nibble < 10U ? '0' + nibble : 'A' + nibble - 10U);
  }
  board::uart_write(reinterpret_cast<const std::uint8_t*>(out), 2U + digits);
}

}  // namespace report

#endif  // MOTIONBUS_FIRMWARE_REPORT_HPP
