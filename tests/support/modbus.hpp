// Modbus helpers shared by the doctest suites: an RTU frame around a PDU, a request served by a
// device through the RTU server dispatch, the encoders' shared arguments, a client framer told
// what was sent.
#ifndef MOTIONBUS_TESTS_MODBUS_HPP
#define MOTIONBUS_TESTS_MODBUS_HPP

#include <doctest/doctest.h>

#include <cstdint>

#include "bytes.hpp"
#include "motionbus/modbus/rtu.hpp"
#include "motionbus/modbus/server.hpp"

namespace testutil {

/// The RTU ADU of `pdu` for `slave`, CRC included.
inline bytes rtu(std::uint8_t slave, const bytes& pdu) {
  std::uint8_t out[256] = {};
  const auto n = motionbus::modbus::encode_rtu(slave, view(pdu), out);
  REQUIRE(n.ok());
  return bytes(out, out + n.value());
}

/// The response PDU `device` (address `own`) gives to the ADU `adu` through serve_rtu; empty
/// when it sends nothing.
template <class Device>
bytes serve_adu(Device& device, std::uint8_t own, motionbus::byte_view adu) {
  std::uint8_t out[256] = {};
  const auto r = motionbus::modbus::serve_rtu(device, own, adu, out);
  REQUIRE(r.ok());
  if (r.value() == 0U) {
    return {};
  }
  const auto f = motionbus::modbus::decode_rtu(motionbus::byte_view(out, r.value()));
  REQUIRE(f.is_complete());
  return bytes(f->pdu.begin(), f->pdu.end());
}

/// The response PDU to `pdu` sent to `slave` (default: the device's own address `own`).
template <class Device>
bytes serve_pdu(Device& device, std::uint8_t own, const bytes& pdu) {
  return serve_adu(device, own, view(rtu(own, pdu)));
}

/// The arguments the encoders' refusal cases share: a buffer for any PDU (`big`) and one of
/// three bytes (`small`), three registers, two packed bytes (up to 16 coils). The views point
/// into the object itself: not copied.
struct encoder_args {
  std::uint8_t out[260] = {};
  std::uint8_t tiny[3] = {};
  const motionbus::mutable_byte_view big{out, sizeof out};
  const motionbus::mutable_byte_view small{tiny, sizeof tiny};
  const std::uint16_t regs[3] = {1, 2, 3};
  const motionbus::span<const std::uint16_t> three{regs, 3};
  const std::uint8_t packed[2] = {0xFF, 0x03};
  const motionbus::byte_view two_bytes{packed, 2};

  encoder_args() = default;
  encoder_args(const encoder_args&) = delete;
  encoder_args& operator=(const encoder_args&) = delete;
};

/// Tells the client framer `f` that a request for `function` went to `slave`: sent() with the
/// head of its ADU (the framer reads the address and the function only).
template <class Framer>
void sent_to(Framer& f, std::uint8_t slave, std::uint8_t function) {
  const std::uint8_t head[2] = {slave, function};
  f.sent(motionbus::byte_view(head, 2));
}

/// A device that knows which unit it is (several slaves on one port, a gateway's line):
/// holding registers 0..19 of unit u hold u * 0x100 + address; writes are counted.
struct unit_device {
  std::uint8_t unit = 0;
  int writes = 0;
  std::uint8_t read_registers(std::uint8_t, std::uint16_t address,
                              motionbus::span<std::uint16_t> out) {
    if (address + out.size() > 20U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = static_cast<std::uint16_t>(unit * 0x100U + address + i);
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t, motionbus::span<const std::uint16_t>) {
    ++writes;
    return 0;
  }
};

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_MODBUS_HPP
