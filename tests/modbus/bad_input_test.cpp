// Regression tests for the classes of input behind published Modbus CVEs (docs/modbus.md §4,
// "Counts against bytes"): count fields that disagree with the bytes present (FC 0F/10/17), the FC
// 17 write range, truncated PDUs, minimum-length FC 07/11 read as if they had an address, oversize
// ADUs, exceptions without CRC, frames for other slaves; plus every prefix and single-bit flip of
// valid RTU frames.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../support/bytes.hpp"
#include "motionbus/modbus.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

namespace {

errc request_error(const bytes& pdu) {
  return decode_request(byte_view(pdu.data(), pdu.size())).error();
}

struct null_device {
  std::uint8_t read_registers(std::uint8_t, std::uint16_t, span<std::uint16_t> out) {
    for (auto& r : out) {
      r = 0;
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t, span<const std::uint16_t>) { return 0; }
};

}  // namespace

TEST_CASE("CVE class: byte count larger than the bytes present (FC 0F, 10, 17)") {
  // the count claims 0xF6 bytes of data; only 4 follow
  CHECK(request_error({0x10, 0x00, 0x00, 0x00, 0x7B, 0xF6, 0x00, 0x01, 0x00, 0x02}) ==
        errc::modbus_byte_count);
  CHECK(request_error({0x0F, 0x00, 0x00, 0x07, 0xB0, 0xF6, 0xFF}) == errc::modbus_byte_count);
  CHECK(request_error({0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x79, 0xF2, 0x00, 0x01}) ==
        errc::modbus_byte_count);
  // byte count smaller than the quantity needs, with enough bytes present
  CHECK(request_error({0x10, 0x00, 0x00, 0x00, 0x02, 0x02, 0x00, 0x01, 0x00, 0x02}) ==
        errc::modbus_byte_count);
  // byte count 0 with a quantity
  CHECK(request_error({0x10, 0x00, 0x00, 0x00, 0x01, 0x00}) == errc::modbus_byte_count);
}

TEST_CASE("CVE class: FC 17 write range past 0xFFFF and write quantity limits") {
  CHECK(request_error({0x17, 0x00, 0x00, 0x00, 0x01, 0xFF, 0xFF, 0x00, 0x02, 0x04, 0, 1, 0, 2}) ==
        errc::modbus_address_overflow);
  CHECK(request_error({0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00}) ==
        errc::modbus_quantity);
  CHECK(request_error({0x17, 0xFF, 0xFF, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x02, 0, 1}) ==
        errc::modbus_address_overflow);
}

TEST_CASE("CVE class: truncated PDUs and minimum-length FC 07/11") {
  for (int fc : {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x10, 0x16, 0x17}) {
    const auto f = static_cast<std::uint8_t>(fc);
    CAPTURE(static_cast<int>(f));
    CHECK(request_error({f}) == errc::truncated);
    CHECK(request_error({f, 0x00}) == errc::truncated);
  }
  CHECK(decode_request(byte_view(bytes{0x07}.data(), 1)).is_complete());
  CHECK(request_error({0x07, 0x00, 0x01, 0x00, 0x01}) == errc::modbus_byte_count);
  CHECK(request_error({0x11, 0x00, 0x01}) == errc::modbus_byte_count);
  // a client must not read an FC11 byte count beyond the PDU
  const bytes req = {0x11};
  const bytes resp = {0x11, 0xFF, 0x01};
  CHECK(
      decode_response_for(byte_view(req.data(), 1), byte_view(resp.data(), resp.size())).error() ==
      errc::modbus_byte_count);
}

TEST_CASE("CVE class: oversize ADUs and PDUs") {
  std::vector<std::uint8_t> big(257, 0x01);
  CHECK(decode_rtu(byte_view(big.data(), big.size())).error() == errc::modbus_pdu_length);
  std::vector<std::uint8_t> pdu(254, 0x03);
  CHECK(request_error(pdu) == errc::modbus_pdu_length);
  // a stream of bytes never makes the framer hold more than one ADU
  rtu_framer f(framer_role::server, {1});
  std::vector<std::uint8_t> noise(4096, 0x10);
  byte_view in(noise.data(), noise.size());
  for (int guard = 0; guard < 10000; ++guard) {
    const auto r = f.feed(in);
    CHECK(f.pending() <= max_rtu_size);
    if (r.is_incomplete()) {
      break;
    }
    in = in.subspan(r.consumed());
  }
  // a TCP header announcing more than 254 bytes is refused
  const std::uint8_t mbap[] = {0x00, 0x01, 0x00, 0x00, 0x01, 0x00, 0x01};
  CHECK(decode_tcp(mbap).error() == errc::modbus_pdu_length);
}

TEST_CASE("CVE class: exceptions without CRC, frames for other slaves") {
  const std::uint8_t no_crc[] = {0x11, 0x83, 0x02};
  CHECK(decode_rtu(no_crc).error() == errc::modbus_pdu_length);
  const std::uint8_t bad_crc[] = {0x11, 0x83, 0x02, 0x00, 0x00};
  CHECK(decode_rtu(bad_crc).error() == errc::crc_mismatch);
  // a server answers nothing to a frame for another slave, valid or not
  null_device dev;
  std::uint8_t adu[256] = {};
  const std::uint8_t pdu[] = {0x03, 0x00, 0x00, 0x00, 0x01};
  const std::size_t n = encode_rtu(0x12, pdu, adu).value();
  std::uint8_t out[256] = {};
  CHECK(serve_rtu(dev, 0x11, byte_view(adu, n), out).value() == 0);
  CHECK(serve_rtu(dev, 0x12, byte_view(adu, n), out).value() > 0);
}

TEST_CASE("every prefix and every single-bit flip of valid RTU frames is rejected") {
  const std::vector<bytes> pdus = {{0x03, 0x00, 0x6B, 0x00, 0x03},
                                   {0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02},
                                   {0x83, 0x02},
                                   {0x11}};
  for (const auto& p : pdus) {
    std::uint8_t adu[256] = {};
    const std::size_t n = encode_rtu(0x11, byte_view(p.data(), p.size()), adu).value();
    for (std::size_t k = 0; k < n; ++k) {
      CHECK(decode_rtu(byte_view(adu, k)).is_failed());
    }
    for (std::size_t bit = 0; bit < n * 8U; ++bit) {
      adu[bit / 8U] = static_cast<std::uint8_t>(adu[bit / 8U] ^ (1U << (bit % 8U)));
      CAPTURE(bit);
      CHECK(decode_rtu(byte_view(adu, n)).is_failed());  // CRC-16 catches every 1-bit error
      adu[bit / 8U] = static_cast<std::uint8_t>(adu[bit / 8U] ^ (1U << (bit % 8U)));
    }
    CHECK(decode_rtu(byte_view(adu, n)).is_complete());
  }
}
