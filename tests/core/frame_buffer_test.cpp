// The bounded frame buffer under the stream objects: bytes appended at the end, dropped from
// the front by moving an index, moved to the front only when the end reaches the capacity or
// the bytes wanted would not fit. Each case states one behaviour, in its name; the state it
// starts from is built by the helpers below, whose own behaviour other cases check.
#include "motionbus/core/frame_buffer.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using namespace motionbus;

namespace {

// Bytes 1, 2, ... n pushed into an empty buffer.
template <std::size_t N>
void push_count(frame_buffer<N>& b, std::uint8_t n) {
  for (std::uint8_t i = 1; i <= n; ++i) {
    b.push(i);
  }
}

// `keep` bytes held from index `at` (bytes at+1 .. at+keep): at + keep pushed, `at` dropped.
template <std::size_t N>
void held_at(frame_buffer<N>& b, std::uint8_t at, std::uint8_t keep) {
  push_count(b, static_cast<std::uint8_t>(at + keep));
  b.drop(at);
}

// fill_and_decide over `in`, which ends before wanted() bytes are held: the bytes it takes.
template <std::size_t N>
std::size_t fill(frame_buffer<N>& b, byte_view in) {
  std::size_t used = 0;
  const bool settled = b.fill_and_decide(in, used, [] { return true; });
  CHECK(!settled);
  return used;
}

const std::uint8_t in[6] = {10, 11, 12, 13, 14, 15};

}  // namespace

TEST_CASE("frame_buffer: a default one is all zeros and empty (a static one is in .bss)") {
  static constexpr frame_buffer<256> zero{};
  static_assert(zero.size() == 0 && zero.empty() && zero.wanted() == 0, "empty when built");
  frame_buffer<256> b;
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: push appends the byte at the end") {
  frame_buffer<4> b;
  CHECK(b.push(1));
  CHECK(b.push(2));
  CHECK(b.size() == 2);
  CHECK(b[1] == 2);
}

TEST_CASE("frame_buffer: a full buffer refuses a push and is unchanged") {
  frame_buffer<4> b;
  push_count(b, 4);
  CHECK(!b.push(5));
  CHECK(b.size() == 4);
  CHECK(b[3] == 4);
}

TEST_CASE("frame_buffer: drop(n) removes the first n bytes, the rest stay in order") {
  frame_buffer<4> b;
  push_count(b, 4);
  b.drop(2);
  CHECK(b.size() == 2);
  CHECK(b[0] == 3);
  CHECK(b[1] == 4);
}

TEST_CASE("frame_buffer: a push at the capacity moves the bytes held to the front first") {
  frame_buffer<4> b;
  held_at(b, 2, 2);  // 3, 4 held at indices 2, 3: the end is at the capacity
  CHECK(b.push(5));
  CHECK(b.size() == 3);
  CHECK(b.view().data() == &b.view()[0]);
  CHECK(b[0] == 3);
  CHECK(b[2] == 5);
}

TEST_CASE("frame_buffer: dropping every byte held empties it") {
  frame_buffer<4> b;
  push_count(b, 3);
  b.drop(3);
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: view() shows the bytes held, from the front") {
  frame_buffer<4> b;
  held_at(b, 1, 2);
  const byte_view v = b.view();
  CHECK(v.size() == 2);
  CHECK(v[0] == 2);
  CHECK(v[1] == 3);
}

TEST_CASE("frame_buffer: with nothing wanted, push_before refuses every byte") {
  frame_buffer<8> b;
  CHECK(!b.push_before(1));
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: push_before takes the bytes before the last one wanted") {
  frame_buffer<8> b;
  b.want(3);
  CHECK(b.wanted() == 3);
  CHECK(b.push_before(1));
  CHECK(b.push_before(2));
  CHECK(b.size() == 2);
}

TEST_CASE("frame_buffer: push_before refuses the byte that makes wanted() held") {
  frame_buffer<8> b;
  b.want(3);
  b.push_before(1);
  b.push_before(2);
  CHECK(!b.push_before(3));
  CHECK(b.size() == 2);
}

TEST_CASE("frame_buffer: put_last appends the byte push_before refused") {
  frame_buffer<8> b;
  b.want(3);
  b.push_before(1);
  b.push_before(2);
  b.put_last(3);
  CHECK(b.size() == 3);
  CHECK(b[2] == 3);
}

TEST_CASE("frame_buffer: want(n) moves the bytes held to the front when n would not fit") {
  frame_buffer<4> b;
  held_at(b, 2, 1);  // 3 held at index 2: 4 from there would not fit
  b.want(4);
  CHECK(b.size() == 1);
  CHECK(b[0] == 3);
  b.push_before(4);
  b.push_before(5);
  b.put_last(6);  // the last byte wanted fits at the end
  CHECK(b.size() == 4);
  CHECK(b[3] == 6);
}

TEST_CASE("frame_buffer: after want(n) moved the bytes, push_before refuses only the nth") {
  frame_buffer<4> b;
  held_at(b, 2, 1);
  b.want(4);
  CHECK(b.push_before(4));
  CHECK(b.push_before(5));
  CHECK(!b.push_before(6));
}

TEST_CASE("frame_buffer: drop(n) keeps wanted(), counted from the new front") {
  frame_buffer<8> b;
  b.want(3);
  push_count(b, 3);
  b.drop(1);  // 2, 3 held, still 3 wanted
  CHECK(b.wanted() == 3);
  CHECK(!b.push_before(4));  // with it 3 would be held
}

TEST_CASE("frame_buffer: drop(n) moves the bytes held where wanted() would not fit") {
  // 3 wanted from index 1 of 4 fits; from index 2 it does not (a refused byte needs room).
  frame_buffer<4> b;
  b.want(3);
  held_at(b, 1, 2);
  b.drop(1);  // 3 held at index 2, 3 wanted: moved to the front
  CHECK(b.size() == 1);
  CHECK(b[0] == 3);
  b.push_before(4);
  b.put_last(5);
  CHECK(b[2] == 5);
}

TEST_CASE("frame_buffer: drop(n, next) drops n and wants next from the new front") {
  frame_buffer<11> b;
  push_count(b, 2);
  b.drop(1, 3);  // a rejected frame: rescan from its second byte, 3 wanted from there
  CHECK(b.size() == 1);
  CHECK(b[0] == 2);
  CHECK(b.wanted() == 3);
  CHECK(b.push_before(3));
  CHECK(!b.push_before(4));
}

TEST_CASE("frame_buffer: drop(n, 0) of everything held empties it and wants nothing") {
  frame_buffer<11> b;
  b.want(11);
  push_count(b, 11);
  b.drop(11, 0);
  CHECK(b.empty());
  CHECK(b.wanted() == 0);
  CHECK(!b.push_before(1));
}

TEST_CASE("frame_buffer: restart(n) empties it and wants n from the front") {
  frame_buffer<8> b;
  held_at(b, 6, 1);
  b.restart(2);
  CHECK(b.empty());
  CHECK(b.wanted() == 2);
  CHECK(b.push_before(0x11));
  CHECK(!b.push_before(0x12));
}

TEST_CASE("frame_buffer: after restart() the bytes dropped stay readable until the next push") {
  frame_buffer<8> b;
  push_count(b, 3);
  const byte_view frame = b.view();  // a frame handed over
  b.restart(0);
  CHECK(frame[0] == 1);
  CHECK(frame[2] == 3);
}

TEST_CASE("frame_buffer: restart(0) wants nothing: push_before refuses every byte") {
  frame_buffer<8> b;
  b.want(4);
  b.restart(0);
  CHECK(!b.push_before(1));
}

TEST_CASE("frame_buffer: fill_and_decide takes what wanted() still needs, then decides") {
  frame_buffer<8> b;
  b.want(3);
  std::size_t used = 0;
  int decisions = 0;
  const bool settled = b.fill_and_decide(byte_view(in, 6), used, [&] {
    ++decisions;
    return true;
  });
  CHECK(settled);
  CHECK(decisions == 1);
  CHECK(used == 3);
  CHECK(b.size() == 3);
  CHECK(b[2] == 12);
}

TEST_CASE("frame_buffer: fill_and_decide decides at once when wanted() bytes are held") {
  frame_buffer<8> b;
  std::size_t used = 0;  // wanted() 0: a decision before any byte is taken
  CHECK(b.fill_and_decide(byte_view(in, 6), used, [] { return true; }));
  CHECK(used == 0);
  CHECK(b.empty());
}

TEST_CASE("frame_buffer: fill_and_decide returns false when the input is used up") {
  frame_buffer<8> b;
  b.want(8);
  CHECK(fill(b, byte_view(in, 6)) == 6);
  CHECK(b.size() == 6);
}

TEST_CASE("frame_buffer: fill_and_decide asks again after each decision that raises wanted()") {
  frame_buffer<8> b;
  b.want(1);
  std::size_t used = 0;
  int decisions = 0;
  const bool settled = b.fill_and_decide(byte_view(in, 6), used, [&] {
    ++decisions;
    b.want(b.size() + 2U);  // each decision wants two more
    return decisions == 3;
  });
  CHECK(settled);
  CHECK(used == 5);  // 1, then 2, then 2
  CHECK(b.size() == 5);
}

TEST_CASE("frame_buffer: fill_and_decide appends after the bytes held") {
  frame_buffer<4> b;
  held_at(b, 1, 2);  // 2, 3 held from index 1
  b.want(4);         // 4 wanted: moved to the front
  CHECK(fill(b, byte_view(in, 1)) == 1);
  CHECK(b.size() == 3);
  CHECK(b[0] == 2);
  CHECK(b[2] == 10);
}
