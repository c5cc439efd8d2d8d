// The bounded frame buffer under the stream objects: bytes appended at the end, dropped from
// the front by moving an index, moved to the front only when the end reaches the capacity.
// Each case states one behaviour; a case that needs an earlier state builds it unchecked.
#include "motionbus/core/frame_buffer.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using namespace motionbus;

namespace {

// Bytes 1, 2, ... n pushed (each one taken) into an empty buffer.
template <std::size_t N>
void push_count(frame_buffer<N>& b, std::uint8_t n) {
  for (std::uint8_t i = 1; i <= n; ++i) {
    CHECK(b.push(i));
  }
}

// Bytes 1, 2, ... n, each one taken by push_before(), into an empty buffer that wants `want`.
template <std::size_t N>
void push_before_count(frame_buffer<N>& b, std::size_t want, std::uint8_t n) {
  b.want(want);
  for (std::uint8_t i = 1; i <= n; ++i) {
    CHECK(b.push_before(i));
  }
}

const std::uint8_t in[6] = {10, 11, 12, 13, 14, 15};

}  // namespace

TEST_CASE("frame_buffer: push appends until full; a full one refuses a byte and is unchanged") {
  frame_buffer<4> b;
  CHECK(b.empty());
  CHECK(b.push(1));
  CHECK(b.push(2));
  CHECK(b.push(3));
  CHECK(b.push(4));
  CHECK(b.size() == 4);
  CHECK(!b.push(5));  // full, nothing to move: refused, nothing changed
  CHECK(b.size() == 4);
}

TEST_CASE("frame_buffer: drop(n) moves the front; the bytes held stay in order") {
  frame_buffer<4> b;
  push_count(b, 4);
  b.drop(2);  // an index moves; the bytes stay where they are
  CHECK(b.size() == 2);
  CHECK(b[0] == 3);
  CHECK(b[1] == 4);
}

TEST_CASE("frame_buffer: a push at the capacity moves the bytes held to the front first") {
  frame_buffer<4> b;
  push_count(b, 4);
  b.drop(2);
  CHECK(b.push(5));  // at the capacity: the two held bytes move to the front first
  CHECK(b.size() == 3);
  CHECK(b.first(3)[0] == 3);
  CHECK(b.first(3)[2] == 5);
}

TEST_CASE("frame_buffer: dropping every byte held empties it") {
  frame_buffer<4> b;
  push_count(b, 4);
  b.drop(2);
  b.push(5);
  b.drop(3);  // everything dropped: back to the front
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: append takes at most n and at most what the input holds") {
  frame_buffer<4> b;
  CHECK(b.append(byte_view(in, 6), 2) == 2);      // at most n
  CHECK(b.append(byte_view(in + 2, 1), 3) == 1);  // at most what `in` holds
  CHECK(b.size() == 3);
}

TEST_CASE("frame_buffer: append moves the bytes held to the front and takes what fits") {
  frame_buffer<4> b;
  b.append(byte_view(in, 6), 3);
  b.drop(1);                                      // 11, 12 held from index 1
  CHECK(b.append(byte_view(in + 3, 3), 3) == 2);  // what fits, after moving to the front
  CHECK(b.size() == 4);
  const byte_view v = b.view();
  CHECK(v[0] == 11);
  CHECK(v[1] == 12);
  CHECK(v[2] == 13);
  CHECK(v[3] == 14);
}

TEST_CASE("frame_buffer: append to a full one takes nothing") {
  frame_buffer<4> b;
  push_count(b, 4);
  CHECK(b.append(byte_view(in, 6), 6) == 0);  // full
  CHECK(b.size() == 4);
}

TEST_CASE("frame_buffer: clear() empties it") {
  frame_buffer<4> b;
  push_count(b, 3);
  b.clear();
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: a default one is all zeros (a static one is in .bss)") {
  static constexpr frame_buffer<256> zero{};
  static_assert(zero.size() == 0 && zero.empty(), "empty when built");
  frame_buffer<256> b;
  CHECK(b.size() == 0);
}

TEST_CASE("frame_buffer: with nothing wanted, push_before refuses every byte") {
  frame_buffer<8> b;
  CHECK(!b.push_before(1));  // want 0: every byte is a decision
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: push_before takes bytes until the last one wanted, which it refuses") {
  frame_buffer<8> b;
  b.want(3);
  CHECK(b.wanted() == 3);
  CHECK(b.push_before(1));
  CHECK(b.wanted() - b.size() == 2U);
  CHECK(b.push_before(2));
  CHECK(b.wanted() - b.size() == 1U);
  CHECK(!b.push_before(3));  // the third byte makes 3 held: a decision
  CHECK(b.size() == 2);
  CHECK(b.size() + 1U == b.wanted());  // refused for the last byte wanted only
}

TEST_CASE("frame_buffer: put_last stores the byte push_before refused") {
  frame_buffer<8> b;
  push_before_count(b, 3, 2);
  b.put_last(3);
  CHECK(b.size() == 3);
  CHECK(b[2] == 3);
}

TEST_CASE("frame_buffer: after drop(n) the bytes wanted count from the new front") {
  frame_buffer<8> b;
  push_before_count(b, 3, 2);
  b.put_last(3);
  b.drop(1);  // the bytes wanted count from the new front: 2 held, 3 wanted
  CHECK(b.wanted() == 3);
  CHECK(!b.push_before(4));  // 3 held with it: a decision
  b.want(5);
  CHECK(b.push_before(4));
  CHECK(b.wanted() - b.size() == 2U);
  CHECK(b.size() == 3);
}

TEST_CASE("frame_buffer: want() moves the bytes held to the front when the count would not fit") {
  frame_buffer<4> b;
  push_before_count(b, 4, 3);
  b.drop(2);  // one held, at index 2 of 4
  b.want(4);  // 4 wanted from index 2 would not fit: the byte held moves to the front
  CHECK(b.size() == 1);
  CHECK(b[0] == 3);
}

TEST_CASE("frame_buffer: after want() made room, only the last byte wanted is refused") {
  frame_buffer<4> b;
  push_before_count(b, 4, 3);
  b.drop(2);
  b.want(4);
  CHECK(b.push_before(4));
  CHECK(b.wanted() - b.size() == 2U);
  CHECK(b.push_before(5));
  CHECK(!b.push_before(6));  // with it 4 would be held: a decision
  CHECK(b.size() + 1U == b.wanted());
  b.put_last(6);  // room for it: the frame fits from the front
  CHECK(b.size() == 4);
  CHECK(b[0] == 3);
  CHECK(b[3] == 6);
}

TEST_CASE("frame_buffer: drop(n) keeps wanted() from the new front, moving what is held") {
  // 3 wanted from index 1 of 4 fits; after a drop of 1, 3 wanted from index 2 does not: the
  // bytes held move to the front (the fuzz targets once found a refused byte with no room).
  frame_buffer<4> b;
  push_before_count(b, 4, 3);
  b.drop(1, 3);              // 2 held from index 1: 3 wanted
  CHECK(!b.push_before(4));  // 3 held with it: a decision
  b.put_last(4);
  b.drop(1);  // 2 held from index 2, still 3 wanted: moved to the front
  CHECK(b.size() == 2);
  CHECK(b[0] == 3);
  CHECK(b[1] == 4);
  CHECK(!b.push_before(5));
  b.put_last(5);
  CHECK(b.size() == 3);
  CHECK(b[2] == 5);
}

TEST_CASE("frame_buffer: a push beyond wanted() still fits, until the buffer is full") {
  frame_buffer<4> b;
  push_before_count(b, 4, 3);
  b.drop(1, 3);
  b.put_last(4);
  b.drop(1);
  b.put_last(5);     // 3, 4, 5 held from the front, 3 wanted
  CHECK(b.push(6));  // a push beyond wanted() still fits
  CHECK(b.size() == 4);
  CHECK(!b.push(7));  // full
}

TEST_CASE("frame_buffer: start_with begins a frame at the front with its count wanted") {
  frame_buffer<11> b;
  b.start_with(0x1A, 11);  // an empty buffer: the first byte at index 0, 11 wanted
  CHECK(b.size() == 1);
  CHECK(b[0] == 0x1A);
  CHECK(b.wanted() == 11);
  for (std::uint8_t i = 1; i < 10; ++i) {
    CHECK(b.push_before(i));
  }
  CHECK(b.wanted() - b.size() == 1U);  // one more: the decision
  CHECK(!b.push_before(10));           // the 11th byte is the decision
  b.put_last(10);
  CHECK(b.size() == 11);
}

TEST_CASE("frame_buffer: drop(n, 0) of a whole frame empties it and wants nothing") {
  frame_buffer<11> b;
  b.start_with(0x1A, 11);
  for (std::uint8_t i = 1; i < 10; ++i) {
    b.push_before(i);
  }
  b.put_last(10);
  b.drop(11, 0);  // the whole frame: empty again, and back to its front
  CHECK(b.empty());
  CHECK(b.wanted() == 0);
  CHECK(!b.push_before(0x02));  // wanted() 0: every byte is a decision
}

TEST_CASE("frame_buffer: drop(1, want) of a rejected frame rescans from its second byte") {
  frame_buffer<11> b;
  b.start_with(0x02, 6);
  CHECK(b.push(0x40));
  b.drop(1, 3);  // a rejected frame: rescan from its second byte, 3 wanted from there
  CHECK(b.size() == 1);
  CHECK(b[0] == 0x40);
  CHECK(b.wanted() == 3);
  CHECK(b.push_before(0x41));
  CHECK(b.wanted() - b.size() == 1U);
  CHECK(!b.push_before(0x42));
}

TEST_CASE("frame_buffer: reserve(n) moves the bytes held only when n would not fit") {
  frame_buffer<8> b;
  push_before_count(b, 8, 7);
  b.drop(6, 1);  // one held (7), at index 6, one wanted: it fits where it is
  const std::uint8_t* const at_6 = b.data();
  b.reserve(2);  // two from index 6 fit: nothing moves
  CHECK(b.data() == at_6);
  CHECK(b[0] == 7);
  b.reserve(4);  // four from index 6 would not: the byte held moves to the front
  CHECK(b.data() != at_6);
  CHECK(b.size() == 1);
  CHECK(b.data()[0] == 7);
}

TEST_CASE("frame_buffer: want_within(n) after reserve(n) wants n from the front") {
  frame_buffer<8> b;
  push_before_count(b, 8, 7);
  b.drop(6, 1);
  b.reserve(4);
  b.want_within(4);  // room was made: 4 wanted from the front, no check
  CHECK(b.wanted() == 4);
  CHECK(b.push_before(8));
  CHECK(b.push_before(9));
  CHECK(!b.push_before(10));  // the fourth: a decision
}

TEST_CASE("frame_buffer: the last byte in two steps, place_last then count_last") {
  frame_buffer<8> b;
  push_before_count(b, 4, 3);
  b.place_last(10);  // stored, not yet counted
  CHECK(b.size() == 3);
  CHECK(b.data()[3] == 10);
  b.count_last();
  CHECK(b.size() == 4);
  CHECK(b[3] == 10);
}

TEST_CASE("frame_buffer: restart(n) drops everything and wants n from the front") {
  frame_buffer<8> b;
  push_before_count(b, 8, 7);
  b.drop(6, 1);
  b.reserve(4);  // 7 moved to the front
  b.restart(2);  // everything dropped: 2 wanted from the front, the bytes still readable
  CHECK(b.empty());
  CHECK(b.wanted() == 2);
  CHECK(b.data()[0] == 7);
  CHECK(b.push_before(0x11));
  CHECK(!b.push_before(0x12));
  b.restart(0);
  CHECK(!b.push_before(0x13));  // nothing wanted: every byte is a decision
}
