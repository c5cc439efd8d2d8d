// Independent reference CRC for the tests: polynomial long division of the augmented message,
// written from the Williams model definition and sharing no code with the engine under test.
//   CRC = reflect_if(refout, (M(x) * x^W + Init * x^len(M)) mod P(x)) XOR XorOut
// where the message bits are taken in the order the CRC consumes them (each byte reflected when
// refin is set).
#ifndef MOTIONBUS_TESTS_REFERENCE_CRC_HPP
#define MOTIONBUS_TESTS_REFERENCE_CRC_HPP

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ref {

struct model {
  unsigned width;
  std::uint32_t poly;  // without the x^width term
  std::uint32_t init;
  bool refin;
  bool refout;
  std::uint32_t xorout;
};

/// CRC of a list of bits, given in the order the CRC consumes them.
inline std::uint32_t crc_of_bits(const model& m, const std::vector<int>& bits) {
  const std::size_t len = bits.size();
  std::vector<int> aug(len + m.width, 0);
  for (std::size_t i = 0; i < len; ++i) {
    aug.at(i) = bits.at(i);
  }
  for (unsigned i = 0; i < m.width; ++i) {  // Init * x^len: the top W coefficients
    aug.at(i) ^= static_cast<int>((m.init >> (m.width - 1U - i)) & 1U);
  }
  // Divisor coefficients, highest first: x^W (always 1) then poly bits W-1..0.
  std::vector<int> divisor(m.width + 1U, 0);
  divisor.at(0) = 1;
  for (unsigned j = 1; j <= m.width; ++j) {
    divisor.at(j) = static_cast<int>((m.poly >> (m.width - j)) & 1U);
  }
  for (std::size_t i = 0; i < len; ++i) {
    if (aug.at(i) != 0) {
      for (unsigned j = 0; j <= m.width; ++j) {
        aug.at(i + j) ^= divisor.at(j);
      }
    }
  }
  std::uint32_t rem = 0;
  for (unsigned i = 0; i < m.width; ++i) {
    rem = (rem << 1U) | static_cast<std::uint32_t>(aug.at(len + i));
  }
  if (m.refout) {
    std::uint32_t r = 0;
    for (unsigned i = 0; i < m.width; ++i) {
      r |= ((rem >> i) & 1U) << (m.width - 1U - i);
    }
    rem = r;
  }
  return rem ^ m.xorout;
}

/// CRC of bytes: each byte contributes its bits LSB first when refin, else MSB first.
inline std::uint32_t crc_of_bytes(const model& m, const std::vector<std::uint8_t>& bytes) {
  std::vector<int> bits;
  for (std::uint8_t b : bytes) {
    for (unsigned i = 0; i < 8U; ++i) {
      const unsigned shift = m.refin ? i : 7U - i;
      bits.push_back((b >> shift) & 1U);
    }
  }
  return crc_of_bits(m, bits);
}

}  // namespace ref

#endif
