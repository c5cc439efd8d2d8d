// Footprint probe: the BiSS-C sensor data frame decoder alone (ABSYS layout, a capture of two
// 32-bit SPI words), as a master that only reads position links it. Inputs arrive as
// parameters of the entry function (no globals), so nothing folds away; the link keeps only
// what the entry reaches (--gc-sections).

#include <motionbus/biss/codec.hpp>

#include <new>

namespace mb = motionbus;
namespace bs = motionbus::biss;

// The result is built in the caller's object (C++17's guaranteed copy elision), as where a
// firmware keeps what it decoded.
extern "C" unsigned probe_entry(const std::uint32_t* capture, unsigned bits,
                                bs::frame_result<1>* out) {
  ::new (static_cast<void*>(out)) bs::frame_result<1>(
      bs::decode_frame(mb::span<const std::uint32_t>(capture, 2), bits, bs::absys_layout));
  return out->is_complete() ? static_cast<unsigned>((*out)->start)
                            : static_cast<unsigned>(out->error());
}
