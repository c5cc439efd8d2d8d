// motionbus — T-format line coding for masters and encoders that see raw bits (SPI, PIO, CLB,
// FPGA soft-cores): every field is 10 bits — start 0, 8 data bits LSB first, delimiter 1 —
// and the idle line is 1 (TS5700N8500 specification §6.3, §8; docs/tformat.md §1, §7).
//
// Streams are sequences of `Word`s (8/16/32/64-bit) packed MSB-first or LSB-first (see
// core/bits.hpp), one sample per bit. A frame starts at the first 0 after idle whose next three
// bits are the sync code 010; otherwise the search goes on (spec §8.1, §9.1). A 0 at the very
// first sample counts as following idle (captures triggered on the start bit).
#ifndef MOTIONBUS_TFORMAT_LINE_HPP
#define MOTIONBUS_TFORMAT_LINE_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/bits.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/frame.hpp"

namespace motionbus {
namespace tformat {

/// Bits per field on the line.
inline constexpr unsigned field_bits = 10;

/// A frame found in a bit stream: the decoded value and the index of its start bit (the line
/// delay, in bits, from the beginning of the stream).
template <class T>
struct line_frame {
  T frame{};
  std::size_t start_bit = 0;
};

/// What the line decoders return: counted in bits of the stream (consumed_bits(),
/// needed_bits()).
template <class T>
using line_result = decode_result<line_frame<T>, input_unit::bits>;

/// Writes `frame` (field bytes) as line bits into `out` from bit `bit_offset`, preceded by
/// `idle_bits` ones. Returns the bits written (idle included); buffer_too_small writes nothing.
template <class Word>
constexpr result<std::size_t> encode_line(byte_view frame, span<Word> out,
                                          bit_order order = bit_order::msb_first,
                                          std::size_t bit_offset = 0,
                                          std::size_t idle_bits = 0) noexcept {
  basic_bit_writer<Word> w(out, order, bit_offset);
  const std::size_t total = idle_bits + frame.size() * field_bits;
  if (bit_offset > w.size() || total > w.remaining()) {
    return errc::buffer_too_small;
  }
  (void)w.fill(true, idle_bits);
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const std::uint64_t b = frame[i];
    // The 10 line bits s0..s9 = 0, b0..b7, 1 as a field in the writer's order.
    const std::uint64_t field = order == bit_order::msb_first
                                    ? ((reverse_bits(b, 8) << 1U) | 1U)
                                    : ((b << 1U) | (std::uint64_t{1} << 9U));
    (void)w.write(field, field_bits);
  }
  return total;
}

namespace detail {

// The frame size in fields announced by a CF, or 0 when the CF is unusable.
struct frame_sizer {
  bool response;
  constexpr std::size_t operator()(std::uint8_t cf) const noexcept {
    if (check_cf(cf) != errc::ok) {
      return 0;
    }
    const auto id = static_cast<data_id>(data_id_code(cf));
    return response ? layout_of(id).size : request_size(id);
  }
};

struct line_fields {
  std::uint8_t bytes[max_response_size] = {};
  std::size_t count = 0;
  std::size_t start_bit = 0;
};

// Finds the frame start at or after `from` and collects its fields' data bytes, checking every
// start and delimiter bit. Complete: consumed_bits() = bit index just after the last delimiter.
template <class Word>
constexpr decode_result<line_fields, input_unit::bits> collect_fields(
    const basic_bit_reader<Word>& stream, std::size_t from, bool response) noexcept {
  const bit_order order = stream.order();
  const std::size_t end = stream.size();
  std::size_t i = from;
  for (;;) {
    // first 0 after idle (or at the first sample)
    while (i < end && !(stream.bit_at(i).value() == false &&
                        (i == 0 || stream.bit_at(i - 1U).value() == true))) {
      ++i;
    }
    if (i >= end) {
      return decode_failure{errc::no_frame, end};
    }
    if (end - i < 4U) {
      return need_input{4U - (end - i)};
    }
    // sync code 010 in the three bits after the start bit
    if (!stream.bit_at(i + 1U).value() && stream.bit_at(i + 2U).value() &&
        !stream.bit_at(i + 3U).value()) {
      break;
    }
    ++i;
  }
  line_fields f;
  f.start_bit = i;
  std::size_t expected = 1;
  const frame_sizer sizer{response};
  basic_bit_reader<Word> r = stream;
  for (std::size_t k = 0; k < expected; ++k) {
    const std::size_t at = i + k * field_bits;
    if (at + field_bits > end) {
      return need_input{at + field_bits - end};
    }
    (void)r.seek(at);
    const std::uint64_t v = r.read(field_bits).value();
    const bool start = order == bit_order::msb_first ? ((v >> 9U) & 1U) != 0U : (v & 1U) != 0U;
    const bool delimiter = order == bit_order::msb_first ? (v & 1U) != 0U : ((v >> 9U) & 1U) != 0U;
    const std::uint8_t byte = order == bit_order::msb_first
                                  ? static_cast<std::uint8_t>(reverse_bits((v >> 1U) & 0xFFU, 8))
                                  : static_cast<std::uint8_t>((v >> 1U) & 0xFFU);
    if (start) {
      return decode_failure{errc::tformat_start_bit, at + field_bits};
    }
    if (!delimiter) {
      return decode_failure{errc::tformat_delimiter, at + field_bits};
    }
    f.bytes[k] = byte;
    f.count = k + 1U;
    if (k == 0) {
      expected = sizer(byte);
      if (expected == 0) {  // sync ok but parity / unknown ID: let the byte codec say which
        expected = 1;
      }
    }
  }
  return decode_result<line_fields, input_unit::bits>::complete(f, i + expected * field_bits);
}

}  // namespace detail

/// Finds and decodes a response in a sampled bit stream: `words` packed in `order`, the first
/// `bit_count` bits valid (default: all), searching from bit `from`. Complete: the response
/// and its start bit; consumed_bits() = the bit just after its last delimiter. Incomplete: the
/// stream ends inside the frame. Failed: no_frame (no start found; consumed_bits() = all bits),
/// tformat_start_bit / tformat_delimiter (a field's framing bit is wrong; consumed_bits() = the bit
/// after that field), or any decode_response error.
template <class Word>
constexpr line_result<response> decode_response_line(
    span<const Word> words, bit_order order = bit_order::msb_first,
    std::size_t bit_count = static_cast<std::size_t>(-1), std::size_t from = 0,
    const decode_options& opt = {}) noexcept {
  const basic_bit_reader<Word> stream(words, order, 0, bit_count);
  const auto f = detail::collect_fields(stream, from, true);
  if (f.is_incomplete()) {
    return need_input{f.needed_bits()};
  }
  if (f.is_failed()) {
    return decode_failure{f.error(), f.consumed_bits()};
  }
  const auto r = decode_response(byte_view(f.value().bytes, f.value().count), opt);
  if (!r.is_complete()) {
    // collect_fields gives the bytes the CF's layout sizes, or a bad CF alone (refused):
    // coverage-branch: r is failed, never incomplete
    return decode_failure{r.is_failed() ? r.error() : errc::truncated, f.consumed_bits(),
                          r.expected(), r.received()};
  }
  return line_result<response>::complete({r.value(), f.value().start_bit}, f.consumed_bits());
}

/// Encoder side: finds and decodes a request in a sampled bit stream (as decode_response_line).
/// A tformat_delimiter failure is what the encoder answers with ID3 data and ca1 set.
template <class Word>
constexpr line_result<request> decode_request_line(
    span<const Word> words, bit_order order = bit_order::msb_first,
    std::size_t bit_count = static_cast<std::size_t>(-1), std::size_t from = 0) noexcept {
  const basic_bit_reader<Word> stream(words, order, 0, bit_count);
  const auto f = detail::collect_fields(stream, from, false);
  if (f.is_incomplete()) {
    return need_input{f.needed_bits()};
  }
  if (f.is_failed()) {
    return decode_failure{f.error(), f.consumed_bits()};
  }
  const auto r = decode_request(byte_view(f.value().bytes, f.value().count));
  if (!r.is_complete()) {
    // collect_fields gives the bytes the CF's request sizes, or a bad CF alone (refused):
    // coverage-branch: r is failed, never incomplete
    return decode_failure{r.is_failed() ? r.error() : errc::truncated, f.consumed_bits(),
                          r.expected(), r.received()};
  }
  return line_result<request>::complete({r.value(), f.value().start_bit}, f.consumed_bits());
}

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_LINE_HPP
