// Footprint probe: the BiSS-C sensor data frame decoder alone (ABSYS layout, a capture of two
// 32-bit SPI words), as a master that only reads position links it. Inputs arrive as
// parameters of the entry function (no globals), so nothing folds away; the link keeps only
// what the entry reaches (--gc-sections).

#include <motionbus/biss/codec.hpp>

namespace mb = motionbus;
namespace bs = motionbus::biss;

extern "C" unsigned probe_entry(const std::uint32_t* capture, unsigned bits, bs::slave_data* d) {
  const auto r =
      bs::decode_frame(mb::span<const std::uint32_t>(capture, 2), bits, bs::absys_layout);
  if (!r.is_complete()) {
    return static_cast<unsigned>(r.error());
  }
  *d = r->slaves[0];  // the slave's data, kept as a firmware keeps it
  return static_cast<unsigned>(r->start);
}
