// Every public header used the way MCU firmware would, compiled for Cortex-M0+, Cortex-M4 and
// rv32imc, C++17 and C++20, -Os -fno-exceptions -fno-rtti: the test command's one check that
// the library has no writable data (.data, .bss): tables land in read-only storage
// (tests/footprint/CMakeLists.txt, cmake/checks/all_headers_probe.cmake).
#include <motionbus/motionbus.hpp>

#include <cstddef>
#include <cstdint>

namespace mb = motionbus;

extern "C" {

std::uint16_t probe_crc16_modbus(const std::uint8_t* data, std::size_t size) {
  return mb::crc16_modbus<>::compute(mb::byte_view(data, size));
}

std::uint16_t probe_crc16_modbus_nibble(const std::uint8_t* data, std::size_t size) {
  return mb::crc16_modbus<mb::crc_table_size::nibble>::compute(mb::byte_view(data, size));
}

std::uint8_t probe_crc8_tformat(const std::uint8_t* data, std::size_t size) {
  return mb::crc8_tformat<mb::crc_table_size::bitwise>::compute(mb::byte_view(data, size));
}

std::uint8_t probe_crc6_biss(const std::uint32_t* words, std::size_t count, std::size_t offset) {
  mb::crc6_biss<> c;
  if (c.update_stream(mb::span<const std::uint32_t>(words, count), mb::bit_order::msb_first, offset,
                      34) != mb::errc::ok) {
    return 0xFF;
  }
  return c.value();
}

std::uint8_t probe_crc4_biss(std::uint32_t bits) {
  return mb::crc4_biss<>::compute_bits(bits, 11);
}

std::int32_t probe_bits(std::uint8_t* buffer, std::size_t size, std::uint32_t value) {
  mb::bit_writer w(mb::mutable_byte_view(buffer, size), mb::bit_order::lsb_first, 3);
  if (w.write(value, 27) != mb::errc::ok) {
    return -1;
  }
  mb::bit_reader r(mb::byte_view(buffer, size), mb::bit_order::lsb_first, 3);
  const mb::result<std::uint64_t> v = r.read(27);
  return v.ok() ? static_cast<std::int32_t>(v.value()) : -static_cast<std::int32_t>(v.error());
}

int probe_version() {
  return MOTIONBUS_VERSION;
}
}
