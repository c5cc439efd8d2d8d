// motionbus — bit reversal and bounds-checked bit I/O over caller-owned words.
//
// A bit stream lives in an array of unsigned words (8, 16, 32 or 64 bits: a UART buffer, an
// SPI/DMA capture in 16- or 32-bit words). `bit_order` says how stream bits map onto a word:
//   msb_first  stream bit i is bit (W-1 - i%W) of word i/W   (SPI, BiSS, most captures)
//   lsb_first  stream bit i is bit (i%W)       of word i/W   (UART order, T-format fields)
// and, for a field of n bits, which end of the value comes first in the stream:
//   msb_first  the first stream bit is the field's most significant bit
//   lsb_first  the first stream bit is the field's least significant bit
// so an 8-bit field at a word boundary of a byte stream reads back as that byte in both orders.
//
// Reads and writes take 0..64 bits. Running past the end is an error (errc::truncated for the
// reader, errc::buffer_too_small for the writer) that leaves the position unchanged; a width
// above 64 is errc::invalid_argument. Nothing is ever accessed out of bounds.
#ifndef MOTIONBUS_CORE_BITS_HPP
#define MOTIONBUS_CORE_BITS_HPP

#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {

enum class bit_order : std::uint8_t { msb_first = 0, lsb_first = 1 };

namespace detail {

template <class Word>
constexpr unsigned word_bits = static_cast<unsigned>(std::numeric_limits<Word>::digits);

/// Mask of the low `count` bits, count 0..64.
constexpr std::uint64_t low_mask64(unsigned count) noexcept {
  return count >= 64U ? ~std::uint64_t{0} : ((std::uint64_t{1} << count) - 1U);
}

template <class Word>
constexpr void check_word_type() noexcept {
  static_assert(std::is_unsigned<Word>::value && std::is_integral<Word>::value &&
                    !std::is_same<Word, bool>::value && word_bits<Word> <= 64,
                "bit I/O words must be unsigned integers of at most 64 bits");
}

}  // namespace detail

/// Reverses the order of all bits of an unsigned word (bit 0 <-> bit W-1).
template <class Word>
constexpr Word reverse_bits(Word value) noexcept {
  detail::check_word_type<Word>();
  using wide = decltype(Word{} + 0U);  // Word, promoted to at least unsigned int
  wide out = 0;
  for (unsigned i = 0; i < detail::word_bits<Word>; ++i) {
    out = static_cast<wide>(out << 1U) | ((static_cast<wide>(value) >> i) & 1U);
  }
  return static_cast<Word>(out);
}

/// Reverses the order of the low `width` bits of `value` (width 0..64); higher bits are dropped.
constexpr std::uint64_t reverse_bits(std::uint64_t value, unsigned width) noexcept {
  std::uint64_t out = 0;
  const unsigned n = width > 64U ? 64U : width;
  for (unsigned i = 0; i < n; ++i) {
    out = (out << 1U) | ((value >> i) & 1U);
  }
  return out;
}

/// Leading zero bits of a 64-bit value (64 for 0).
constexpr unsigned countl_zero64(std::uint64_t v) noexcept {
  if (v == 0U) {
    return 64U;
  }
#if defined(__GNUC__) || defined(__clang__)
  return static_cast<unsigned>(__builtin_clzll(v));
#else
  unsigned n = 0;
  while ((v & (std::uint64_t{1} << 63U)) == 0U) {
    v <<= 1U;
    ++n;
  }
  return n;
#endif
}

/// Leading zero bits of a 32-bit value (32 for 0).
constexpr unsigned countl_zero32(std::uint32_t v) noexcept {
  if (v == 0U) {
    return 32U;
  }
#if (defined(__GNUC__) || defined(__clang__)) && __SIZEOF_INT__ == 4
  return static_cast<unsigned>(__builtin_clz(v));
#else
  return countl_zero64(v) - 32U;
#endif
}

/// Trailing zero bits of a 64-bit value (64 for 0).
constexpr unsigned countr_zero64(std::uint64_t v) noexcept {
  if (v == 0U) {
    return 64U;
  }
#if defined(__GNUC__) || defined(__clang__)
  return static_cast<unsigned>(__builtin_ctzll(v));
#else
  unsigned n = 0;
  while ((v & 1U) == 0U) {
    v >>= 1U;
    ++n;
  }
  return n;
#endif
}

/// Sequential, bounds-checked reader of a bit stream held in `Word`s.
template <class Word>
class basic_bit_reader {
 public:
  using word_type = Word;
  static constexpr unsigned bits_per_word = detail::word_bits<Word>;

  /// Reads the stream `words` in `order`, starting at bit `bit_offset` and ending after
  /// `bit_limit` bits of the words (default: all of them; a larger limit is clamped). An offset
  /// past the end leaves an empty reader. The reader refers to `words`: keep them alive.
  constexpr explicit basic_bit_reader(span<const Word> words,
                                      bit_order order = bit_order::msb_first,
                                      std::size_t bit_offset = 0,
                                      std::size_t bit_limit = static_cast<std::size_t>(-1)) noexcept
      : words_(words), order_(order) {
    detail::check_word_type<Word>();
    const std::size_t available = words.size() * bits_per_word;
    size_ = bit_limit < available ? bit_limit : available;
    pos_ = bit_offset < size_ ? bit_offset : size_;
  }

  constexpr bit_order order() const noexcept { return order_; }
  /// Index of the next bit to read, counted from the first bit of `words`.
  constexpr std::size_t position() const noexcept { return pos_; }
  /// Total bits readable (the end position).
  constexpr std::size_t size() const noexcept { return size_; }
  constexpr std::size_t remaining() const noexcept { return size_ - pos_; }

  /// Reads `count` (0..64) bits as a field in the reader's order and advances.
  constexpr result<std::uint64_t> read(unsigned count) noexcept {
    const result<std::uint64_t> r = peek(count);
    if (r.ok()) {
      pos_ += count;
    }
    return r;
  }

  /// Reads `count` (0..64) bits without advancing.
  constexpr result<std::uint64_t> peek(unsigned count) const noexcept {
    if (count > 64U) {
      return errc::invalid_argument;
    }
    if (count > remaining()) {
      return errc::truncated;
    }
    return extract(pos_, count);
  }

  constexpr result<bool> read_bit() noexcept {
    if (pos_ >= size_) {
      return errc::truncated;
    }
    const bool b = bit_at_unchecked(pos_);
    ++pos_;
    return b;
  }

  /// `count` (0..64) bits at absolute position `at`, independent of the read position.
  constexpr result<std::uint64_t> field_at(std::size_t at, unsigned count) const noexcept {
    if (count > 64U) {
      return errc::invalid_argument;
    }
    if (at > size_ || count > size_ - at) {
      return errc::truncated;
    }
    return extract(at, count);
  }

  /// The bit at absolute position `index` (independent of the read position).
  constexpr result<bool> bit_at(std::size_t index) const noexcept {
    if (index >= size_) {
      return errc::truncated;
    }
    return bit_at_unchecked(index);
  }

  /// Advances `count` bits; errc::truncated (position unchanged) past the end.
  constexpr errc skip(std::size_t count) noexcept {
    if (count > remaining()) {
      return errc::truncated;
    }
    pos_ += count;
    return errc::ok;
  }

  /// Returned by find() when no bit matches.
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);

  /// Index of the first bit equal to `value` among the `limit` bits from absolute position
  /// `from` (clipped to size()), or npos. Scans up to 64 bits per step (a count of leading
  /// zeros), not bit by bit. The read position does not change.
  constexpr std::size_t find(bool value, std::size_t from,
                             std::size_t limit = npos) const noexcept {
    if (from >= size_) {
      return npos;
    }
    const std::size_t end = limit >= size_ - from ? size_ : from + limit;
    std::size_t pos = from;
    while (pos < end) {
      const unsigned n = end - pos >= 64U ? 64U : static_cast<unsigned>(end - pos);
      std::uint64_t x = extract(pos, n);
      if (!value) {
        x = ~x & detail::low_mask64(n);
      }
      if (x != 0U) {
        return pos +
               (order_ == bit_order::msb_first ? countl_zero64(x << (64U - n)) : countr_zero64(x));
      }
      pos += n;
    }
    return npos;
  }

  /// Moves to absolute bit `position` (0..size()); errc::truncated beyond size().
  constexpr errc seek(std::size_t position) noexcept {
    if (position > size_) {
      return errc::truncated;
    }
    pos_ = position;
    return errc::ok;
  }

 private:
  constexpr bool bit_at_unchecked(std::size_t index) const noexcept {
    const Word w = words_[index / bits_per_word];
    const unsigned in_word = static_cast<unsigned>(index % bits_per_word);
    const unsigned shift = order_ == bit_order::msb_first ? bits_per_word - 1U - in_word : in_word;
    return ((w >> shift) & 1U) != 0U;
  }

  // Precondition: at + count <= size_, count <= 64. Takes whole runs of a word at a time.
  constexpr std::uint64_t extract(std::size_t at, unsigned count) const noexcept {
    std::uint64_t acc = 0;
    unsigned got = 0;
    while (got < count) {
      const std::size_t index = at + got;
      const unsigned in_word = static_cast<unsigned>(index % bits_per_word);
      const unsigned avail = bits_per_word - in_word;
      const unsigned take = (count - got) < avail ? (count - got) : avail;
      const std::uint64_t w = words_[index / bits_per_word];
      if (order_ == bit_order::msb_first) {
        const std::uint64_t chunk = (w >> (avail - take)) & detail::low_mask64(take);
        acc = take >= 64U ? chunk : ((acc << take) | chunk);
      } else {
        const std::uint64_t chunk = (w >> in_word) & detail::low_mask64(take);
        // coverage-branch: got < count <= 64 inside the loop: the guard of the shift never fires
        acc |= got >= 64U ? 0U : (chunk << got);
      }
      got += take;
    }
    return acc;
  }

  span<const Word> words_;
  bit_order order_;
  std::size_t size_ = 0;
  std::size_t pos_ = 0;
};

/// Sequential, bounds-checked writer of a bit stream into caller-owned `Word`s. Bits of the
/// words outside the written fields are left as they were.
template <class Word>
class basic_bit_writer {
 public:
  using word_type = Word;
  static constexpr unsigned bits_per_word = detail::word_bits<Word>;

  /// Writes into `words` in `order` from bit `bit_offset` (an offset past the end leaves a full
  /// writer). The writer refers to `words`: keep them alive while writing.
  constexpr explicit basic_bit_writer(span<Word> words, bit_order order = bit_order::msb_first,
                                      std::size_t bit_offset = 0) noexcept
      : words_(words), order_(order), size_(words.size() * bits_per_word) {
    detail::check_word_type<Word>();
    pos_ = bit_offset < size_ ? bit_offset : size_;
  }

  constexpr bit_order order() const noexcept { return order_; }
  constexpr std::size_t position() const noexcept { return pos_; }
  constexpr std::size_t size() const noexcept { return size_; }
  constexpr std::size_t remaining() const noexcept { return size_ - pos_; }

  /// Writes the low `count` (0..64) bits of `value` as a field in the writer's order. Higher
  /// bits of `value` are ignored. errc::buffer_too_small (nothing written) past the end.
  constexpr errc write(std::uint64_t value, unsigned count) noexcept {
    if (count > 64U) {
      return errc::invalid_argument;
    }
    if (count > remaining()) {
      return errc::buffer_too_small;
    }
    for (unsigned i = 0; i < count; ++i) {
      // i-th stream bit of the field: MSB first or LSB first.
      const unsigned bit_index = order_ == bit_order::msb_first ? count - 1U - i : i;
      put(pos_ + i, ((value >> bit_index) & 1U) != 0U);
    }
    pos_ += count;
    return errc::ok;
  }

  constexpr errc write_bit(bool bit) noexcept { return write(bit ? 1U : 0U, 1U); }

  /// Writes `count` copies of `bit` (e.g. idle or Ack runs); count may exceed 64.
  constexpr errc fill(bool bit, std::size_t count) noexcept {
    if (count > remaining()) {
      return errc::buffer_too_small;
    }
    for (std::size_t i = 0; i < count; ++i) {
      put(pos_ + i, bit);
    }
    pos_ += count;
    return errc::ok;
  }

 private:
  constexpr void put(std::size_t index, bool bit) noexcept {
    const unsigned in_word = static_cast<unsigned>(index % bits_per_word);
    const unsigned shift = order_ == bit_order::msb_first ? bits_per_word - 1U - in_word : in_word;
    Word& w = words_[index / bits_per_word];
    const Word mask = static_cast<Word>(Word{1} << shift);
    w = bit ? static_cast<Word>(w | mask) : static_cast<Word>(w & static_cast<Word>(~mask));
  }

  span<Word> words_;
  bit_order order_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

using bit_reader = basic_bit_reader<std::uint8_t>;
using bit_writer = basic_bit_writer<std::uint8_t>;

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_BITS_HPP
