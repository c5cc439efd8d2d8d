// Oracle shared by the stream-object fuzz targets: the per-byte step agrees with the chunk
// feed. A stream object fed one byte at a time through put() (after each true, feed() with an
// empty chunk until incomplete: the rescan its contract names) must report the same results,
// in the same order, as one fed the same bytes in chunks through feed(). by_chunks() is that
// chunk feed, with the bounds every stream object keeps checked at each call.
#ifndef MOTIONBUS_FUZZ_STREAM_ORACLE_HPP
#define MOTIONBUS_FUZZ_STREAM_ORACLE_HPP

#include <motionbus/core/span.hpp>

#include "fuzz_check.hpp"

#include <cstddef>
#include <vector>

namespace motionbus_fuzz {

// `note(result)` returns a comparable record of a complete or failed result (its consumed()
// left out: it counts different inputs in the two forms).
template <class Stream, class Note>
auto results_by_put(Stream& s, motionbus::byte_view stream, Note&& note) {
  std::vector<decltype(note(s.result()))> out;
  for (const std::uint8_t b : stream) {
    if (!s.put(b)) {
      continue;
    }
    auto r = s.result();
    while (!r.is_incomplete()) {
      out.push_back(note(r));
      r = s.feed(motionbus::byte_view{});
    }
  }
  return out;
}

// note(r) of every result `s` settles over `stream` handed to feed() in chunks of `chunk`
// bytes (the last one shorter), each chunk fed until incomplete. Checked at every call: at
// most `most_held` bytes held (pending()), and when incomplete at most `most_wanted` held and
// wanted (pending() + needed()); consumed() within the chunk; the loop ends.
template <class Stream, class Note>
auto by_chunks(Stream& s, motionbus::byte_view stream, std::size_t chunk, Note&& note,
               std::size_t most_held, std::size_t most_wanted) {
  std::vector<decltype(note(s.result()))> out;
  for (std::size_t at = 0; at < stream.size(); at += chunk) {
    motionbus::byte_view part =
        stream.subspan(at, chunk < stream.size() - at ? chunk : stream.size() - at);
    for (int guard = 0;; ++guard) {
      MOTIONBUS_FUZZ_CHECK(guard < 100000);
      const auto r = s.feed(part);
      MOTIONBUS_FUZZ_CHECK(s.pending() <= most_held);
      if (r.is_incomplete()) {
        MOTIONBUS_FUZZ_CHECK(s.pending() + r.needed() <= most_wanted);
        break;
      }
      MOTIONBUS_FUZZ_CHECK(r.consumed() <= part.size());
      part = part.subspan(r.consumed());
      out.push_back(note(r));
    }
  }
  return out;
}

}  // namespace motionbus_fuzz

#endif
