// T-format line coding (raw bits): responses and requests found on the line at any line delay,
// in words of 8, 16 and 32 bits, MSB or LSB first; framing errors; frames cut short.
// Line bit patterns are built here by hand from the spec's field structure (start 0, 8 data
// bits LSB first, delimiter 1, idle 1), independently of encode_line.
#include "motionbus/tformat/line.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../support/bytes.hpp"
#include "motionbus/tformat/codec.hpp"

using namespace motionbus;
using namespace motionbus::tformat;

using testutil::with_crc;

namespace {

// Line bits of a frame as a list of 0/1, spec field structure, preceded by `idle` ones.
std::vector<int> line_bits(const std::vector<std::uint8_t>& frame, std::size_t idle) {
  std::vector<int> bits(idle, 1);
  for (std::uint8_t b : frame) {
    bits.push_back(0);
    for (unsigned i = 0; i < 8; ++i) {
      bits.push_back((b >> i) & 1U);
    }
    bits.push_back(1);
  }
  return bits;
}

// Packs bits into words in `order`, padding with idle ones.
template <class Word>
std::vector<Word> pack(const std::vector<int>& bits, bit_order order, std::size_t extra_words = 1) {
  constexpr std::size_t w = sizeof(Word) * 8U;
  std::vector<Word> words((bits.size() + w - 1U) / w + extra_words, static_cast<Word>(~Word{0}));
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const std::size_t shift = order == bit_order::msb_first ? w - 1U - i % w : i % w;
    const Word mask = static_cast<Word>(Word{1} << shift);
    if (bits[i] != 0) {
      words[i / w] = static_cast<Word>(words[i / w] | mask);
    } else {
      words[i / w] = static_cast<Word>(words[i / w] & static_cast<Word>(~mask));
    }
  }
  return words;
}

template <class Word>
void line_round_trip(bit_order order) {
  const auto frame = with_crc({0x1A, 0x20, 0x45, 0x23, 0x01, 0x11, 0x34, 0x12, 0x00, 0x80});
  for (std::size_t idle = 0; idle < 70; ++idle) {
    const auto bits = line_bits(frame, idle);
    const auto words = pack<Word>(bits, order);
    const auto r = decode_response_line(span<const Word>(words.data(), words.size()), order);
    CAPTURE(idle);
    REQUIRE(r.is_complete());
    CHECK(r->start_bit == idle);
    CHECK(r.consumed_bits() == idle + 110U);
    CHECK(r->frame.abs == 0x012345);
    CHECK(r->frame.abm == 0x1234);
    CHECK(r->frame.almc == 0x80);

    // encode_line writes the same bits
    std::vector<Word> out(words.size(), static_cast<Word>(~Word{0}));
    const auto n = encode_line(byte_view(frame.data(), frame.size()),
                               span<Word>(out.data(), out.size()), order, 0, idle);
    REQUIRE(n.ok());
    CHECK(n.value() == bits.size());
    CHECK(out == words);
  }
}

// The line samples of `fields` after `idle` ones, MSB first in bytes, with a byte of idle
// ones after them.
std::vector<std::uint8_t> line_of(const std::vector<std::uint8_t>& fields, unsigned idle) {
  return pack<std::uint8_t>(line_bits(fields, idle), bit_order::msb_first);
}

}  // namespace

TEST_CASE("line: responses found at any line delay, MSB/LSB-first, 8/16/32-bit words") {
  for (bit_order order : {bit_order::msb_first, bit_order::lsb_first}) {
    line_round_trip<std::uint8_t>(order);
    line_round_trip<std::uint16_t>(order);
    line_round_trip<std::uint32_t>(order);
  }
}

TEST_CASE("line: a 0 not followed by the sync code is skipped; framing errors are reported") {
  const auto frame = with_crc({0x02, 0x00, 0x01, 0x00, 0x00});
  // glitch: idle, a lone 0 followed by 1 1 1, then idle, then the frame
  std::vector<int> bits = {1, 1, 0, 1, 1, 1, 1, 1};
  const auto body = line_bits(frame, 3);
  bits.insert(bits.end(), body.begin(), body.end());
  auto words = pack<std::uint8_t>(bits, bit_order::msb_first);
  auto r = decode_response_line(span<const std::uint8_t>(words.data(), words.size()));
  REQUIRE(r.is_complete());
  CHECK(r->start_bit == 11);
  CHECK(r->frame.abs == 1);

  // a bad delimiter in the second field
  auto bad = line_bits(frame, 2);
  bad[2 + 19] = 0;
  words = pack<std::uint8_t>(bad, bit_order::msb_first);
  r = decode_response_line(span<const std::uint8_t>(words.data(), words.size()));
  CHECK(r.error() == errc::tformat_delimiter);
  CHECK(r.consumed_bits() == 2 + 20);
  // a bad start bit in the third field
  bad = line_bits(frame, 2);
  bad[2 + 20] = 1;
  words = pack<std::uint8_t>(bad, bit_order::msb_first);
  r = decode_response_line(span<const std::uint8_t>(words.data(), words.size()));
  CHECK(r.error() == errc::tformat_start_bit);
  // a CRC error surfaces from the byte codec
  auto crc_bad = frame;
  crc_bad[5] ^= 1;
  words = pack<std::uint8_t>(line_bits(crc_bad, 5), bit_order::msb_first);
  r = decode_response_line(span<const std::uint8_t>(words.data(), words.size()));
  CHECK(r.error() == errc::crc_mismatch);
  // idle only: no frame
  const std::vector<std::uint8_t> idle(8, 0xFF);
  r = decode_response_line(span<const std::uint8_t>(idle.data(), idle.size()));
  CHECK(r.error() == errc::no_frame);
  CHECK(r.consumed_bits() == 64);
}

TEST_CASE("line: every truncation of a frame needs more bits") {
  const auto frame = with_crc({0x92, 0x00, 0x11});
  const auto bits = line_bits(frame, 7);
  const auto words = pack<std::uint8_t>(bits, bit_order::lsb_first, 0);
  for (std::size_t n = 11; n < bits.size(); ++n) {  // from just after the start bit + sync
    const auto r = decode_response_line(span<const std::uint8_t>(words.data(), words.size()),
                                        bit_order::lsb_first, n);
    CAPTURE(n);
    CHECK(r.is_incomplete());
  }
  CHECK(decode_response_line(span<const std::uint8_t>(words.data(), words.size()),
                             bit_order::lsb_first, bits.size())
            .is_complete());
}

TEST_CASE("line: requests encoded and decoded at the encoder side") {
  for (data_id id : {data_id::read_abs, data_id::read_all, data_id::eeprom_write,
                     data_id::eeprom_read, data_id::reset_multi_turn}) {
    std::uint8_t req[4] = {};
    const std::size_t n = encode_request(id, 77, 0x3C, req).value();
    std::uint32_t words[3] = {};
    const auto bits =
        encode_line(byte_view(req, n), span<std::uint32_t>(words, 3), bit_order::msb_first, 0, 13);
    REQUIRE(bits.ok());
    const auto q = decode_request_line(span<const std::uint32_t>(words, 3), bit_order::msb_first,
                                       bits.value());
    REQUIRE(q.is_complete());
    CHECK(q->frame.id == id);
    CHECK(q->start_bit == 13);
    if (id == data_id::eeprom_write) {
      CHECK(q->frame.address == 77);
      CHECK(q->frame.edf == 0x3C);
    }
  }
  std::uint8_t tiny[1] = {};
  const std::uint8_t cf[] = {0x02};
  CHECK(encode_line(byte_view(cf), span<std::uint8_t>(tiny, 1)).error() == errc::buffer_too_small);
}
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

TEST_CASE("encode_line: a bit offset past the words is refused, as a frame too long is") {
  const std::uint8_t cf[] = {0x02};
  std::uint8_t words[2] = {};
  CHECK(encode_line(byte_view(cf), span<std::uint8_t>(words, 2), bit_order::msb_first, 6).ok());
  CHECK(
      encode_line(byte_view(cf), span<std::uint8_t>(words, 2), bit_order::msb_first, 17).error() ==
      errc::buffer_too_small);
  CHECK(encode_line(byte_view(cf), span<std::uint8_t>(words, 2), bit_order::msb_first, 7).error() ==
        errc::buffer_too_small);
}

TEST_CASE(
    "request line: a start bit whose sync code breaks at its second or third bit is skipped") {
  // 1111 0001: a start bit, then 0 0 1 (the sync code 010 broken at its second bit); 1111 0011:
  // 0 1 1 (broken at its third); the request behind either is found
  for (const std::uint8_t lead : {std::uint8_t{0xF1}, std::uint8_t{0xF3}}) {
    CAPTURE(lead);
    std::vector<std::uint8_t> bits = line_of({0x1A}, 2);
    bits.insert(bits.begin(), lead);
    const auto r = decode_request_line(span<const std::uint8_t>(bits.data(), bits.size()));
    REQUIRE(r.is_complete());
    CHECK(r->frame.id == data_id::read_all);
  }
}

TEST_CASE("encode_line: by default MSB first from the first bit, with no idle before the frame") {
  const std::vector<std::uint8_t> frame = {0x1A};
  const auto expected = line_of(frame, 0);  // the frame's bits from bit 0, idle ones after
  std::vector<std::uint8_t> out(expected.size(), 0xFF);
  const auto n = encode_line(byte_view(frame.data(), frame.size()),
                             span<std::uint8_t>(out.data(), out.size()));
  REQUIRE(n.ok());
  CHECK(n.value() == field_bits);
  CHECK(out == expected);
}

TEST_CASE("encode_line: an empty frame at the end of the words writes nothing and succeeds") {
  std::uint8_t words[2] = {0xA5, 0x5A};
  const auto n =
      encode_line(byte_view{}, span<std::uint8_t>(words, 2), bit_order::msb_first, 16, 0);
  REQUIRE(n.ok());
  CHECK(n.value() == 0);
  CHECK(words[0] == 0xA5);
  CHECK(words[1] == 0x5A);
  // one idle bit there is past the words
  CHECK(
      encode_line(byte_view{}, span<std::uint8_t>(words, 2), bit_order::msb_first, 16, 1).error() ==
      errc::buffer_too_small);
}

TEST_CASE("line_frame: a default one, and a failed decode's value, start at bit 0") {
  const line_frame<response> f;
  CHECK(f.start_bit == 0);
  CHECK(f.frame.abs == 0);
  const std::uint8_t idle[2] = {0xFF, 0xFF};
  const auto r = decode_response_line(span<const std::uint8_t>(idle, 2));
  REQUIRE(r.error() == errc::no_frame);
  CHECK(r->start_bit == 0);
  const auto q = decode_request_line(span<const std::uint8_t>(idle, 2));
  REQUIRE(q.error() == errc::no_frame);
  CHECK(q->start_bit == 0);
}

TEST_CASE("line: a start bit and the sync code with nothing after need the rest of the CF field") {
  // 1111 0010: idle, the start bit at sample 4, the sync code 010 in samples 5 to 7: the CF's
  // field (10 bits from its start bit) needs 6 more
  const std::uint8_t head[1] = {0xF2};
  const auto r = decode_response_line(span<const std::uint8_t>(head, 1));
  REQUIRE(r.is_incomplete());
  CHECK(r.needed_bits() == 6);
  const auto q = decode_request_line(span<const std::uint8_t>(head, 1));
  REQUIRE(q.is_incomplete());
  CHECK(q.needed_bits() == 6);
}

TEST_CASE("line: a CF with bad parity or an unknown Data ID is one field: consumed to its end") {
  const std::uint8_t id4_cf = control_field(std::uint8_t{4});
  for (const std::uint8_t cf : {std::uint8_t{0x1A ^ 0x80}, id4_cf}) {
    CAPTURE(static_cast<int>(cf));
    const auto bits = line_of({cf}, 3);
    const auto r = decode_response_line(span<const std::uint8_t>(bits.data(), bits.size()));
    REQUIRE(r.is_failed());
    CHECK(r.error() == (cf == id4_cf ? errc::tformat_unknown_data_id : errc::tformat_parity));
    CHECK(r.consumed_bits() == 3U + field_bits);
    const auto q = decode_request_line(span<const std::uint8_t>(bits.data(), bits.size()));
    REQUIRE(q.is_failed());
    CHECK(q.error() == r.error());
    CHECK(q.consumed_bits() == 3U + field_bits);
  }
}

TEST_CASE("request line: a request from the very first sample is found (no idle before it)") {
  const auto bits = line_of({0x1A}, 0);
  const auto q = decode_request_line(span<const std::uint8_t>(bits.data(), bits.size()));
  REQUIRE(q.is_complete());
  CHECK(q->frame.id == data_id::read_all);
  CHECK(q->start_bit == 0);
  CHECK(q.consumed_bits() == field_bits);
}
