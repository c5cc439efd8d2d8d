// The test tools' hex text of bytes (two lower-case digits a byte, nothing between): the form
// the interop tools print frames in and the scripts compare.
#ifndef MOTIONBUS_TESTS_HEX_HPP
#define MOTIONBUS_TESTS_HEX_HPP

#include <cstddef>
#include <cstdint>
#include <string>

namespace testutil {

inline std::string to_hex(const std::uint8_t* p, std::size_t n) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string s;
  s.reserve(2U * n);
  for (std::size_t i = 0; i < n; ++i) {
    s += digits[p[i] >> 4U];
    s += digits[p[i] & 0x0FU];
  }
  return s;
}

/// Any contiguous bytes with data() and size() (a byte_view, a std::vector<std::uint8_t>).
template <class Bytes>
std::string to_hex(const Bytes& bytes) {
  return to_hex(bytes.data(), bytes.size());
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_HEX_HPP
