// A tour of the shared core: the protocols' CRCs on real frames, and bits pulled out of a
// BiSS-style SPI capture at an unknown offset. Prints what it computes.
#include <motionbus/motionbus.hpp>

#include <cstdint>
#include <cstdio>

namespace mb = motionbus;

int main() {
  // Modbus over Serial Line example request: read 3 holding registers from slave 0x11.
  const std::uint8_t modbus_request[] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03};
  const unsigned crc16 = mb::crc16_modbus<>::compute(modbus_request);
  std::printf("Modbus  11 03 00 6B 00 03      CRC-16 = 0x%04X -> wire bytes %02X %02X\n", crc16,
              crc16 & 0xFFU, crc16 >> 8U);

  // T-format: CRC (G = X^8 + 1) of a response's fields is the XOR of the bytes.
  const std::uint8_t tformat_fields[] = {0x02, 0x00, 0x34, 0x12, 0x01};
  std::printf("T-format 02 00 34 12 01        CRC    = 0x%02X\n",
              static_cast<unsigned>(mb::crc8_tformat<>::compute(tformat_fields)));

  // BiSS: a 34-bit word (32-bit position, nE, nW) written into 32-bit SPI words after 5 idle
  // and Ack bits, then read back at that offset and checked with CRC6 over the stream.
  std::uint32_t capture[3] = {0xFFFFFFFFU, 0xFFFFFFFFU, 0xFFFFFFFFU};
  mb::basic_bit_writer<std::uint32_t> w(capture, mb::bit_order::msb_first, 5);
  const std::uint64_t word = (std::uint64_t{0x00C0FFEEU} << 2U) | 0x3U;
  if (w.write(word, 34) != mb::errc::ok) {
    return 1;
  }
  mb::basic_bit_reader<std::uint32_t> r(capture, mb::bit_order::msb_first, 5);
  const auto position = r.read(32);
  const auto status = r.read(2);
  mb::crc6_biss<> crc6;
  if (!position || !status ||
      crc6.update_stream(mb::span<const std::uint32_t>(capture), mb::bit_order::msb_first, 5, 34) !=
          mb::errc::ok) {
    return 1;
  }
  std::printf("BiSS    position 0x%08llX nE=%llu nW=%llu CRC6 (wire, inverted) = 0x%02X\n",
              static_cast<unsigned long long>(position.value()),
              static_cast<unsigned long long>(status.value() >> 1U),
              static_cast<unsigned long long>(status.value() & 1U),
              static_cast<unsigned>(crc6.value()));
  return 0;
}
