// Footprint probe: the Modbus RTU server with dispatch of modbus_server.cpp (holding registers,
// read and write) through the C API (c/include/motionbus/c.h): decode_rtu, then serve_frame over
// a callback table, the C API's source compiled into the probe as a C firmware links it. The C
// API's server compiles every function it can serve (01-06, 0F, 10, 11, 16, 17: the table's
// callbacks choose at run time). Inputs arrive as parameters of the entry function (no
// globals), so nothing folds away; the link keeps only what the entry reaches (--gc-sections).

#include "../../c/motionbus_c.cpp"  // NOLINT(bugprone-suspicious-include): the C API's source

namespace {

std::uint8_t read_holding(std::uint16_t address, std::uint16_t quantity, std::uint16_t* out,
                          void* context) {
  const auto* regs = static_cast<const std::uint16_t*>(context);
  if (address + quantity > 64U) {
    return 0x02;
  }
  for (std::uint16_t i = 0; i < quantity; ++i) {
    out[i] = regs[address + i];
  }
  return 0;
}

std::uint8_t write_registers(std::uint16_t address, std::uint16_t quantity,
                             const std::uint16_t* values, void* context) {
  auto* regs = static_cast<std::uint16_t*>(context);
  if (address + quantity > 64U) {
    return 0x02;
  }
  for (std::uint16_t i = 0; i < quantity; ++i) {
    regs[address + i] = values[i];
  }
  return 0;
}

}  // namespace

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n, unsigned char* out,
                                std::uint16_t* regs) {
  mb_modbus_callbacks cb = {};
  cb.read_holding_registers = read_holding;
  cb.write_multiple_registers = write_registers;
  cb.context = regs;
  mb_modbus_frame frame;
  if (mb_modbus_decode_rtu(in, n, &frame).status != MB_COMPLETE) {
    return 0;
  }
  std::size_t written = 0;
  return mb_modbus_serve_frame(&cb, 1, &frame, out, 256, &written) == MB_OK
             ? static_cast<unsigned>(written)
             : 0U;
}
