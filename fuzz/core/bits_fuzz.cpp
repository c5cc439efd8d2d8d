// Bit I/O oracle: an input is a buffer plus a list of operations. Every write at any offset and
// width either succeeds, reads back exactly, puts each bit where the order's mapping says
// (bits.hpp) and leaves every other bit alone, or fails with
// buffer_too_small and changes nothing; every read past the end fails with truncated and moves
// nothing. Out-of-bounds accesses are caught by ASan.
#include <motionbus/core/bits.hpp>

#include <cstring>

#include "../fuzz_check.hpp"

namespace mb = motionbus;

namespace {

template <class Word>
void run(const std::uint8_t* ops, std::size_t ops_size, std::size_t buffer_words) {
  Word words[8] = {};
  Word before[8] = {};
  const std::size_t n = buffer_words % 9U;  // 0..8 words
  std::memcpy(words, ops, ops_size < sizeof words ? ops_size : sizeof words);
  const mb::span<Word> view(words, n);
  const std::size_t total = n * sizeof(Word) * 8U;
  for (std::size_t i = 0; i + 11U <= ops_size; i += 11U) {
    const mb::bit_order order =
        (ops[i] & 1U) != 0 ? mb::bit_order::lsb_first : mb::bit_order::msb_first;
    const unsigned count = ops[i + 1] % 70U;  // includes invalid widths 65..69
    const std::size_t at = ops[i + 2] % (total + 3U);
    std::uint64_t value = 0;
    std::memcpy(&value, ops + i + 3, sizeof value);
    std::memcpy(before, words, sizeof words);
    const std::size_t start = at < total ? at : total;  // an offset past the end is clamped

    mb::basic_bit_writer<Word> w(view, order, at);
    const mb::errc e = w.write(value, count);
    if (count > 64U) {
      MOTIONBUS_FUZZ_CHECK(e == mb::errc::invalid_argument);
      MOTIONBUS_FUZZ_CHECK(std::memcmp(before, words, sizeof words) == 0);
      continue;
    }
    if (start + count > total) {
      MOTIONBUS_FUZZ_CHECK(e == mb::errc::buffer_too_small);
      MOTIONBUS_FUZZ_CHECK(std::memcmp(before, words, sizeof words) == 0);
      mb::basic_bit_reader<Word> r(mb::span<const Word>(words, n), order, at);
      const auto got = r.read(count);
      MOTIONBUS_FUZZ_CHECK(!got.ok() && got.error() == mb::errc::truncated);
      MOTIONBUS_FUZZ_CHECK(r.position() == start);
      continue;
    }
    MOTIONBUS_FUZZ_CHECK(e == mb::errc::ok);
    const std::uint64_t mask =
        count == 64U ? ~std::uint64_t{0} : ((std::uint64_t{1} << count) - 1U);
    MOTIONBUS_FUZZ_CHECK(w.position() == start + count);
    mb::basic_bit_reader<Word> r(mb::span<const Word>(words, n), order, start);
    MOTIONBUS_FUZZ_CHECK(r.read(count).value() == (value & mask));
    // each bit of the field where the header's mapping puts it (bit_at; MSB first the field's
    // most significant bit comes first in the stream, LSB first its least significant)
    const mb::basic_bit_reader<Word> now(mb::span<const Word>(words, n), order);
    for (unsigned j = 0; j < count; ++j) {
      const unsigned from_value = order == mb::bit_order::msb_first ? count - 1U - j : j;
      MOTIONBUS_FUZZ_CHECK(now.bit_at(start + j).value() == (((value >> from_value) & 1U) != 0U));
    }
    // bits outside [at, at + count) unchanged, and the words past the view's n untouched: each
    // bit that changed, at its stream position (the order's own mapping: stream bit b is bit
    // W-1-(b%W) of word b/W MSB first, bit b%W LSB first), lies in the field. (Word by word:
    // reading every bit of the buffer through the reader after every operation made this
    // oracle most of the target's time.)
    constexpr unsigned word_bits = sizeof(Word) * 8U;
    for (std::size_t k = 0; k < 8U; ++k) {
      auto changed = static_cast<std::uint64_t>(static_cast<Word>(words[k] ^ before[k]));
      MOTIONBUS_FUZZ_CHECK(k < n || changed == 0U);
      for (; changed != 0U; changed &= changed - 1U) {
        const auto bit = static_cast<unsigned>(__builtin_ctzll(changed));
        const std::size_t b =
            k * word_bits + (order == mb::bit_order::msb_first ? word_bits - 1U - bit : bit);
        MOTIONBUS_FUZZ_CHECK(b >= start && b < start + count);
      }
    }
    // a byte-aligned 8-bit field reads back as the same byte in either order
    const mb::bit_order other =
        order == mb::bit_order::msb_first ? mb::bit_order::lsb_first : mb::bit_order::msb_first;
    if (sizeof(Word) == 1U && start % 8U == 0U && count == 8U) {
      mb::basic_bit_reader<Word> o(mb::span<const Word>(words, n), other, start);
      MOTIONBUS_FUZZ_CHECK(o.read(8).value() == (value & 0xFFU));
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  switch (data[0] % 4U) {
    case 0: run<std::uint8_t>(data + 2, size - 2, data[1]); break;
    case 1: run<std::uint16_t>(data + 2, size - 2, data[1]); break;
    case 2: run<std::uint32_t>(data + 2, size - 2, data[1]); break;
    default: run<std::uint64_t>(data + 2, size - 2, data[1]); break;
  }
  return 0;
}
