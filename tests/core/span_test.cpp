// span: the C++17 stand-in for std::span (std::span itself under C++20), and the byte views.
#include "motionbus/core/span.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>

using namespace motionbus;

TEST_CASE("byte views from arrays, std::array and pointer + size") {
  std::array<std::uint8_t, 4> a{{1, 2, 3, 4}};
  const byte_view v = a;
  CHECK(v.size() == 4);
  CHECK(v[3] == 4);
  CHECK(v.first(2).size() == 2);
  CHECK(v.last(1)[0] == 4);
  CHECK(v.subspan(1)[0] == 2);
  CHECK(v.subspan(1, 2).size() == 2);
  mutable_byte_view m = a;
  m[0] = 9;
  CHECK(a[0] == 9);
  const byte_view from_mutable = m;
  CHECK(from_mutable.data() == a.data());
  std::uint8_t raw[3] = {5, 6, 7};
  const byte_view r = raw;
  CHECK(r.size_bytes() == 3);
  CHECK(!r.empty());
  CHECK(byte_view{}.empty());
  std::size_t sum = 0;
  for (std::uint8_t b : r) {
    sum += b;
  }
  CHECK(sum == 18);
}

TEST_CASE("span: first, last and subspan view the same elements, front and back") {
  std::uint32_t words[5] = {10, 20, 30, 40, 50};
  const span<std::uint32_t> s = words;
  CHECK(s.size() == 5);
  CHECK(s.size_bytes() == 5 * sizeof(std::uint32_t));
  CHECK(s.front() == 10);
  CHECK(s.back() == 50);
  CHECK(s.first(2).data() == words);
  CHECK(s.last(2).data() == words + 3);
  CHECK(s.last(2)[1] == 50);
  CHECK(s.subspan(2).size() == 3);
  CHECK(s.subspan(2)[0] == 30);
  CHECK(s.subspan(1, 3).back() == 40);
  CHECK(s.subspan(5).empty());
  s[4] = 55;  // a span of non-const elements writes through
  CHECK(words[4] == 55);
  const span<const std::uint32_t> read_only = s;
  CHECK(read_only.end() - read_only.begin() == 5);
}
