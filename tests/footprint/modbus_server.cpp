// Footprint probe: Modbus RTU server with dispatch (holding registers, read and write). Inputs
// arrive as parameters of the entry function (no globals), so nothing folds away; the link keeps
// only what the entry reaches (--gc-sections).

#include <motionbus/modbus/server.hpp>

#include <cstdint>

namespace mb = motionbus;
namespace md = motionbus::modbus;

namespace {

struct device {
  std::uint16_t* regs;
  std::uint8_t read_registers(std::uint8_t, std::uint16_t address, mb::span<std::uint16_t> out) {
    if (address + out.size() > 64U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = regs[address + i];
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> in) {
    if (address + in.size() > 64U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < in.size(); ++i) {
      regs[address + i] = in[i];
    }
    return 0;
  }
};

}  // namespace

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n, unsigned char* out,
                                std::uint16_t* regs) {
  device d{regs};
  const auto w = md::serve_rtu(d, 1, mb::byte_view(in, n), mb::mutable_byte_view(out, 256));
  return w.ok() ? *w : 0U;
}
