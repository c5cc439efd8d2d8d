// The feed loops written once for every stream object: feed_all() and put_each(), driven by a
// scripted stream object whose results are given in advance (the receiver's and the framer's
// own tests drive them with real frames).
#include "motionbus/core/stream.hpp"

#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

using namespace motionbus;

namespace {

// What a stream object reports: incomplete, or a settled result (a frame or a failure) that
// used `used` bytes of the chunk it was given.
struct scripted_result {
  bool incomplete = true;
  std::size_t used = 0;
  int id = 0;
  bool is_incomplete() const { return incomplete; }
  std::size_t consumed() const { return used; }
};

struct scripted_stream {
  std::vector<scripted_result> script;  // feed() returns these in order, then incomplete
  std::size_t next = 0;
  std::vector<std::size_t> chunk_sizes;  // what each feed() was given
  bool put_settles = false;
  std::vector<std::uint8_t> put_bytes;

  scripted_result feed(byte_view in) {
    chunk_sizes.push_back(in.size());
    return next < script.size() ? script[next++] : scripted_result{};
  }
  bool put(std::uint8_t b) {
    put_bytes.push_back(b);
    return put_settles;
  }
  scripted_result result() const { return {false, 1, 99}; }
};

scripted_result settled(std::size_t consumed, int id) {
  return {false, consumed, id};
}

}  // namespace

TEST_CASE("feed_all: each settled result in order, the chunk advanced by what each consumed") {
  scripted_stream s;
  s.script = {settled(3, 1), settled(2, 2)};
  const std::uint8_t in[6] = {};
  std::vector<int> seen;
  const byte_view rest = feed_all(s, byte_view(in, 6), [&](const scripted_result& r) {
    seen.push_back(r.id);
    return true;
  });
  CHECK(rest.empty());
  CHECK(seen == std::vector<int>{1, 2});
  CHECK(s.chunk_sizes == std::vector<std::size_t>{6, 3, 1});  // the last feed() is incomplete
}

TEST_CASE("feed_all: a failure with the chunk used up calls feed() again, to rescan") {
  scripted_stream s;
  s.script = {settled(4, 1), settled(0, 2)};  // the second comes from the bytes held
  const std::uint8_t in[4] = {};
  std::vector<int> seen;
  (void)feed_all(s, byte_view(in, 4), [&](const scripted_result& r) {
    seen.push_back(r.id);
    return true;
  });
  CHECK(seen == std::vector<int>{1, 2});
  CHECK(s.chunk_sizes == std::vector<std::size_t>{4, 0, 0});
}

TEST_CASE("feed_all: each returning false stops it, and the bytes not taken are returned") {
  scripted_stream s;
  s.script = {settled(2, 1), settled(2, 2)};
  const std::uint8_t in[5] = {};
  int calls = 0;
  const byte_view rest = feed_all(s, byte_view(in, 5), [&](const scripted_result&) {
    ++calls;
    return false;
  });
  CHECK(calls == 1);
  CHECK(rest.size() == 3);
  CHECK(rest.data() == in + 2);
  CHECK(s.next == 1);  // the second result was never asked for
}

TEST_CASE("put_each: nothing settled, no call; settled, its result then the rescan's") {
  scripted_stream s;
  std::vector<int> seen;
  const auto each = [&](const scripted_result& r) {
    seen.push_back(r.id);
    return true;
  };
  put_each(s, 0x11, each);
  CHECK(seen.empty());
  CHECK(s.chunk_sizes.empty());  // no rescan without a settled byte
  s.put_settles = true;
  s.script = {settled(0, 5)};
  put_each(s, 0x22, each);
  CHECK(s.put_bytes == std::vector<std::uint8_t>{0x11, 0x22});
  CHECK(seen == std::vector<int>{99, 5});                  // result(), then what feed() of {} found
  CHECK(s.chunk_sizes == std::vector<std::size_t>{0, 0});  // until incomplete
}

TEST_CASE("put_each: each returning false for the byte's result skips the rescan") {
  scripted_stream s;
  s.put_settles = true;
  s.script = {settled(0, 5)};
  int calls = 0;
  put_each(s, 0x33, [&](const scripted_result&) {
    ++calls;
    return false;
  });
  CHECK(calls == 1);
  CHECK(s.chunk_sizes.empty());
}
