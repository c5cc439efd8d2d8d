// Bit strings for the BiSS tests: "0101…", first bit first, as the notes describe the wire.
#ifndef MOTIONBUS_TESTS_BIT_STRINGS_HPP
#define MOTIONBUS_TESTS_BIT_STRINGS_HPP

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace testutil {

/// The low `n` bits of `v`, most significant first.
inline std::string bits_of(std::uint64_t v, unsigned n) {
  std::string s;
  for (unsigned i = 0; i < n; ++i) {
    s.push_back(((v >> (n - 1U - i)) & 1U) != 0U ? '1' : '0');
  }
  return s;
}

/// The first `n` bits of 32-bit words, each word's most significant bit first (the order
/// biss::encode_frame writes them in).
inline std::string bits_of_words(const std::uint32_t* words, std::size_t n) {
  std::string s;
  for (std::size_t k = 0; k < n; ++k) {
    s.push_back(((words[k / 32U] >> (31U - k % 32U)) & 1U) != 0U ? '1' : '0');
  }
  return s;
}

/// A bit string as 0/1 integers (the reference CRC's input).
inline std::vector<int> as_ints(const std::string& s) {
  std::vector<int> v;
  for (char c : s) {
    v.push_back(c == '1' ? 1 : 0);
  }
  return v;
}

}  // namespace testutil

#endif
