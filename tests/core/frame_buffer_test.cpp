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

TEST_CASE("frame_buffer: push_before takes bytes until the owner's decision point") {
  frame_buffer<8> b;
  std::size_t at_least = 99;
  CHECK(!b.push_before(1, at_least));  // want 0: every byte is a decision
  CHECK(b.empty());
  b.want(3);
  CHECK(b.wanted() == 3);
  CHECK(b.push_before(1, at_least));
  CHECK(at_least == 2);
  CHECK(b.push_before(2, at_least));
  CHECK(at_least == 1);
  CHECK(!b.push_before(3, at_least));  // the third byte makes 3 held: a decision
  CHECK(b.size() == 2);
  CHECK(b.completes_want());
  b.put_last(3);
  CHECK(b.size() == 3);
  CHECK(b[2] == 3);
  b.drop(1);  // the bytes wanted count from the new front: 2 held, 3 wanted
  CHECK(b.wanted() == 3);
  CHECK(b.completes_want());
  CHECK(!b.push_before(4, at_least));  // 3 held with it: a decision
  b.want(5);
  CHECK(!b.completes_want());
  CHECK(b.push_before(4, at_least));
  CHECK(at_least == 2);
  CHECK(b.size() == 3);
}

TEST_CASE("frame_buffer: push_before stops at the capacity, a push makes room") {
  frame_buffer<4> b;
  b.want(4);
  std::size_t at_least = 0;
  CHECK(b.push_before(1, at_least));
  CHECK(b.push_before(2, at_least));
  CHECK(b.push_before(3, at_least));
  b.drop(2);  // two held at the end of the storage
  b.want(4);  // 4 wanted from index 2: the decision point is capped at the capacity
  CHECK(!b.push_before(4, at_least));  // index 3 is free, but the end would reach capacity
  CHECK(!b.completes_want());          // not because 4 are held: room is made out of line
  CHECK(b.push(4));
  CHECK(b.push(5));  // moves the held bytes to the front, then appends
  CHECK(b.size() == 3);
  CHECK(b[0] == 3);
  CHECK(b[2] == 5);
  CHECK(!b.push_before(6, at_least));  // with it 4 would be held: a decision
  CHECK(b.completes_want());
}

TEST_CASE("frame_buffer: a byte completing wanted() at the capacity is not put_last's") {
  // 4 wanted from index 2 of 4: the end reaches the capacity with 2 held; the byte that would
  // make 3 held still leaves one to want, and the one after that completes wanted() where there
  // is no room at the end: room must be made first (the fuzz targets found this case).
  frame_buffer<4> b;
  std::size_t at_least = 0;
  b.want(4);
  CHECK(b.push_before(1, at_least));
  CHECK(b.push_before(2, at_least));
  b.drop(1);
  b.want(3);                           // 1 held, at index 1: stop at index 4, the capacity
  CHECK(b.push_before(3, at_least));   // index 2
  CHECK(!b.push_before(4, at_least));  // index 3 would reach the capacity: refused
  CHECK(b.completes_want());           // with it, 3 held, and index 3 is free
  CHECK(b.push(4));                    // the slow path stores it
  b.want(4);                           // 3 held from index 1: the next byte completes 4
  CHECK(!b.push_before(5, at_least));
  CHECK(!b.completes_want());  // but the end is at the capacity: no put_last
  CHECK(b.push(5));            // push makes room (moves the held bytes to the front)
  CHECK(b.size() == 4);
  CHECK(b[0] == 2);
  CHECK(b[3] == 5);
}

TEST_CASE("frame_buffer: start_with begins a frame at the front, drop(n, want) ends it") {
  frame_buffer<11> b;
  std::size_t at_least = 0;
  b.start_with(0x1A, 11);  // an empty buffer: the first byte at index 0, 11 wanted
  CHECK(b.size() == 1);
  CHECK(b[0] == 0x1A);
  CHECK(b.wanted() == 11);
  for (std::uint8_t i = 1; i < 10; ++i) {
    CHECK(b.push_before(i, at_least));
  }
  CHECK(at_least == 1);                 // one more before the decision
  CHECK(!b.push_before(10, at_least));  // the 11th byte is the decision
  CHECK(b.completes_want());
  b.put_last(10);
  CHECK(b.size() == 11);
  b.drop(11, 0);  // the whole frame: empty again, and back to its front
  CHECK(b.empty());
  CHECK(b.wanted() == 0);
  CHECK(!b.push_before(0x02, at_least));  // wanted() 0: every byte is a decision
  b.start_with(0x02, 6);
  CHECK(b.push(0x40));
  b.drop(1, 3);  // a rejected frame: rescan from its second byte, 3 wanted from there
  CHECK(b.size() == 1);
  CHECK(b[0] == 0x40);
  CHECK(b.wanted() == 3);
  CHECK(b.push_before(0x41, at_least));
  CHECK(at_least == 1);
  CHECK(!b.push_before(0x42, at_least));
}
