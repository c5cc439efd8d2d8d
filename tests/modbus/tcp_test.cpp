// Modbus TCP ADUs (Modbus Messaging on TCP/IP Implementation Guide V1.0b §3.1.3): the MBAP
// header around the same PDU codec, frames cut short, bad lengths and protocol ids.
#include "motionbus/modbus/tcp.hpp"

#include <doctest/doctest.h>

#include <cstdint>

#include "../support/bytes.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

TEST_CASE("TCP: MBAP header around the same PDU codec") {
  const std::uint8_t pdu[] = {0x03, 0x00, 0x6B, 0x00, 0x03};
  std::uint8_t out[300] = {};
  const auto n = encode_tcp(0x1234, 0x11, pdu, out);
  REQUIRE(n.ok());
  CHECK(bytes(out, out + n.value()) ==
        bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x11, 0x03, 0x00, 0x6B, 0x00, 0x03});
  for (std::size_t k = 0; k < n.value(); ++k) {
    CHECK(decode_tcp(byte_view(out, k)).is_incomplete());
  }
  const auto f = decode_tcp(byte_view(out, n.value() + 3));  // extra bytes: the next frame
  REQUIRE(f.is_complete());
  CHECK(f.consumed() == 12);
  CHECK(f->transaction == 0x1234);
  CHECK(f->unit == 0x11);
  CHECK(f->pdu.size() == 5);
  out[5] = 0x01;  // length 1: no room for a function code
  CHECK(decode_tcp(byte_view(out, 12)).error() == errc::modbus_pdu_length);
  out[5] = 0x06;
  out[3] = 0x01;  // protocol id 1
  CHECK(decode_tcp(byte_view(out, 12)).error() == errc::invalid_argument);
  CHECK(encode_tcp(1, 1, byte_view{}, out).error() == errc::modbus_pdu_length);
}

TEST_CASE("MBAP header: a buffer shorter than header and PDU is refused") {
  std::uint8_t out[8] = {};
  const bytes pdu = {0x03, 0x00, 0x00, 0x00, 0x01};
  CHECK(encode_tcp(1, 1, view(pdu), mutable_byte_view(out, sizeof out)).error() ==
        errc::buffer_too_small);
}

TEST_CASE("tcp_adu_size: a stream's MBAP header checked as its bytes arrive") {
  std::uint8_t out[max_tcp_size] = {};
  const std::uint8_t pdu[] = {0x03, 0x00, 0x01, 0x00, 0x02};
  REQUIRE(encode_tcp(0x0102, 7, pdu, out).value() == 12);
  for (std::size_t k = 0; k < 6; ++k) {
    CHECK(tcp_adu_size(byte_view(out, k)).is_incomplete());
  }
  const auto r = tcp_adu_size(byte_view(out, 6));
  REQUIRE(r.is_complete());
  CHECK(r.value() == 12);
  out[3] = 1;  // protocol id 1: failed from its 4th byte, before the length
  CHECK(tcp_adu_size(byte_view(out, 4)).error() == errc::invalid_argument);
  CHECK(tcp_adu_size(byte_view(out, 3)).is_incomplete());
  out[3] = 0;
  for (const std::uint16_t length :
       {std::uint16_t{0}, std::uint16_t{1}, std::uint16_t{255},
        std::uint16_t{0xFFFF}}) {  // no PDU; more than 260 bytes in all
    store_be16(mutable_byte_view(out, 6), 4, length);
    CHECK(tcp_adu_size(byte_view(out, 6)).error() == errc::modbus_pdu_length);
  }
  store_be16(mutable_byte_view(out, 6), 4, 254);  // 260 bytes: the largest
  CHECK(tcp_adu_size(byte_view(out, 6)).value() == max_tcp_size);
}

TEST_CASE("TCP: a length field of 0 or 1 (no unit identifier, or no PDU) fails at once") {
  CHECK(decode_tcp(view({0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x11})).error() ==
        errc::modbus_pdu_length);
  CHECK(decode_tcp(view({0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x11})).error() ==
        errc::modbus_pdu_length);
  CHECK(decode_tcp(view({0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x11, 0x07})).is_complete());
}

TEST_CASE("tcp_frame: a default frame is transaction 0, Modbus, unit 0, no PDU") {
  const tcp_frame f{};
  CHECK(f.transaction == 0);
  CHECK(f.protocol == 0);
  CHECK(f.unit == 0);
  CHECK(f.pdu.empty());
}

TEST_CASE("encode_tcp writes the MBAP header and the PDU and nothing past them") {
  // into a buffer of 0xA5s, the PDU the first bytes of a longer array: the protocol id is
  // written as 0, and no byte follows the ADU
  const std::uint8_t pdu[4] = {0x03, 0x00, 0x6B, 0xEE};
  bytes out(32, 0xA5);
  const auto n = encode_tcp(0x1234, 0x11, byte_view(pdu, 3), mutable_byte_view(out.data(), 32));
  REQUIRE(n.ok());
  CHECK(bytes(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n.value())) ==
        bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x04, 0x11, 0x03, 0x00, 0x6B});
  CHECK(out[n.value()] == 0xA5);
}

TEST_CASE("tcp_adu_size consumes nothing; decode_tcp reads the protocol id from bytes 2 and 3") {
  const bytes adu = {0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x01, 0x07};
  const auto size = tcp_adu_size(view(adu));
  REQUIRE(size.is_complete());
  CHECK(size.value() == 8U);
  CHECK(size.consumed() == 0U);
  // protocol id 0x0100: not Modbus, though its low byte is 0
  const bytes other = {0x00, 0x01, 0x01, 0x00, 0x00, 0x02, 0x01, 0x07};
  CHECK(decode_tcp(view(other)).error() == errc::invalid_argument);
  CHECK(tcp_adu_size(view(other)).error() == errc::invalid_argument);
}
