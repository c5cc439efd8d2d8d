// Modbus helpers shared by the doctest suites: an RTU frame around a PDU, and a request served
// by a device through the RTU server dispatch.
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

/// Tells the client framer `f` that a request for `function` went to `slave`: sent() with the
/// head of its ADU (the framer reads the address and the function only).
template <class Framer>
void sent_to(Framer& f, std::uint8_t slave, std::uint8_t function) {
  const std::uint8_t head[2] = {slave, function};
  f.sent(motionbus::byte_view(head, 2));
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_MODBUS_HPP
