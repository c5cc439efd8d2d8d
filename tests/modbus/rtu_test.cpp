// Modbus RTU ADUs: the example of Modbus over Serial Line V1.02 §6.2.2, CRC low byte first,
// addresses and lengths.
#include "motionbus/modbus/rtu.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../support/bytes.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

TEST_CASE("RTU: the serial-line example, CRC low byte first, addresses and lengths") {
  const std::uint8_t pdu[] = {0x03, 0x00, 0x6B, 0x00, 0x03};
  std::uint8_t out[256] = {};
  const auto n = encode_rtu(0x11, pdu, out);
  REQUIRE(n.ok());
  CHECK(bytes(out, out + n.value()) == bytes{0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87});
  const auto f = decode_rtu(byte_view(out, n.value()));
  REQUIRE(f.is_complete());
  CHECK(f->slave == 0x11);
  CHECK(f->pdu.size() == 5);
  CHECK(f->crc == 0x8776);
  CHECK(!f->broadcast());

  out[7] ^= 0x01;
  const auto bad = decode_rtu(byte_view(out, n.value()));
  CHECK(bad.error() == errc::crc_mismatch);
  CHECK(bad.expected() == 0x8776);
  CHECK(bad.received() == 0x8676);

  CHECK(encode_rtu(248, pdu, out).error() == errc::modbus_slave_address);
  CHECK(encode_rtu(1, byte_view{}, out).error() == errc::modbus_pdu_length);
  CHECK(encode_rtu(1, pdu, mutable_byte_view(out, 7)).error() == errc::buffer_too_small);
  REQUIRE(encode_rtu(0, pdu, out).ok());
  CHECK(decode_rtu(byte_view(out, 8))->broadcast());
  REQUIRE(encode_rtu(247, pdu, out).ok());
  out[0] = 248;  // re-CRC with a reserved address
  const auto c = crc16::compute(byte_view(out, 6));
  out[6] = static_cast<std::uint8_t>(c & 0xFF);
  out[7] = static_cast<std::uint8_t>(c >> 8);
  CHECK(decode_rtu(byte_view(out, 8)).error() == errc::modbus_slave_address);
  CHECK(decode_rtu(byte_view(out, 3)).error() == errc::modbus_pdu_length);
  std::uint8_t huge[257] = {};
  CHECK(decode_rtu(byte_view(huge, 257)).error() == errc::modbus_pdu_length);
}

TEST_CASE("encode_rtu: a PDU inside the output behind the address (a TCP ADU converted in place)") {
  // FC03 of 10 registers from 0x6B, as a TCP ADU: MBAP (7 bytes), then the PDU
  const bytes pdu = {0x03, 0x00, 0x6B, 0x00, 0x0A};
  std::uint8_t apart[16] = {};
  const std::size_t n = encode_rtu(0x11, view(pdu), apart).value();
  REQUIRE(n == 8U);
  for (std::size_t behind = 1; behind <= 7; ++behind) {
    CAPTURE(behind);
    std::uint8_t buf[16] = {};
    for (std::size_t i = 0; i < pdu.size(); ++i) {
      buf[behind + i] = pdu[i];
    }
    const auto r = encode_rtu(0x11, byte_view(buf + behind, pdu.size()), buf);
    REQUIRE(r.ok());
    CHECK(bytes(buf, buf + r.value()) == bytes(apart, apart + n));
  }
}
