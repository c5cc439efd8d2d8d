// The bounded frame buffer under the stream objects: bytes appended at the end, dropped from
// the front by moving an index, moved to the front only when the end reaches the capacity.
#include "motionbus/core/frame_buffer.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using namespace motionbus;

TEST_CASE("frame_buffer: push, drop and append keep the bytes held contiguous, in order") {
  frame_buffer<4> b;
  CHECK(b.empty());
  CHECK(b.push(1));
  CHECK(b.push(2));
  CHECK(b.push(3));
  CHECK(b.push(4));
  CHECK(b.size() == 4);
  CHECK(!b.push(5));  // full, nothing to move: refused, nothing changed
  CHECK(b.size() == 4);
  b.drop(2);  // an index moves; the bytes stay where they are
  CHECK(b.size() == 2);
  CHECK(b[0] == 3);
  CHECK(b[1] == 4);
  CHECK(b.push(5));  // at the capacity: the two held bytes move to the front first
  CHECK(b.size() == 3);
  CHECK(b.first(3)[0] == 3);
  CHECK(b.first(3)[2] == 5);
  b.drop(3);  // everything dropped: back to the front
  CHECK(b.empty());
  const std::uint8_t in[6] = {10, 11, 12, 13, 14, 15};
  CHECK(b.append(byte_view(in, 6), 2) == 2);      // at most n
  CHECK(b.append(byte_view(in + 2, 1), 3) == 1);  // at most what `in` holds
  b.drop(1);
  CHECK(b.append(byte_view(in + 3, 3), 3) == 2);  // what fits, after moving to the front
  CHECK(b.size() == 4);
  const byte_view v = b.view();
  CHECK(v[0] == 11);
  CHECK(v[1] == 12);
  CHECK(v[2] == 13);
  CHECK(v[3] == 14);
  CHECK(b.append(byte_view(in, 6), 6) == 0);  // full
  b.clear();
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: a default one is all zeros (a static one is in .bss)") {
  static constexpr frame_buffer<256> zero{};
  static_assert(zero.size() == 0 && zero.empty(), "empty when built");
  frame_buffer<256> b;
  CHECK(b.size() == 0);
}
