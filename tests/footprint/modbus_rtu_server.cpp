// Footprint probe: a whole Modbus RTU server firmware's codec of function codes 01-06, 0F and
// 10 with the bitwise CRC: bytes from the UART into a server framer (rtu_server_framer: the
// request length rule only, no client code), each frame served by serve_frame over a device
// with the bit accessors and the big-endian register accessors (no register buffer). Inputs arrive
// as parameters of the entry function (no globals), so nothing folds away; the link keeps only what
// the entry reaches (--gc-sections).

#include <motionbus/modbus/framer.hpp>
#include <motionbus/modbus/server.hpp>

#include <cstdint>

#include "server_device.hpp"

extern "C" unsigned probe_entry(md::basic_rtu_framer<table, md::framer_role::server>* rx,
                                const unsigned char* in, unsigned n, unsigned char* out,
                                std::uint8_t* bits, std::uint8_t* registers) {
  device d{bits, registers};
  unsigned sent = 0;
  mb::byte_view bytes(in, n);
  for (;;) {
    const auto f = rx->feed(bytes);
    if (f.is_incomplete()) {
      break;
    }
    bytes = bytes.subspan(f.consumed());
    if (f.is_complete()) {
      const auto w = md::serve_frame<table>(d, 1, f.value(), mb::mutable_byte_view(out, 256));
      sent += w.ok() ? *w : 0U;
    }
  }
  const auto last = rx->idle();
  if (last.is_complete()) {
    const auto w = md::serve_frame<table>(d, 1, last.value(), mb::mutable_byte_view(out, 256));
    sent += w.ok() ? *w : 0U;
  }
  return sent;
}
