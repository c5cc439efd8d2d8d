// Helpers shared by the doctest suites: byte vectors and views of them, an encoder's output as
// bytes, text as bytes, byte vectors joined, the T-format CRC (the XOR of the fields) appended.
#ifndef MOTIONBUS_TESTS_BYTES_HPP
#define MOTIONBUS_TESTS_BYTES_HPP

#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <vector>

#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace testutil {

using bytes = std::vector<std::uint8_t>;

inline motionbus::byte_view view(const bytes& b) {
  return motionbus::byte_view(b.data(), b.size());
}

/// What an encoder wrote into `out` (it must have succeeded).
inline bytes output(const motionbus::result<std::size_t>& n, const std::uint8_t* out) {
  REQUIRE(n.ok());
  return bytes(out, out + n.value());
}

/// The characters of `s`, without its terminating NUL.
inline motionbus::byte_view text(const char* s) {
  return motionbus::byte_view(reinterpret_cast<const std::uint8_t*>(s), std::strlen(s));
}

/// The XOR of the bytes: the T-format CRC (G(X) = X^8 + 1) of the fields before it.
inline std::uint8_t xor_of(const bytes& v) {
  std::uint8_t x = 0;
  for (const std::uint8_t b : v) {
    x = static_cast<std::uint8_t>(x ^ b);
  }
  return x;
}

/// The parts one after the other.
inline bytes cat(std::initializer_list<bytes> parts) {
  bytes out;
  for (const bytes& p : parts) {
    out.insert(out.end(), p.begin(), p.end());
  }
  return out;
}

/// `v` with its T-format CRC appended.
inline bytes with_crc(bytes v) {
  v.push_back(xor_of(v));
  return v;
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_BYTES_HPP
