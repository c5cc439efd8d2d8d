// The record the Modbus stream-object suites (ASCII, RTU over TCP) make of each result a
// framer settles: a frame's slave and PDU, or a failure's error and its expected/received
// figures; comparable, for the vectors fed_notes() and put_notes() (stream.hpp) return.
#ifndef MOTIONBUS_TESTS_FRAME_EVENTS_HPP
#define MOTIONBUS_TESTS_FRAME_EVENTS_HPP

#include <cstdint>

#include "bytes.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"

namespace testutil {

struct frame_note {
  bool ok;
  motionbus::errc error;
  std::uint8_t slave;
  bytes pdu;
  std::uint32_t expected;
  std::uint32_t received;
  bool operator==(const frame_note& o) const {
    return ok == o.ok && error == o.error && slave == o.slave && pdu == o.pdu &&
           expected == o.expected && received == o.received;
  }
};

/// note_frame(r): the frame_note of a settled result of any frame type with `slave` and `pdu`.
struct note_frame_fn {
  template <class Frame>
  frame_note operator()(const motionbus::decode_result<Frame>& r) const {
    if (r) {
      return {true, motionbus::errc::ok, r->slave, bytes(r->pdu.begin(), r->pdu.end()), 0, 0};
    }
    return {false, r.error(), 0, {}, r.expected(), r.received()};
  }
};
inline constexpr note_frame_fn note_frame{};

inline frame_note frame_event(std::uint8_t slave, const bytes& pdu) {
  return {true, motionbus::errc::ok, slave, pdu, 0, 0};
}
inline frame_note failure_event(motionbus::errc e, std::uint32_t expected = 0,
                                std::uint32_t received = 0) {
  return {false, e, 0, {}, expected, received};
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_FRAME_EVENTS_HPP
