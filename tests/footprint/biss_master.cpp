// Footprint probe: BiSS-C master: ABSYS frame decoder and register access. Inputs arrive as
// parameters of the entry function (no globals), so nothing folds away; the link keeps only what
// the entry reaches (--gc-sections).

#include <motionbus/biss/codec.hpp>
#include <motionbus/biss/control.hpp>

namespace mb = motionbus;
namespace bs = motionbus::biss;

extern "C" unsigned probe_entry(const std::uint32_t* capture, unsigned bits,
                                bs::control_master* control, unsigned char* registers) {
  const auto r =
      bs::decode_frame(mb::span<const std::uint32_t>(capture, 2), bits, bs::absys_layout);
  if (!control->busy()) {
    (void)control->start_read(0, 0x7E, mb::mutable_byte_view(registers, 2));
  }
  const bool cdm = control->step(r.is_complete() && r->cds);
  return (r.is_complete() ? static_cast<unsigned>(r->slaves[0].single_turn) : 0U) + (cdm ? 1U : 0U);
}
