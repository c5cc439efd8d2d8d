// Oracle shared by the stream-object fuzz targets: the per-byte step agrees with the chunk
// feed. A stream object fed one byte at a time through put() (after each true, feed() with an
// empty chunk until incomplete: the rescan its contract names) must report the same results,
// in the same order, as one fed the same bytes in chunks through feed().
#ifndef MOTIONBUS_FUZZ_STREAM_ORACLE_HPP
#define MOTIONBUS_FUZZ_STREAM_ORACLE_HPP

#include <motionbus/core/span.hpp>

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

}  // namespace motionbus_fuzz

#endif
