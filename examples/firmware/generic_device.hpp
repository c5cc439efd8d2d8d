// motionbus firmware examples — the generic server's device: 100 coils, 100 discrete inputs,
// 100 holding and 100 input registers at addresses 0..99, served by the library's dispatch
// (01-06, 0F, 10, 11, 16, 17). Shared by the polled and the interrupt-driven server images.
#ifndef MOTIONBUS_EXAMPLES_FIRMWARE_GENERIC_DEVICE_HPP
#define MOTIONBUS_EXAMPLES_FIRMWARE_GENERIC_DEVICE_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu.hpp"

namespace firmware {

namespace mb = motionbus;
namespace mo = motionbus::modbus;

constexpr std::uint16_t points = 100;

// The data: coils and holding registers as written; discrete input i is on when i % 3 == 0,
// input register i reads 1000 + i.
struct generic_device {
  std::uint8_t coils[(points + 7U) / 8U] = {};
  std::uint16_t holding[points] = {};

  static bool fits(std::uint16_t address, std::size_t quantity) {
    return address + quantity <= points;
  }
  std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
                         mb::mutable_byte_view packed) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      const unsigned a = address + i;
      const bool on = function == 0x01 ? ((coils[a / 8U] >> (a % 8U)) & 1U) != 0U : a % 3U == 0U;
      if (on) {
        packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (1U << (i % 8U)));
      }
    }
    return 0;
  }
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              mb::span<std::uint16_t> out) {
    if (!fits(address, out.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] =
          function == 0x04 ? static_cast<std::uint16_t>(1000U + address + i) : holding[address + i];
    }
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, mb::byte_view packed) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      const unsigned a = address + i;
      const auto bit = static_cast<std::uint8_t>(1U << (a % 8U));
      coils[a / 8U] = mo::bit_at(packed, i) ? static_cast<std::uint8_t>(coils[a / 8U] | bit)
                                            : static_cast<std::uint8_t>(coils[a / 8U] & ~bit);
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> values) {
    if (!fits(address, values.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      holding[address + i] = values[i];
    }
    return 0;
  }
  // FC11: the byte count, then server ID 0x4D ('M'), run indicator 0xFF (on), "motionbus".
  std::uint8_t report_server_id(mb::mutable_byte_view out, std::size_t& size) {
    const char id[] = "\x4D\xFFmotionbus";
    const std::size_t n = sizeof id - 1U;
    out[0] = static_cast<std::uint8_t>(n);
    for (std::size_t i = 0; i < n; ++i) {
      out[1U + i] = static_cast<std::uint8_t>(id[i]);
    }
    size = 1U + n;
    return 0;
  }
};

}  // namespace firmware

#endif  // MOTIONBUS_EXAMPLES_FIRMWARE_GENERIC_DEVICE_HPP
