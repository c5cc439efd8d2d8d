// Footprint probe: a Modbus RTU server of function codes 01-06, 0F and 10 with the bitwise
// CRC, as a small device builds it: decode_rtu, then serve_frame over a device with the bit
// accessors and the big-endian register accessors (no register buffer). The server decodes
// only the functions its device serves and links no client code. Inputs arrive as parameters
// of the entry function (no globals), so nothing folds away; the link keeps only what the entry
// reaches (--gc-sections).

#include <motionbus/modbus/server.hpp>

#include <cstdint>

#include "server_device.hpp"

extern "C" unsigned probe_entry(const unsigned char* in, unsigned n, unsigned char* out,
                                std::uint8_t* bits, std::uint8_t* registers) {
  device d{bits, registers};
  const auto f = md::decode_rtu<table>(mb::byte_view(in, n));
  if (!f.is_complete()) {
    return 0;
  }
  const auto w = md::serve_frame<table>(d, 1, f.value(), mb::mutable_byte_view(out, 256));
  return w.ok() ? *w : 0U;
}
