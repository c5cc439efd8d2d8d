// The device of the Modbus server footprint probes (modbus_server_core, modbus_rtu_server):
// FC01-06, 0F and 10 over 64 coils, 64 inputs and 64 registers held by the caller, with the
// bit accessors and the big-endian register accessors (no register buffer in the server).
#ifndef MOTIONBUS_TESTS_FOOTPRINT_SERVER_DEVICE_HPP
#define MOTIONBUS_TESTS_FOOTPRINT_SERVER_DEVICE_HPP

#include <motionbus/modbus/server.hpp>

#include <cstddef>
#include <cstdint>

namespace mb = motionbus;
namespace md = motionbus::modbus;

namespace {

constexpr mb::crc_table_size table = mb::crc_table_size::bitwise;

struct device {
  // FC01-06, 0F and 10 (not FC16/17, which the register accessors would also allow)
  static constexpr md::function_set functions =
      md::functions_of(0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x10);
  std::uint8_t* bits;       // 64 coils and 64 inputs, one byte each
  std::uint8_t* registers;  // 64 registers, big-endian, as the PDU carries them
  std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
                         mb::mutable_byte_view packed) {
    if (address + quantity > 64U) {
      return 0x02;
    }
    const std::uint8_t* from = bits + (function == 0x01 ? 0U : 64U) + address;
    for (std::size_t i = 0; i < quantity; ++i) {
      if (from[i] != 0U) {
        packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (1U << (i % 8U)));
      }
    }
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, mb::byte_view packed) {
    if (address + quantity > 64U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      bits[address + i] = static_cast<std::uint8_t>((packed[i / 8U] >> (i % 8U)) & 1U);
    }
    return 0;
  }
  std::uint8_t read_registers_be(std::uint8_t, std::uint16_t address, std::uint16_t quantity,
                                 mb::mutable_byte_view out) {
    if (address + quantity > 64U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < 2U * quantity; ++i) {
      out[i] = registers[2U * address + i];
    }
    return 0;
  }
  std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity,
                                  mb::byte_view data) {
    if (address + quantity > 64U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < data.size(); ++i) {
      registers[2U * address + i] = data[i];
    }
    return 0;
  }
};

}  // namespace

#endif  // MOTIONBUS_TESTS_FOOTPRINT_SERVER_DEVICE_HPP
