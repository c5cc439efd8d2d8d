// A minimal consumer: includes the umbrella header and checks two published CRC values.
#include <motionbus/motionbus.hpp>

#include <cstdint>
#include <cstdio>

int main() {
  constexpr std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  static_assert(motionbus::crc16_modbus<>::compute(check) == 0x4B37, "CRC-16/MODBUS");
  const unsigned crc = motionbus::crc16_modbus<>::compute(check);
  std::printf("motionbus %d: CRC-16/MODBUS(\"123456789\") = 0x%04X\n", MOTIONBUS_VERSION, crc);
  return crc == 0x4B37U ? 0 : 1;
}
