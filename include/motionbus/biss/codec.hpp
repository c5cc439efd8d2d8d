// motionbus — BiSS-C sensor data: decoder of raw SL captures (master side) and encoder of SL
// bit streams (slave side: emulators, test benches).
//
// Captures are sequences of 8/16/32/64-bit words, one sample per bit, first sample in the most
// significant bit (SPI order; bit_order::lsb_first is accepted too), starting at any sample
// from the first clock. The decoder finds the Ack as the first 0 and the Start bit as the
// first 1 after it: it never assumes the Ack length or the CDS value and never looks for a
// fixed pattern (docs/biss.md §5). Bits after the last CRC are ignored.
//
// The words are given as span<const Word>, span<Word> or a plain array (Word deduced from
// each, as the Modbus and T-format decoders take arrays).
//
// Outcomes of decode_frame, a frame_result<N> (decode_result counted in bits):
//   complete      chain_frame<N>: line delay, Start bit index, Ack length, CDS and every
//                 slave's fields (N = 1 for one layout, N for an array of N layouts,
//                 max_chain for a chain given as a span);
//                 consumed_bits() = bits up to the end of the last CRC
//   need input    the capture ends before the frame does (truncated), or before a bound
//                 was reached with no Ack / no Start yet; needed_bits() more at least
//   failed        biss_no_ack (only 1s over max_line_delay + 1 samples), biss_no_start (only 0s
//                 over max_ack_bits after the first 0), crc_mismatch (the first slave whose
//                 CRC fails: expected() is the CRC its data calls for, received() the CRC
//                 sent; consumed_bits() the frame), biss_layout, invalid_argument (empty
//                 chain, or longer than max_chain)
// An active nE or nW is device status (slave_data::error()/warning()), not a decode failure.
#ifndef MOTIONBUS_BISS_CODEC_HPP
#define MOTIONBUS_BISS_CODEC_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "motionbus/biss/frame.hpp"
#include "motionbus/core/bits.hpp"
#include "motionbus/core/config.hpp"
#include "motionbus/core/crc.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {
namespace biss {

/// Search bounds of the decoder.
struct decode_options {
  /// Idle (1) samples accepted before the Ack's first 0: the longest line delay, in bits.
  std::size_t max_line_delay = 64;
  /// Ack (0) samples accepted before the Start bit (the slave's processing time).
  /// Both bounds are in samples; a longer run fails rather than waiting for more input.
  std::size_t max_ack_bits = 256;
};

namespace detail {

// Any CRC format, bit by bit from its run-time parameters (kept out of the inlined fast path).
constexpr std::uint32_t dynamic_wire_crc(const crc_format& f, std::uint64_t data,
                                         unsigned data_bits, std::uint32_t status,
                                         unsigned status_bits) noexcept {
  dynamic_crc c(f.parameters());
  c.update_bits(data, data_bits).update_bits(status, status_bits);
  return c.value();
}

}  // namespace detail

/// The wire value of the CRC over `data` (data_bits) followed by `status` (status_bits), as a
/// slave sends it. The CRC6 0x43 used by nearly every encoder takes a compile-time table of
/// `Table` size; any other format is computed bit by bit from its run-time parameters.
// inline: with the caller's constant format it folds to the table steps alone.
template <crc_table_size Table = default_crc_table>
MOTIONBUS_INLINE constexpr std::uint32_t wire_crc(const crc_format& f, std::uint64_t data,
                                                  unsigned data_bits, std::uint32_t status,
                                                  unsigned status_bits) noexcept {
  if (f.width == 0U) {
    return 0;
  }
  if (f.width == 6U && f.poly == 0x03U && f.start == 0U) {
    auto c = crc6_biss<Table>();
    if (data_bits + status_bits <= 64U) {  // one field: one sliced step where tables allow
      c.update_bits(status_bits == 0U ? data : ((data << status_bits) | status),
                    data_bits + status_bits);
    } else {
      c.update_bits(data, data_bits).update_bits(status, status_bits);
    }
    return f.inverted ? c.value() : (c.value() ^ 0x3FU);
  }
  return detail::dynamic_wire_crc(f, data, data_bits, status, status_bits);
}

namespace detail {

// Validates a chain and returns its bits after CDS (0 on error, with `e` set).
// inline: a constant one-slave chain folds to a constant.
MOTIONBUS_INLINE constexpr std::size_t checked_chain_bits(span<const slave_layout> chain,
                                                          errc& e) noexcept {
  std::size_t bits = 0;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const errc v = chain[i].validate();
    if (v != errc::ok) {
      e = v;
      return 0;
    }
    bits += chain[i].frame_bits();
  }
  e = errc::ok;
  return bits;
}

}  // namespace detail

namespace detail {

// decode_frame into a chain_frame<N> (chain.size() <= N).
// inline, although long (the one exception to the policy, docs/design.md): a layout
// known at the call site folds its checks, field offsets and CRC choice away; out of line,
// the ABSYS decode costs several times as many instructions (meter: biss.decode_frame.absys64).
template <crc_table_size Table, std::size_t N, class Word>
MOTIONBUS_INLINE constexpr frame_result<N> decode_chain(span<const Word> words,
                                                        std::size_t bit_count,
                                                        span<const slave_layout> chain,
                                                        const decode_options& opt,
                                                        bit_order order) noexcept {
  // Every exit settles `result` through `o` and returns it: the frame is filled in place
  // (no copy of up to max_chain slaves).
  // The starting result, overwritten by every exit. It is the caller's object (the return
  // slot), so its starting stores stay: for one slave the default (all zeros, "1 more bit
  // needed"), stored from one zero register; for a chain from a run-time count (a constant
  // one lets GCC clear the whole object first).
  frame_result<N> result = N == 1U ? frame_result<N>{} : frame_result<N>(need_input{chain.size()});
  typename frame_result<N>::outcome o(result);
  if (chain.empty() || chain.size() > N) {
    o.fail(errc::invalid_argument, 0);
    return result;
  }
  errc layout_error = errc::ok;
  const std::size_t frame_bits = detail::checked_chain_bits(chain, layout_error);
  if (layout_error != errc::ok) {
    o.fail(layout_error, 0);
    return result;
  }
  const basic_bit_reader<Word> r(words, order, 0, bit_count);
  const std::size_t size = r.size();
  // Fields go MSB first on the wire; an LSB-first capture returns them reversed.
  const auto field = [&r, order](std::size_t at, unsigned n) {
    const std::uint64_t v = r.field_at(at, n).value();
    return order == bit_order::msb_first ? v : reverse_bits(v, n);
  };
  // The first (up to) 64 samples, left-aligned, zeros past the capture: the Ack, the Start
  // bit and a whole short frame are found in this one word with leading-zero counts.
  const unsigned n0 = size >= 64U ? 64U : static_cast<unsigned>(size);
  std::uint64_t win = 0;
  constexpr unsigned word_bits = basic_bit_reader<Word>::bits_per_word;
  // (64-bit words take the last branch; `step` only keeps their dead shifts below 64.)
  constexpr unsigned step = word_bits <= 32U ? word_bits : 32U;
  if (order == bit_order::msb_first && n0 == 64U && word_bits <= 32U) {
    for (unsigned k = 0; k < 64U / step; ++k) {  // whole words: no per-bit work
      win = (win << step) | words[k];
    }
  } else if (order == bit_order::msb_first && word_bits <= 32U) {  // a shorter capture
    // The samples past the capture stay in the window: every use below is bounded by n0 (an
    // Ack or Start found at or past n0 is none, fields are taken from it only when the frame
    // ends within n0).
    for (unsigned k = 0; k < 64U / step; ++k) {
      win = (win << step) | (k < words.size() ? static_cast<std::uint64_t>(words[k]) : 0U);
    }
  } else if (n0 != 0U) {
    win = field(0, n0) << (64U - n0);
  }
  // Ack: the first 0 within max_line_delay + 1 samples.
  // (The window's high word first: with a short line delay the Ack, and the Start bit after it,
  // are there, and 32-bit counts and shifts do.)
  const auto high = static_cast<std::uint32_t>(win >> 32U);
  std::size_t ack = 0;         // leading ones, at most n0
  std::uint32_t from_ack = 0;  // the high word from the Ack on (0: the Ack is not in it)
  if (MOTIONBUS_FAST_CLZ != 0 && high != 0xFFFFFFFFU) {
    ack = countl_zero32(~high);
    from_ack = high << ack;
  } else {
    ack = countl_zero64(~win);
  }
  if (ack >= n0) {  // no 0 in the window: search on past it
    ack = n0 == 64U && opt.max_line_delay >= 64U ? r.find(false, 64, opt.max_line_delay - 63U)
                                                 : r.npos;
  }
  if (ack == r.npos || ack > opt.max_line_delay) {
    if (size > opt.max_line_delay) {
      o.fail(errc::biss_no_ack, size);
      return result;
    }
    o.need(1);
    return result;
  }
  // Start: the first 1 after the Ack began, within max_ack_bits + 1 samples.
  std::size_t start = r.npos;
  if (ack < n0) {
    // Zeros from the Ack on (padding too): in the high word when the Start bit is there too.
    const std::size_t k = from_ack != 0U ? countl_zero32(from_ack) : countl_zero64(win << ack);
    if (ack + k < n0) {
      start = ack + k;
    }
  }
  if (start == r.npos && n0 == 64U && size > 64U) {  // search on past the window
    const std::size_t from = ack > 64U ? ack : 64U;
    if (from - ack <= opt.max_ack_bits) {
      start = r.find(true, from, opt.max_ack_bits + 1U - (from - ack));
    }
  }
  if (start == r.npos || start - ack > opt.max_ack_bits) {
    if (size - ack > opt.max_ack_bits) {
      o.fail(errc::biss_no_start, size);
      return result;
    }
    o.need(1);
    return result;
  }
  const std::size_t end = start + 2U + frame_bits;
  if (end > size) {
    o.need(end - size);
    return result;
  }
  chain_frame<N>& info = o.complete_in_place(end);
  info.line_delay = ack;
  info.start = start;
  if constexpr (N > 1U) {
    info.count = chain.size();
  }
  for (std::size_t i = chain.size(); i < N; ++i) {  // complete_in_place sets no member
    info.slaves[i] = slave_data{};
  }
  // The window from the CDS bit on (when the CDS bit is in it): the CDS bit, then the first
  // slave's fields, from one shift.
  const std::uint64_t from_cds = start + 1U < n0 ? win << (start + 1U) : 0U;
  info.cds = start + 1U < n0 ? (from_cds >> 63U) != 0U : field(start + 1U, 1) != 0U;
  bool bad = false;  // the first slave whose CRC fails, as evidence
  std::uint32_t bad_expected = 0;
  std::uint32_t bad_received = 0;
  const bool in_window = end <= n0;
  std::size_t pos = start + 2U;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const slave_layout& l = chain[i];
    slave_data& d = info.slaves[i];
    const unsigned db = l.data_bits();
    const unsigned sb = l.status_bits();
    const unsigned cb = l.crc.width;
    std::uint32_t status = 0;
    if (in_window) {  // pos < 64 and pos + n <= 64 for every field here
      // The slave's fields left-aligned by one shift, then split at the layout's offsets.
      const std::uint64_t fields = i == 0U ? from_cds << 1U : win << pos;
      const auto take = [fields](unsigned at, unsigned n) {
        return n == 0U ? std::uint64_t{0} : ((fields << at) >> (64U - n));
      };
      d.data = take(0, db);
      status = static_cast<std::uint32_t>(take(db, sb));
      d.crc = static_cast<std::uint32_t>(take(db + sb, cb));
    } else if (l.frame_bits() <= 64U) {  // the slave's fields in one read, split by shifts
      const unsigned fb = l.frame_bits();
      const std::uint64_t all = field(pos, fb) << (64U - fb);
      const auto take = [all](unsigned at, unsigned n) {
        return n == 0U ? std::uint64_t{0} : ((all << at) >> (64U - n));
      };
      d.data = take(0, db);
      status = static_cast<std::uint32_t>(take(db, sb));
      d.crc = static_cast<std::uint32_t>(take(db + sb, cb));
    } else {
      d.data = field(pos, db);
      status = static_cast<std::uint32_t>(field(pos + db, sb));
      d.crc = static_cast<std::uint32_t>(field(pos + db + sb, cb));
    }
    pos += l.frame_bits();
    d.ne = l.has_error ? (((status >> (l.has_warning ? 1U : 0U)) & 1U) != 0U) : true;
    d.nw = l.has_warning ? ((status & 1U) != 0U) : true;
    d.crc_computed = wire_crc<Table>(l.crc, d.data, db, status, sb);
    const std::uint64_t value = l.alignment_bits >= 64U ? 0U : (d.data >> l.alignment_bits);
    d.single_turn = l.single_turn_bits >= 64U
                        ? value
                        : value & motionbus::detail::low_mask64(l.single_turn_bits);
    d.multi_turn = l.single_turn_bits >= 64U ? 0U : (value >> l.single_turn_bits);
    if (!d.crc_ok() && !bad) {
      bad = true;
      bad_expected = d.crc_computed;
      bad_received = d.crc;
    }
  }
  if (bad) {
    o.fail(errc::crc_mismatch, end, bad_expected, bad_received);
  }
  return result;
}

}  // namespace detail

namespace detail {

// The capture as span<const Word>, from a span<const Word>, a span<Word> or a plain array.
template <class Word>
constexpr span<const Word> capture_words(span<const Word> words) noexcept {
  return words;
}
template <class Word, class = std::enable_if_t<!std::is_const<Word>::value>>
constexpr span<const Word> capture_words(span<Word> words) noexcept {
  return span<const Word>(words);
}
template <class Word, std::size_t N>
constexpr span<const Word> capture_words(const Word (&words)[N]) noexcept {
  return span<const Word>(words, N);
}
template <class Words>
using capture_word_t = typename decltype(capture_words(std::declval<const Words&>()))::value_type;

}  // namespace detail

/// Decodes the sensor data frame of a chain from a raw SL capture of `bit_count` samples
/// (clipped to the words given): a span<const Word>, a span<Word> or a plain array of Word.
/// See the file comment for the outcomes.
// inline: hands the caller's constant layouts on to decode_chain, which folds them.
template <crc_table_size Table = default_crc_table, class Words,
          class Word = detail::capture_word_t<Words>>
MOTIONBUS_INLINE constexpr frame_result<max_chain> decode_frame(
    const Words& words, std::size_t bit_count, span<const slave_layout> chain,
    const decode_options& opt = {}, bit_order order = bit_order::msb_first) noexcept {
  return detail::decode_chain<Table, max_chain, Word>(detail::capture_words(words), bit_count,
                                                      chain, opt, order);
}

/// Fixed-chain form: a chain known at compile time as an array of N layouts gives a
/// chain_frame<N>, sized by the chain (no unused slots to clear and return).
// inline: as the chain form.
template <crc_table_size Table = default_crc_table, class Words, std::size_t N,
          class Word = detail::capture_word_t<Words>>
MOTIONBUS_INLINE constexpr frame_result<N> decode_frame(
    const Words& words, std::size_t bit_count, const slave_layout (&chain)[N],
    const decode_options& opt = {}, bit_order order = bit_order::msb_first) noexcept {
  return detail::decode_chain<Table, N, Word>(detail::capture_words(words), bit_count,
                                              span<const slave_layout>(chain, N), opt, order);
}

/// Single-slave form: the slave's data is `slaves[0]`.
// inline: as the chain form.
template <crc_table_size Table = default_crc_table, class Words,
          class Word = detail::capture_word_t<Words>>
MOTIONBUS_INLINE constexpr frame_result<1> decode_frame(
    const Words& words, std::size_t bit_count, const slave_layout& layout,
    const decode_options& opt = {}, bit_order order = bit_order::msb_first) noexcept {
  return detail::decode_chain<Table, 1, Word>(detail::capture_words(words), bit_count,
                                              span<const slave_layout>(&layout, 1), opt, order);
}

// ---------------------------------------------------------------------------------------------
// Slave side

/// What a slave reports in one frame.
struct slave_values {
  std::uint64_t multi_turn = 0;
  std::uint64_t single_turn = 0;  ///< the position for single-turn layouts such as ABSYS
  bool ne = true;                 ///< nE line level (false: error active)
  bool nw = true;                 ///< nW line level (false: warning active)
};

/// The SL line around the frame.
struct line_options {
  std::size_t line_delay = 0;    ///< 1s before the Ack: the line delay, in samples
  std::size_t ack_bits = 1;      ///< Ack length, at least 1
  bool cds = false;              ///< the CDS bit
  std::size_t timeout_bits = 0;  ///< 0s after the last CRC (the slave's timeout)
};

/// Bits encode_frame writes for a chain and line options (0 when a layout is invalid).
constexpr std::size_t encoded_bits(span<const slave_layout> chain,
                                   const line_options& line) noexcept {
  errc e = errc::ok;
  const std::size_t bits = detail::checked_chain_bits(chain, e);
  if (e != errc::ok) {
    return 0;
  }
  return line.line_delay + line.ack_bits + 2U + bits + line.timeout_bits;
}

/// Writes the SL samples of one frame into `out` from bit `bit_offset`: the line delay (idle
/// 1s), Ack, Start, CDS,
/// then each slave's data (values that do not fit their fields are errc::out_of_range), nE,
/// nW and CRC, then the timeout. Returns the bits written. Errors write nothing:
/// invalid_argument (empty or mismatched chain/values, Ack length 0), biss_layout,
/// out_of_range, buffer_too_small.
template <crc_table_size Table = default_crc_table, class Word>
constexpr result<std::size_t> encode_frame(span<const slave_layout> chain,
                                           span<const slave_values> values, span<Word> out,
                                           const line_options& line = {},
                                           bit_order order = bit_order::msb_first,
                                           std::size_t bit_offset = 0) noexcept {
  if (chain.empty() || chain.size() > max_chain || values.size() != chain.size() ||
      line.ack_bits == 0U) {
    return errc::invalid_argument;
  }
  errc e = errc::ok;
  const std::size_t frame_bits = detail::checked_chain_bits(chain, e);
  if (e != errc::ok) {
    return e;
  }
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const slave_layout& l = chain[i];
    const bool st_fits =
        l.single_turn_bits >= 64U || (values[i].single_turn >> l.single_turn_bits) == 0U;
    const bool mt_fits =
        l.multi_turn_bits >= 64U || (values[i].multi_turn >> l.multi_turn_bits) == 0U;
    if (!st_fits || !mt_fits) {
      return errc::out_of_range;
    }
  }
  basic_bit_writer<Word> w(out, order, bit_offset);
  const std::size_t total = line.line_delay + line.ack_bits + 2U + frame_bits + line.timeout_bits;
  if (bit_offset > w.size() || total > w.remaining()) {
    return errc::buffer_too_small;
  }
  const auto put = [&w, order](std::uint64_t v, unsigned n) {
    (void)w.write(order == bit_order::msb_first ? v : reverse_bits(v, n), n);
  };
  (void)w.fill(true, line.line_delay);
  (void)w.fill(false, line.ack_bits);
  put(line.cds ? 0x3U : 0x2U, 2);  // Start 1, CDS
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const slave_layout& l = chain[i];
    const slave_values& v = values[i];
    const unsigned db = l.data_bits();
    const unsigned sb = l.status_bits();
    // data = multi-turn : single-turn : alignment zeros (each part < 64 bits, validated)
    std::uint64_t data = l.multi_turn_bits == 0U ? 0U : v.multi_turn;
    data =
        l.single_turn_bits >= 64U ? v.single_turn : ((data << l.single_turn_bits) | v.single_turn);
    data = l.alignment_bits >= 64U ? 0U : (data << l.alignment_bits);
    std::uint32_t status = 0;
    if (l.has_error) {
      status = v.ne ? 1U : 0U;
    }
    if (l.has_warning) {
      status = (status << 1U) | (v.nw ? 1U : 0U);
    }
    put(data, db);
    put(status, sb);
    put(wire_crc<Table>(l.crc, data, db, status, sb), l.crc.width);
  }
  (void)w.fill(false, line.timeout_bits);
  return total;
}

/// Single-slave form.
template <crc_table_size Table = default_crc_table, class Word>
constexpr result<std::size_t> encode_frame(const slave_layout& layout, const slave_values& values,
                                           span<Word> out, const line_options& line = {},
                                           bit_order order = bit_order::msb_first,
                                           std::size_t bit_offset = 0) noexcept {
  return encode_frame<Table, Word>(span<const slave_layout>(&layout, 1),
                                   span<const slave_values>(&values, 1), out, line, order,
                                   bit_offset);
}

/// The same into a plain array of words (chain and single-slave forms).
template <crc_table_size Table = default_crc_table, class Word, std::size_t N>
constexpr result<std::size_t> encode_frame(span<const slave_layout> chain,
                                           span<const slave_values> values, Word (&out)[N],
                                           const line_options& line = {},
                                           bit_order order = bit_order::msb_first,
                                           std::size_t bit_offset = 0) noexcept {
  return encode_frame<Table, Word>(chain, values, span<Word>(out, N), line, order, bit_offset);
}
template <crc_table_size Table = default_crc_table, class Word, std::size_t N>
constexpr result<std::size_t> encode_frame(const slave_layout& layout, const slave_values& values,
                                           Word (&out)[N], const line_options& line = {},
                                           bit_order order = bit_order::msb_first,
                                           std::size_t bit_offset = 0) noexcept {
  return encode_frame<Table, Word>(layout, values, span<Word>(out, N), line, order, bit_offset);
}

}  // namespace biss
}  // namespace motionbus

#endif  // MOTIONBUS_BISS_CODEC_HPP
