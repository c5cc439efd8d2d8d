// Stream-object drivers shared by the doctest suites (tformat::receiver, tformat::line_listener,
// modbus::rtu_framer and its forms): a byte stream fed in chunks through feed_all(), or one
// byte at a time through put(), optionally followed by the silence (idle()), each result the
// object settles recorded as `note(result)`.
#ifndef MOTIONBUS_TESTS_STREAM_HPP
#define MOTIONBUS_TESTS_STREAM_HPP

#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "motionbus/core/span.hpp"
#include "motionbus/core/stream.hpp"

namespace testutil {

/// What follows the stream: nothing, or the silence of the line (idle() until it settles
/// nothing more).
enum class then { nothing, idle };

/// Calls each(r) for every result idle() settles, until one is incomplete.
template <class Stream, class Each>
void idle_all(Stream& s, Each&& each) {
  for (auto r = s.idle(); !r.is_incomplete(); r = s.idle()) {
    each(r);
  }
}

/// Calls each(r) for every result `s` settles over `in` handed over in chunks of `chunk`
/// bytes (the last one shorter), through feed_all().
template <class Stream, class Each>
void feed_chunks(Stream& s, motionbus::byte_view in, std::size_t chunk, Each&& each) {
  for (std::size_t at = 0; at < in.size(); at += chunk) {
    (void)motionbus::feed_all(s, in.subspan(at, std::min(chunk, in.size() - at)), each);
  }
}

/// Calls each(r) for every result `s` settles over `in` one byte at a time, through put()
/// and the rescan after it (put_each). A put() that returns true has settled something: the
/// result it hands over is never incomplete (checked).
template <class Stream, class Each>
void put_bytes(Stream& s, motionbus::byte_view in, Each&& each) {
  for (const std::uint8_t b : in) {
    motionbus::put_each(s, b, [&](const auto& r) {
      CHECK(!r.is_incomplete());
      return each(r);
    });
  }
}

/// The type `note` makes of a result of `Stream`.
template <class Stream, class Note>
using note_of = std::decay_t<decltype(std::declval<Note&>()(std::declval<Stream&>().result()))>;

/// note(r) of every result `s` settles over `in` fed in chunks of `chunk` bytes, then at
/// the silence with then::idle.
template <class Stream, class Note>
std::vector<note_of<Stream, Note>> fed_notes(Stream& s, motionbus::byte_view in, std::size_t chunk,
                                             Note&& note, then end = then::nothing) {
  std::vector<note_of<Stream, Note>> out;
  const auto each = [&](const auto& r) {
    out.push_back(note(r));
    return true;
  };
  feed_chunks(s, in, chunk, each);
  if (end == then::idle) {
    idle_all(s, each);
  }
  return out;
}

/// note(r) of every result `s` settles over `in` one byte at a time through put(), then at
/// the silence with then::idle.
template <class Stream, class Note>
std::vector<note_of<Stream, Note>> put_notes(Stream& s, motionbus::byte_view in, Note&& note,
                                             then end = then::nothing) {
  std::vector<note_of<Stream, Note>> out;
  const auto each = [&](const auto& r) {
    out.push_back(note(r));
    return true;
  };
  put_bytes(s, in, each);
  if (end == then::idle) {
    idle_all(s, each);
  }
  return out;
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_STREAM_HPP
