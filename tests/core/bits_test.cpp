// Bit I/O: reader and writer against a naive bit-by-bit model, every offset and width, both
// orders, 8/16/32/64-bit words; truncation and bad widths are errors that move nothing.
#include "motionbus/core/bits.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../support/prng.hpp"

using namespace motionbus;

namespace {

// Naive model: stream bit i of a word array in the given order.
template <class Word>
int model_bit(const std::vector<Word>& words, bit_order order, std::size_t i) {
  constexpr unsigned w = sizeof(Word) * 8U;
  const unsigned in_word = static_cast<unsigned>(i % w);
  const unsigned shift = order == bit_order::msb_first ? w - 1U - in_word : in_word;
  return static_cast<int>((words[i / w] >> shift) & 1U);
}

// Naive model of a field read: first stream bit is the MSB (msb_first) or LSB (lsb_first).
template <class Word>
std::uint64_t model_field(const std::vector<Word>& words, bit_order order, std::size_t at,
                          unsigned count) {
  std::uint64_t v = 0;
  for (unsigned k = 0; k < count; ++k) {
    const std::uint64_t b = static_cast<std::uint64_t>(model_bit(words, order, at + k));
    if (order == bit_order::msb_first) {
      v = (v << 1U) | b;
    } else {
      v |= b << k;
    }
  }
  return v;
}

template <class Word>
void reader_matches_model(bit_order order, std::uint64_t seed) {
  testutil::splitmix64 rng(seed);
  std::vector<Word> words(9);
  for (auto& w : words) {
    w = static_cast<Word>(rng.next());
  }
  const std::size_t total = words.size() * sizeof(Word) * 8U;
  for (std::size_t at = 0; at <= total; ++at) {
    for (unsigned count = 0; count <= 64U; ++count) {
      basic_bit_reader<Word> r(span<const Word>(words.data(), words.size()), order, at);
      const auto got = r.read(count);
      if (at + count <= total) {
        REQUIRE(got.ok());
        REQUIRE(got.value() == model_field(words, order, at, count));
        REQUIRE(r.position() == at + count);
      } else {
        REQUIRE(got.error() == errc::truncated);
        REQUIRE(r.position() == at);
      }
    }
  }
}

template <class Word>
void writer_round_trip(bit_order order, std::uint64_t seed) {
  testutil::splitmix64 rng(seed);
  for (int iteration = 0; iteration < 2000; ++iteration) {
    std::vector<Word> words(5);
    for (auto& w : words) {
      w = static_cast<Word>(rng.next());
    }
    const std::vector<Word> before = words;
    const std::size_t total = words.size() * sizeof(Word) * 8U;
    const std::size_t at = static_cast<std::size_t>(rng.below(total + 1));
    const unsigned count = static_cast<unsigned>(rng.below(65));
    const std::uint64_t value = rng.next();
    basic_bit_writer<Word> w(span<Word>(words.data(), words.size()), order, at);
    const errc e = w.write(value, count);
    if (at + count > total) {
      REQUIRE(e == errc::buffer_too_small);
      REQUIRE(words == before);
      REQUIRE(w.position() == at);
      continue;
    }
    REQUIRE(e == errc::ok);
    REQUIRE(w.position() == at + count);
    const std::uint64_t masked =
        count == 64U ? value : (value & ((std::uint64_t{1} << count) - 1U));
    REQUIRE(model_field(words, order, at, count) == masked);
    // every bit outside the field is untouched
    for (std::size_t i = 0; i < total; ++i) {
      if (i < at || i >= at + count) {
        REQUIRE(model_bit(words, order, i) == model_bit(before, order, i));
      }
    }
    basic_bit_reader<Word> r(span<const Word>(words.data(), words.size()), order, at);
    REQUIRE(r.read(count).value() == masked);
  }
}

}  // namespace

TEST_CASE("bit_reader matches the model at every offset and width") {
  for (bit_order order : {bit_order::msb_first, bit_order::lsb_first}) {
    reader_matches_model<std::uint8_t>(order, 11);
    reader_matches_model<std::uint16_t>(order, 12);
    reader_matches_model<std::uint32_t>(order, 13);
    reader_matches_model<std::uint64_t>(order, 14);
  }
}

TEST_CASE("bit_writer writes exactly the field and round-trips through the reader") {
  for (bit_order order : {bit_order::msb_first, bit_order::lsb_first}) {
    writer_round_trip<std::uint8_t>(order, 21);
    writer_round_trip<std::uint16_t>(order, 22);
    writer_round_trip<std::uint32_t>(order, 23);
    writer_round_trip<std::uint64_t>(order, 24);
  }
}

TEST_CASE("field order conventions") {
  const std::uint8_t bytes[] = {0x12, 0x34};
  bit_reader msb(bytes, bit_order::msb_first);
  CHECK(msb.read(16).value() == 0x1234);  // big-endian
  bit_reader lsb(bytes, bit_order::lsb_first);
  CHECK(lsb.read(16).value() == 0x3412);  // little-endian
  bit_reader m4(bytes, bit_order::msb_first);
  CHECK(m4.read(4).value() == 0x1);
  CHECK(m4.read(8).value() == 0x23);
  bit_reader l4(bytes, bit_order::lsb_first);
  CHECK(l4.read(4).value() == 0x2);
  CHECK(l4.read(8).value() == 0x41);
}

TEST_CASE("errors: bad width, truncation, limits, seek and skip") {
  const std::uint8_t bytes[] = {0xFF, 0x00, 0xAA};
  bit_reader r(bytes, bit_order::msb_first, 3, 20);  // bits 3..19
  CHECK(r.size() == 20);
  CHECK(r.remaining() == 17);
  CHECK(r.read(65).error() == errc::invalid_argument);
  CHECK(r.position() == 3);
  CHECK(r.peek(18).error() == errc::truncated);
  CHECK(r.peek(17).ok());
  CHECK(r.skip(18) == errc::truncated);
  CHECK(r.skip(17) == errc::ok);
  CHECK(r.read_bit().error() == errc::truncated);
  CHECK(r.read(0).ok());
  CHECK(r.seek(21) == errc::truncated);
  CHECK(r.seek(8) == errc::ok);
  CHECK(r.read_bit().value() == false);
  CHECK(r.bit_at(0).value() == true);
  CHECK(r.bit_at(20).error() == errc::truncated);

  bit_reader past(bytes, bit_order::msb_first, 1000);
  CHECK(past.remaining() == 0);
  CHECK(past.read(1).error() == errc::truncated);

  bit_reader empty(byte_view{});
  CHECK(empty.size() == 0);
  CHECK(empty.read(1).error() == errc::truncated);

  std::uint8_t out[2] = {0, 0};
  bit_writer w(out, bit_order::msb_first, 4);
  CHECK(w.write(0, 65) == errc::invalid_argument);
  CHECK(w.write(0xFFF, 13) == errc::buffer_too_small);
  CHECK(w.fill(true, 13) == errc::buffer_too_small);
  CHECK(w.fill(true, 12) == errc::ok);
  CHECK(out[0] == 0x0F);
  CHECK(out[1] == 0xFF);
  CHECK(w.write_bit(true) == errc::buffer_too_small);
  CHECK(w.write(0, 0) == errc::ok);
}

TEST_CASE("reverse_bits") {
  CHECK(reverse_bits(std::uint8_t{0x01}) == 0x80);
  CHECK(reverse_bits(std::uint8_t{0xA0}) == 0x05);
  CHECK(reverse_bits(std::uint16_t{0x0001}) == 0x8000);
  CHECK(reverse_bits(std::uint32_t{0x12345678}) == 0x1E6A2C48U);
  CHECK(reverse_bits(std::uint64_t{1}) == 0x8000000000000000ULL);
  CHECK(reverse_bits(0x3ULL, 6) == 0x30);
  CHECK(reverse_bits(0xFFULL, 4) == 0xF);  // bits above the width are dropped
  CHECK(reverse_bits(0x1ULL, 0) == 0);
  CHECK(reverse_bits(0x1ULL, 200) == 0x8000000000000000ULL);  // width clamped to 64
  testutil::splitmix64 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const auto v = static_cast<std::uint8_t>(rng.next());
    CHECK(reverse_bits(reverse_bits(v)) == v);
    const unsigned width = static_cast<unsigned>(rng.below(65));
    const std::uint64_t x = rng.next();
    const std::uint64_t masked = width == 64U ? x : (x & ((std::uint64_t{1} << width) - 1U));
    CHECK(reverse_bits(reverse_bits(x, width), width) == masked);
  }
}

TEST_CASE("leading zero counts of 32- and 64-bit values agree") {
  CHECK(countl_zero32(0) == 32);
  CHECK(countl_zero32(1) == 31);
  CHECK(countl_zero32(0x80000000U) == 0);
  for (unsigned k = 0; k < 32; ++k) {
    const std::uint32_t v = (std::uint32_t{1} << k) | (std::uint32_t{1} << (k / 2U));
    CHECK(countl_zero32(v) == countl_zero64(v) - 32U);
  }
}

TEST_CASE("countr_zero64: trailing zeros, 64 for zero") {
  CHECK(countr_zero64(0) == 64U);
  CHECK(countr_zero64(1) == 0U);
  CHECK(countr_zero64(std::uint64_t{1} << 63U) == 63U);
  CHECK(countr_zero64(0x28) == 3U);
}

TEST_CASE("bit reader find: 0s and 1s, MSB and LSB first, past 64 bits, not found") {
  // 96 bits: 70 ones, a zero at 70, ones to the end (MSB first); the same words read
  // LSB first put that zero at bit 70 - 64 + (31 - 6) ... computed below from the words.
  const std::uint32_t words[3] = {0xFFFFFFFFU, 0xFFFFFFFFU, 0xFDFFFFFFU};
  const basic_bit_reader<std::uint32_t> msb(span<const std::uint32_t>(words, 3));
  CHECK(msb.find(false, 0) == 70U);        // three 64-bit steps: the zero in the second
  CHECK(msb.find(false, 71) == msb.npos);  // ones to the end
  CHECK(msb.find(true, 0) == 0U);
  CHECK(msb.find(false, 0, 70) == msb.npos);  // limit stops before it
  CHECK(msb.find(false, 96) == msb.npos);     // from at the end
  const basic_bit_reader<std::uint32_t> lsb(span<const std::uint32_t>(words, 3),
                                            bit_order::lsb_first);
  CHECK(lsb.find(false, 0) == 64U + 25U);  // bit 25 of the third word, counted from its LSB
  CHECK(lsb.find(true, 89) == 90U);
  // field_at refusals
  CHECK(msb.field_at(0, 65).error() == errc::invalid_argument);
  CHECK(msb.field_at(90, 8).error() == errc::truncated);
  CHECK(msb.field_at(97, 0).error() == errc::truncated);
}

TEST_CASE("the end is a position: a zero-bit field at size(), seek(size())") {
  // Positions run 0..size() (seek's contract) and only a field that runs past the end is
  // truncated, so the empty field at size() is 0 and seek(size()) leaves nothing to read.
  const std::uint8_t bytes[] = {0xFF, 0x00, 0xAA};
  bit_reader r(bytes, bit_order::msb_first, 0, 20);
  const auto empty = r.field_at(20, 0);
  REQUIRE(empty.ok());
  CHECK(empty.value() == 0U);
  CHECK(r.field_at(21, 0).error() == errc::truncated);
  CHECK(r.seek(20) == errc::ok);
  CHECK(r.position() == 20U);
  CHECK(r.remaining() == 0U);
  CHECK(r.read_bit().error() == errc::truncated);
  CHECK(r.seek(0) == errc::ok);
  CHECK(r.read(8).value() == 0xFFU);
}

TEST_CASE("a bit_writer without an offset writes from the first bit") {
  std::uint8_t out[2] = {0x00, 0x00};
  bit_writer w(out);
  CHECK(w.order() == bit_order::msb_first);
  CHECK(w.position() == 0U);
  CHECK(w.remaining() == 16U);
  CHECK(w.write(0x5, 3) == errc::ok);  // 101 in the top three bits of the first byte
  CHECK(out[0] == 0xA0);
  CHECK(out[1] == 0x00);
  CHECK(w.position() == 3U);
}

TEST_CASE("bit_writer fill: the run and not a bit past it, longer than 64 bits too") {
  std::uint8_t ones[12] = {};  // 96 bits
  bit_writer msb(ones, bit_order::msb_first, 2);
  CHECK(msb.fill(true, 70) == errc::ok);  // stream bits 2..71: the top six of byte 0, bytes 1..8
  CHECK(msb.position() == 72U);
  CHECK(ones[0] == 0x3F);
  for (int i = 1; i <= 8; ++i) {
    CHECK(ones[i] == 0xFF);
  }
  CHECK(ones[9] == 0x00);  // stream bit 72, the first after the run, as it was
  CHECK(ones[10] == 0x00);
  CHECK(ones[11] == 0x00);

  std::uint8_t zeros[2] = {0xFF, 0xFF};
  bit_writer lsb(zeros, bit_order::lsb_first);
  CHECK(lsb.fill(false, 5) == errc::ok);  // bits 0..4 of byte 0, counted from its LSB
  CHECK(zeros[0] == 0xE0);
  CHECK(zeros[1] == 0xFF);
}
