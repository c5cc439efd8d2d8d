// T-format at its edges: the encoder side's line decoder on short, unusable and corrupted
// requests, a response that is not the echo the receiver waited for, decode_response_for on
// a short response, and alarm symbols of undefined bits.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/line.hpp"
#include "motionbus/tformat/receiver.hpp"

using namespace motionbus;
using namespace motionbus::tformat;

namespace {

// The line samples of `fields` (10 bits each: start 0, 8 data bits LSB first, delimiter 1)
// after `idle` ones, MSB first in bytes.
std::vector<std::uint8_t> line_of(const std::vector<std::uint8_t>& fields, unsigned idle) {
  std::vector<bool> bits(idle, true);
  for (const std::uint8_t f : fields) {
    bits.push_back(false);
    for (unsigned b = 0; b < 8U; ++b) {
      bits.push_back(((f >> b) & 1U) != 0U);
    }
    bits.push_back(true);
  }
  bits.resize(bits.size() + 8U, true);
  std::vector<std::uint8_t> out((bits.size() + 7U) / 8U, 0xFF);
  for (std::size_t i = 0; i < bits.size(); ++i) {
    if (!bits[i]) {
      out[i / 8U] = static_cast<std::uint8_t>(out[i / 8U] & ~(0x80U >> (i % 8U)));
    }
  }
  return out;
}

}  // namespace

TEST_CASE("request line: too few bits, a CF with bad parity, a corrupted EEPROM request") {
  const std::uint8_t start_only[1] = {0xFE};  // ones, then a start bit in the last sample
  const auto r1 = decode_request_line(span<const std::uint8_t>(start_only, 1));
  CHECK(r1.is_incomplete());
  // CF of ID3 with its parity bit flipped: the sync code is right, so one field is taken and
  // the byte codec says which error it is
  const auto parity = line_of({0x1A ^ 0x80}, 2);
  const auto r2 = decode_request_line(span<const std::uint8_t>(parity.data(), parity.size()));
  CHECK(r2.error() == errc::tformat_parity);
  // IDD request with a wrong CRC: found on the line, refused by the byte codec
  const auto bad_crc = line_of({0xEA, 0x05, 0x00}, 2);
  const auto r3 = decode_request_line(span<const std::uint8_t>(bad_crc.data(), bad_crc.size()));
  CHECK(r3.error() == errc::crc_mismatch);
  CHECK(r3.expected() == (0xEAU ^ 0x05U));
  // nothing but idle ones: no frame
  const std::uint8_t idle[2] = {0xFF, 0xFF};
  CHECK(decode_request_line(span<const std::uint8_t>(idle, 2)).error() == errc::no_frame);
  // the first two fields of an EEPROM write only: incomplete
  const auto part = line_of({0x32, 0x05}, 2);
  const auto r4 = decode_request_line(span<const std::uint8_t>(part.data(), part.size() - 1U));
  CHECK(r4.is_incomplete());
}

TEST_CASE("receiver: bytes that are not the awaited echo are parsed as the response") {
  receiver_options opt;
  opt.echo_mode = echo::expected;
  receiver rx(opt);
  std::uint8_t req[4] = {};
  const std::size_t n = encode_request(data_id::eeprom_read, 5, 0, req).value();
  rx.sent(byte_view(req, n));
  // no echo on the line: the response comes straight away; its first two bytes equal the
  // request's (CF, ADF), the third does not
  std::vector<std::uint8_t> resp = {0xEA, 0x05, 0x77};
  std::uint8_t x = 0;
  for (const auto b : resp) {
    x = static_cast<std::uint8_t>(x ^ b);
  }
  resp.push_back(x);
  const auto r = rx.feed(byte_view(resp.data(), resp.size()));
  REQUIRE(r.is_complete());
  CHECK(r->edf == 0x77);
  CHECK(rx.echoes_skipped() == 0);
}

TEST_CASE("decode_response_for: a short response needs more input") {
  std::uint8_t req[1] = {};
  (void)encode_request(data_id::read_all, req);
  const std::uint8_t part[3] = {0x1A, 0x00, 0x00};
  const auto r = decode_response_for(byte_view(req, 1), byte_view(part, 3));
  CHECK(r.is_incomplete());
  CHECK(r.needed() == 8);
}

TEST_CASE("alarm symbols: an undefined bit value has none") {
  CHECK(std::strcmp(symbol(almc_bit::ba), "BA") == 0);
  CHECK(std::strcmp(symbol(static_cast<almc_bit>(0x03)), "??") == 0);
}
