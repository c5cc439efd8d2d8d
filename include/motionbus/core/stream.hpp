// motionbus — the feed loops of the stream objects (tformat::receiver, modbus::rtu_framer and
// its fixed-role forms, modbus::ascii_framer), written once: every result they report for a
// chunk of input, or for one byte, in order.
//
//   feed_all(rx, in, [&](const auto& r) {   // r: a decode_result, complete or failed
//     if (r) handle(r.value()); else log(r.error());
//     return true;                           // false: stop here, the rest of `in` is returned
//   });
//   put_each(rx, byte, same_lambda);         // one byte, from a receive interrupt
//
// put_each() in a receive interrupt, run under QEMU by the interrupt-driven firmware images
// (examples/firmware/modbus_server_irq.cpp, tformat_master_irq.cpp; the firmware.*_irq.*
// tests): `each` runs in the interrupt too, so it copies out what it keeps (a result lives in,
// or points into, the stream object until its next call).
//
// No heap, no I/O.
#ifndef MOTIONBUS_CORE_STREAM_HPP
#define MOTIONBUS_CORE_STREAM_HPP

#include <cstdint>

#include "motionbus/core/span.hpp"

namespace motionbus {

/// Hands `in` to `stream.feed()` until every byte is taken, calling `each(result)` for every
/// result that is not incomplete (a frame, or a failure: after one, the stream object rescans
/// the bytes it holds, so the loop calls feed() again even when `in` is used up). `each`
/// returns false to stop early. Returns the bytes of `in` not taken: empty, unless `each`
/// stopped. A frame a result points into is valid during `each` only.
template <class Stream, class Each>
constexpr byte_view feed_all(Stream& stream, byte_view in, Each&& each) {
  for (;;) {
    const auto r = stream.feed(in);
    if (r.is_incomplete()) {
      return byte_view{};
    }
    in = in.subspan(r.consumed());
    if (!each(r)) {
      return in;
    }
  }
}

/// The loop of the per-byte step (a receive interrupt's): `stream.put(byte)`, then `each(result)`
/// for what it settled and for every result the rescan of the bytes held then finds (feed_all
/// of an empty chunk), until one is incomplete or `each` returns false.
template <class Stream, class Each>
constexpr void put_each(Stream& stream, std::uint8_t byte, Each&& each) {
  if (stream.put(byte) && each(stream.result())) {
    (void)feed_all(stream, byte_view{}, each);
  }
}

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_STREAM_HPP
