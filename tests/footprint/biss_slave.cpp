// Footprint probe: BiSS-C slave: ABSYS frame encoder and register access. Inputs arrive as
// parameters of the entry function (no globals), so nothing folds away; the link keeps only what
// the entry reaches (--gc-sections).

#include <motionbus/biss/codec.hpp>
#include <motionbus/biss/control.hpp>

#include <cstdint>

namespace mb = motionbus;
namespace bs = motionbus::biss;

namespace {

struct registers {
  std::uint8_t* mem;
  bool readable(std::uint8_t) const { return true; }
  bool writable(std::uint8_t a) const { return a >= 0x40U; }
  bool ready() const { return true; }
  std::uint8_t read(std::uint8_t a) const { return mem[a]; }
  void write(std::uint8_t a, std::uint8_t v) { mem[a] = v; }
};

}  // namespace

extern "C" unsigned probe_entry(std::uint32_t* out, std::uint32_t position, bool cdm,
                                bs::control_slave<registers>* control) {
  bs::slave_values v;
  v.single_turn = position;
  bs::line_options line;
  line.cds = control->step(cdm);
  const auto n = bs::encode_frame(bs::absys_layout, v, mb::span<std::uint32_t>(out, 2), line);
  return n.ok() ? static_cast<unsigned>(*n) : 0U;
}
