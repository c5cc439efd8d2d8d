// motionbus — T-format byte codec, master side and encoder side, all constexpr.
//
// Master:  encode_request        → CF [ADF [EDF] CRC] into a caller buffer
//          decode_response       → typed response, layout chosen by the response's CF
//          decode_response_for   → the same, checked against the request that was sent
// Encoder: decode_request        → typed request (what an encoder received)
//          encode_response       → response bytes for given values
//
// Decoders return decode_result<T>: complete (value, bytes consumed), incomplete (need more
// bytes), or failed (error, bytes the caller may drop to resynchronise, evidence). Inputs are
// never trusted: every length is checked before use.
// Sources: TS5700N8500 specification §6.2–6.3, §8.4, §9.4, Table 5; docs/tformat.md §7.
#ifndef MOTIONBUS_TFORMAT_CODEC_HPP
#define MOTIONBUS_TFORMAT_CODEC_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/bytes.hpp"
#include "motionbus/core/config.hpp"
#include "motionbus/core/crc.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/tformat/frame.hpp"

namespace motionbus {
namespace tformat {

/// The T-format CRC (G = X^8 + 1: the XOR of the bytes; no table is emitted).
using crc_type = crc8_tformat<crc_table_size::byte>;

constexpr std::uint8_t crc_of(byte_view fields) noexcept {
  return crc_type::compute(fields);
}

struct decode_options {
  /// Valid bits of ABS and ABM; bits above them must be 0 when check_unused_bits is set.
  resolution res{};
  bool check_unused_bits = true;
  /// For ID3 responses, take the resolution from a known ENID (0x11, 0x17, 0x0B) instead of res.
  bool resolution_from_enid = false;
};

namespace detail {

constexpr std::uint32_t le24(byte_view in, std::size_t at) noexcept {
  return static_cast<std::uint32_t>(in[at]) | (static_cast<std::uint32_t>(in[at + 1U]) << 8U) |
         (static_cast<std::uint32_t>(in[at + 2U]) << 16U);
}

constexpr void put_le24(mutable_byte_view out, std::size_t at, std::uint32_t v) noexcept {
  out[at] = static_cast<std::uint8_t>(v & 0xFFU);
  out[at + 1U] = static_cast<std::uint8_t>((v >> 8U) & 0xFFU);
  out[at + 2U] = static_cast<std::uint8_t>((v >> 16U) & 0xFFU);
}

constexpr bool fits(std::uint32_t value, unsigned bits) noexcept {
  return bits >= 32U || (value >> bits) == 0U;
}

// The error of a CF byte that is not its code's valid CF: sync code first (no reply is
// possible without it), then parity, then an undefined ID. The three codes are consecutive,
// so the count of checks passed selects the code.
constexpr errc cf_error(std::uint8_t cf) noexcept {
  static_assert(
      static_cast<int>(errc::tformat_parity) == static_cast<int>(errc::tformat_sync_code) + 1 &&
          static_cast<int>(errc::tformat_unknown_data_id) ==
              static_cast<int>(errc::tformat_sync_code) + 2,
      "cf_error counts on consecutive CF error codes");
  const unsigned sync = sync_ok(cf) ? 1U : 0U;
  const unsigned parity = sync & (parity_ok(cf) ? 1U : 0U);
  return static_cast<errc>(static_cast<unsigned>(errc::tformat_sync_code) + sync + parity);
}

/// Checks a CF byte: errc::ok, or its error as cf_error says (one comparison for a valid CF).
constexpr errc check_cf(std::uint8_t cf) noexcept {
  return cf == valid_control_fields[data_id_code(cf)] ? errc::ok : cf_error(cf);
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// Master side

/// Writes the request for `id` into `out`: CF for IDs 0,1,2,3,7,8,C; CF ADF CRC for IDD (the
/// EEPROM `address`); CF ADF EDF CRC for ID6 (`data` written at `address`). `address` and
/// `data` are not sent where the Data ID has no such field. Returns the bytes written.
/// Errors: tformat_unknown_data_id, out_of_range (address above 127), buffer_too_small.
/// Nothing is written on error. Arguments as everywhere in the library: input, output, options.
constexpr result<std::size_t> encode_request(data_id id, std::uint8_t address, std::uint8_t data,
                                             mutable_byte_view out) noexcept {
  if (!is_known(id)) {
    return errc::tformat_unknown_data_id;
  }
  if (address > adf_address_mask) {
    return errc::out_of_range;
  }
  const std::size_t n = request_size(id);
  if (out.size() < n) {
    return errc::buffer_too_small;
  }
  const std::uint8_t cf = control_fields[static_cast<std::uint8_t>(id)];
  out[0] = cf;
  if (n > 1U) {
    // The CRC (crc_of: the XOR of the fields before it) accumulated as the fields are written,
    // which saves a pass over the output on small cores.
    out[1] = address;
    std::uint8_t crc = static_cast<std::uint8_t>(cf ^ address);
    if (id == data_id::eeprom_write) {
      out[2] = data;
      crc = static_cast<std::uint8_t>(crc ^ data);
    }
    out[n - 1U] = crc;
  }
  return n;
}

/// The request for a Data ID without fields (0, 1, 2, 3, 7, 8, C): its CF.
constexpr result<std::size_t> encode_request(data_id id, mutable_byte_view out) noexcept {
  return encode_request(id, 0, 0, out);
}

namespace detail {

// Decodes a response of compile-time layout L (fields after CF and SF), `in` holding at least
// L.size bytes and a valid CF: straight-line code, the CRC an unrolled XOR.
template <std::size_t Size, bool Abs, bool Enid, bool Abm, bool Almc>
constexpr decode_result<response> decode_status_frame(byte_view in, data_id id,
                                                      const decode_options& opt) noexcept {
  response r;
  r.id = id;
  r.cf = in[0];
  r.crc = in[Size - 1U];
  const std::uint8_t computed = crc_of(in.first(Size - 1U));
  if (computed != r.crc) {
    return decode_failure{errc::crc_mismatch, 1, computed, r.crc};
  }
  r.sf = in[1];
  if ((r.sf & sf::reserved_mask) != 0U) {
    return decode_failure{errc::reserved_bits, 1};
  }
  constexpr std::size_t abs_at = 2;
  constexpr std::size_t enid_at = abs_at + (Abs ? 3U : 0U);
  constexpr std::size_t abm_at = enid_at + (Enid ? 1U : 0U);
  constexpr std::size_t almc_at = abm_at + (Abm ? 3U : 0U);
  resolution res = opt.res;
  if constexpr (Abs) {
    r.abs = le24(in, abs_at);
  }
  if constexpr (Enid) {
    r.enid = in[enid_at];
    if (Abs && opt.resolution_from_enid) {
      res = resolution_for_enid(r.enid, opt.res);
    }
  }
  if constexpr (Abm) {
    r.abm = le24(in, abm_at);
  }
  if constexpr (Almc) {
    r.almc = in[almc_at];
  }
  if (opt.check_unused_bits &&
      ((Abs && !fits(r.abs, res.single_turn_bits)) || (Abm && !fits(r.abm, res.multi_turn_bits)))) {
    return decode_failure{errc::out_of_range, 1};
  }
  return decode_result<response>::complete(r, Size);
}

// The ID3 response (the one polled every control cycle), from one 64-bit little-endian
// load of fields 0..7 plus fields 8..10, the CRC (the XOR of fields 0..9) folded in the same
// register. Same checks, same order as decode_status_frame, which the tests pin it to.
// inline: straight-line code (a few dozen instructions) the receiver runs per frame.
MOTIONBUS_INLINE constexpr decode_result<response> decode_read_all(
    byte_view in, const decode_options& opt) noexcept {
  const std::uint64_t w = load_le<8>(in, 0);
  const std::uint32_t f8 = in[8];
  const std::uint32_t f9 = in[9];
  const std::uint8_t crc = in[10];
  std::uint64_t x = w ^ (f8 | (f9 << 8U));
  x ^= x >> 32U;
  x ^= x >> 16U;
  x ^= x >> 8U;
  const auto computed = static_cast<std::uint8_t>(x);
  if (computed != crc) {
    return decode_failure{errc::crc_mismatch, 1, computed, crc};
  }
  const auto status = static_cast<std::uint8_t>(w >> 8U);
  if ((status & sf::reserved_mask) != 0U) {
    return decode_failure{errc::reserved_bits, 1};
  }
  const std::uint32_t abs = static_cast<std::uint32_t>(w >> 16U) & 0xFFFFFFU;
  const auto enid = static_cast<std::uint8_t>(w >> 40U);
  const std::uint32_t abm = static_cast<std::uint32_t>(w >> 48U) | (f8 << 16U);
  const resolution res = opt.resolution_from_enid ? resolution_for_enid(enid, opt.res) : opt.res;
  // Both unused-bit checks in one test (64-bit shifts, counts capped at 32: always defined).
  const unsigned st = res.single_turn_bits < 32U ? res.single_turn_bits : 32U;
  const unsigned mt = res.multi_turn_bits < 32U ? res.multi_turn_bits : 32U;
  if (opt.check_unused_bits &&
      ((static_cast<std::uint64_t>(abs) >> st) | (static_cast<std::uint64_t>(abm) >> mt)) != 0U) {
    return decode_failure{errc::out_of_range, 1};
  }
  // Every field given (aggregate initialisation): each is stored once. By position, in the
  // order of response's members, which frame.hpp checks: set by name, the ID3 decode costs more
  // than the performance policy allows (docs/design.md, "Field order and construction").
  return decode_result<response>::complete(
      response{data_id::read_all, static_cast<std::uint8_t>(w), status, enid,
               static_cast<std::uint8_t>(f9), 0, false, 0, crc, abs, abm},
      11);
}

MOTIONBUS_COLD constexpr decode_result<response> cf_failure(std::uint8_t cf) noexcept {
  return decode_failure{check_cf(cf), 1};
}

constexpr decode_result<response> decode_short_response(byte_view in,
                                                        const decode_options& opt) noexcept;

// How responses are decoded, and why three ways: decode_read_all (ID3, the response polled
// every control cycle, from one 64-bit load) serves both forms; decode_status_frame<layout>
// is the speed form's straight-line decoder for ID0, the other polled response;
// decode_short_response is one table-driven path for every other layout, in both forms (the
// size form's only other path, the speed form's cold one). The tests and the response fuzz
// target pin all three to the same outcomes.
//
// The speed form of decode_response: the polled IDs inline, the others out of line, so that
// the call site stays small enough to inline. Each inline branch checks its own constant size,
// so that a compiler looking at the caller's buffer sees every read guarded (no
// -Warray-bounds false positives on short arrays).
// inline: the polled IDs' straight-line decode in the caller (hosts, -O2).
MOTIONBUS_INLINE constexpr decode_result<response> decode_response_fast(
    byte_view in, const decode_options& opt) noexcept {
  if (in.empty()) {
    return need_input{4};
  }
  const std::uint8_t cf = in[0];
  const std::uint8_t code = data_id_code(cf);
  const auto id = static_cast<data_id>(code);
  // One comparison covers sync code, parity and a defined Data ID; the slow path tells which.
  if (cf != valid_control_fields[code]) {
    return cf_failure(cf);
  }
  if (id == data_id::read_all) {
    if (in.size() < 11U) {
      return need_input{11U - in.size()};
    }
    return decode_read_all(in, opt);
  }
  if (id == data_id::read_abs) {
    if (in.size() < 6U) {
      return need_input{6U - in.size()};
    }
    return decode_status_frame<6, true, false, false, false>(in, id, opt);
  }
  return decode_short_response(in, opt);
}

// Every response but a whole ID3 one (decode_response_small takes those): the fields before
// the CRC (at most five bytes) are gathered into a zero-padded word, where each field has one
// place whatever the layout (an absent field reads as 0, which fits any resolution: no
// per-field condition in the unused-bit check); the checks settle one error, returned from one
// place. An ID3 CF with fewer than 11 bytes needs more.
constexpr decode_result<response> decode_short_response(byte_view in,
                                                        const decode_options& opt) noexcept {
  if (in.empty()) {
    return need_input{4};  // the shortest response, while no CF is known
  }
  const std::uint8_t cf = in[0];
  const std::uint8_t code = data_id_code(cf);
  if (cf != valid_control_fields[code]) {
    return decode_failure{cf_error(cf), 1};
  }
  const std::size_t size = response_layouts[code].size;
  if (in.size() < size) {
    return need_input{size - in.size()};
  }
  const std::uint8_t fields = response_layouts[code].fields;
  const std::size_t last = size - 1U;
  // CF, SF (or ADF), then ABS, or else the one field after SF, from byte 2.
  std::uint64_t w = 0;
  for (std::size_t i = last < 5U ? last : 5U; i > 0U; --i) {
    w = (w << 8U) | in[i - 1U];
  }
  std::uint32_t x = static_cast<std::uint32_t>(w) ^ static_cast<std::uint32_t>(w >> 32U);
  x ^= x >> 16U;
  x ^= x >> 8U;
  const auto computed = static_cast<std::uint8_t>(x);
  const std::uint8_t sent = in[last];
  const bool eeprom = (fields & field_bit::eeprom) != 0U;
  const auto second = static_cast<std::uint8_t>(w >> 8U);
  const auto first = static_cast<std::uint32_t>(w >> 16U);
  const std::uint32_t abs = (fields & field_bit::abs) != 0U ? first : 0U;
  const std::uint32_t abm = fields == field_bit::abm ? first : 0U;
  errc e = errc::ok;
  if (computed != sent) {
    e = errc::crc_mismatch;
  } else if (!eeprom && (second & sf::reserved_mask) != 0U) {
    e = errc::reserved_bits;
  } else if (opt.check_unused_bits &&
             (!fits(abs, opt.res.single_turn_bits) || !fits(abm, opt.res.multi_turn_bits))) {
    e = errc::out_of_range;
  }
  if (e != errc::ok) {
    const bool crc = e == errc::crc_mismatch;
    return decode_failure{e, 1, crc ? computed : 0U, crc ? sent : 0U};
  }
  const auto third = static_cast<std::uint8_t>(first);
  // Every field given (aggregate initialisation): each is stored once. By position, in the
  // order of response's members, which frame.hpp checks: set by name, the ID3 decode costs more
  // than the performance policy allows (docs/design.md, "Field order and construction").
  return decode_result<response>::complete(
      response{static_cast<data_id>(code), cf, eeprom ? std::uint8_t{0} : second,
               fields == field_bit::enid ? third : std::uint8_t{0}, std::uint8_t{0},
               eeprom ? static_cast<std::uint8_t>(second & adf_address_mask) : std::uint8_t{0},
               eeprom && (second & adf_busy) != 0U, eeprom ? third : std::uint8_t{0}, sent, abs,
               abm},
      size);
}

// The size form of decode_response (MOTIONBUS_SMALL_CODE): a whole ID3 response (polled every
// control cycle) through decode_read_all, inline at the call site, every other input through
// the one table-driven path for the short layouts, out of line. Same checks in the same order
// as the speed form, which the tests and the response fuzz target pin it to.
// inline: the ID3 test and decode_read_all in the caller, the rest called.
MOTIONBUS_INLINE constexpr decode_result<response> decode_response_small(
    byte_view in, const decode_options& opt) noexcept {
  if (in.size() >= max_response_size && in[0] == control_field(data_id::read_all)) {
    return decode_read_all(in, opt);
  }
  return decode_short_response(in, opt);
}

}  // namespace detail

/// Decodes one response from the start of `in`; the layout follows the response's CF.
/// Complete: the response and its size in bytes (extra input is left unconsumed).
/// Incomplete: fewer bytes than the CF's layout needs. Failed, with 1 byte to drop: CF sync
/// code, parity or unknown Data ID; crc_mismatch (expected = computed, received = sent);
/// reserved_bits (SF bits 0..3 set); out_of_range (ABS/ABM bits above the resolution set).
/// A busy EEPROM is state (response::busy), not an error. MOTIONBUS_SMALL_CODE picks the
/// form (core/config.hpp); both return the same results.
// inline: as the two forms it forwards to, so that the polled IDs decode in the caller.
MOTIONBUS_INLINE constexpr decode_result<response> decode_response(
    byte_view in, const decode_options& opt = {}) noexcept {
#if MOTIONBUS_SMALL_CODE
  return detail::decode_response_small(in, opt);
#else
  return detail::decode_response_fast(in, opt);
#endif
}

/// decode_response on a buffer that must hold exactly one frame (e.g. bytes received up to
/// the line's idle): fewer bytes are errc::truncated, more are errc::tformat_length.
constexpr decode_result<response> decode_response_frame(byte_view in,
                                                        const decode_options& opt = {}) noexcept {
  const decode_result<response> r = decode_response(in, opt);
  if (r.is_incomplete()) {
    return decode_failure{errc::truncated, in.size()};
  }
  if (r.is_complete() && r.consumed() != in.size()) {
    return decode_failure{errc::tformat_length, in.size()};
  }
  return r;
}

namespace detail {

// check_response on a request frame already known to be valid (a known CF, all its bytes).
constexpr errc check_against(const std::uint8_t* request_frame, const response& v,
                             std::uint32_t& want, std::uint32_t& got) noexcept {
  const bool eeprom =
      (response_layouts[static_cast<std::uint8_t>(v.id) & 0xFU].fields & field_bit::eeprom) != 0U;
  if (!eeprom && (v.sf & (sf::ca0 | sf::ca1)) != 0U) {
    return errc::tformat_communication_alarm;
  }
  if (v.cf != request_frame[0]) {
    want = request_frame[0];
    got = v.cf;
    return errc::tformat_cf_mismatch;
  }
  if (eeprom) {
    const auto want_address = static_cast<std::uint8_t>(request_frame[1] & adf_address_mask);
    if (v.address != want_address) {
      want = want_address;
      got = v.address;
      return errc::tformat_address_mismatch;
    }
    if (v.id == data_id::eeprom_write && !v.busy && v.edf != request_frame[2]) {
      want = request_frame[2];
      got = v.edf;
      return errc::tformat_data_mismatch;
    }
  }
  return errc::ok;
}

// Whether `request_frame` is a request the master may have sent (a known CF, all its bytes).
constexpr bool valid_request(byte_view request_frame) noexcept {
  return !request_frame.empty() && check_cf(request_frame[0]) == errc::ok &&
         request_frame.size() >= request_size(static_cast<data_id>(data_id_code(request_frame[0])));
}

}  // namespace detail

/// Checks a decoded response against the request frame that was sent. A complete `r` stays
/// complete, or fails (consuming the whole response) with tformat_communication_alarm when the
/// encoder flags ca0/ca1 (the request arrived corrupted: send it again; spec §6.3.2),
/// tformat_cf_mismatch, tformat_address_mismatch (EEPROM) or tformat_data_mismatch (ID6 not
/// echoing the data while not busy), the request's and the response's field as expected() and
/// received(). An incomplete or failed `r` is returned as it is. An empty or malformed
/// `request_frame` is errc::invalid_argument (consumed 0), whatever `r` is.
constexpr decode_result<response> check_response(byte_view request_frame,
                                                 const decode_result<response>& r) noexcept {
  if (!detail::valid_request(request_frame)) {
    return decode_failure{errc::invalid_argument, 0};
  }
  if (!r.is_complete()) {
    return r;
  }
  std::uint32_t want = 0;
  std::uint32_t got = 0;
  const errc e = detail::check_against(request_frame.data(), r.value(), want, got);
  if (e != errc::ok) {
    return decode_failure{e, r.consumed(), want, got};
  }
  return r;
}

/// decode_response checked against the request frame that was sent (check_response): the
/// request first, the bytes that answer it second, as modbus::decode_response_for.
constexpr decode_result<response> decode_response_for(byte_view request_frame, byte_view in,
                                                      const decode_options& opt = {}) noexcept {
  return check_response(request_frame, decode_response(in, opt));
}

// ---------------------------------------------------------------------------------------------
// Encoder side

/// Decodes one request from the start of `in` (what an encoder receives). Complete: the
/// request and its size. Incomplete: an EEPROM request lacks ADF/EDF/CRC. Failed, 1 byte to
/// drop: tformat_sync_code (the encoder must not reply), tformat_parity, tformat_unknown_data_id
/// (the encoder replies with ID3 data, ca0 set for parity). Failed, whole frame consumed:
/// crc_mismatch and reserved_bits (busy bit set in a request ADF): ID3 data in reply.
constexpr decode_result<request> decode_request(byte_view in) noexcept {
  if (in.empty()) {
    return need_input{1};
  }
  const std::uint8_t cf = in[0];
  const errc cf_error = detail::check_cf(cf);
  if (cf_error != errc::ok) {
    return decode_failure{cf_error, 1};
  }
  request q;
  q.id = static_cast<data_id>(data_id_code(cf));
  q.cf = cf;
  const std::size_t n = request_size(q.id);
  if (in.size() < n) {
    return need_input{n - in.size()};
  }
  if (n > 1U) {
    q.crc = in[n - 1U];
    const std::uint8_t computed = crc_of(in.first(n - 1U));
    if (computed != q.crc) {
      return decode_failure{errc::crc_mismatch, n, computed, q.crc};
    }
    if ((in[1] & adf_busy) != 0U) {
      return decode_failure{errc::reserved_bits, n};
    }
    q.address = in[1];
    if (q.id == data_id::eeprom_write) {
      q.edf = in[2];
    }
  }
  return decode_result<request>::complete(q, n);
}

/// Writes the response for `r.id` with r's field values into `out` (CF from the ID, CRC
/// computed; r.cf and r.crc are ignored). Returns the bytes written. Errors:
/// tformat_unknown_data_id, reserved_bits (SF bits 0..3 set), out_of_range (ABS/ABM above 24
/// bits, address above 127), buffer_too_small. Nothing is written on error.
constexpr result<std::size_t> encode_response(const response& r, mutable_byte_view out) noexcept {
  if (!is_known(r.id)) {
    return errc::tformat_unknown_data_id;
  }
  const response_layout lay = layout_of(r.id);
  if (lay.eeprom() ? r.address > adf_address_mask : (r.sf & sf::reserved_mask) != 0U) {
    return lay.eeprom() ? errc::out_of_range : errc::reserved_bits;
  }
  if ((lay.abs() && !detail::fits(r.abs, 24)) || (lay.abm() && !detail::fits(r.abm, 24))) {
    return errc::out_of_range;
  }
  if (out.size() < lay.size) {
    return errc::buffer_too_small;
  }
  out[0] = control_field(r.id);
  std::size_t at = 1;
  if (lay.eeprom()) {
    out[1] = static_cast<std::uint8_t>(r.address | (r.busy ? adf_busy : 0U));
    out[2] = r.busy ? std::uint8_t{0} : r.edf;  // EDF is 00 while busy (spec Table 5)
    at = 3;
  } else {
    out[at++] = r.sf;
    if (lay.abs()) {
      detail::put_le24(out, at, r.abs);
      at += 3U;
    }
    if (lay.enid()) {
      out[at++] = r.enid;
    }
    if (lay.abm()) {
      detail::put_le24(out, at, r.abm);
      at += 3U;
    }
    if (lay.almc()) {
      out[at++] = r.almc;
    }
  }
  out[at] = crc_of(byte_view(out.data(), at));
  return at + 1U;
}

/// The status field an encoder reports for alarm bits `almc` and communication alarms:
/// ea0 = CE, ea1 = OH | ME | BE | BA (spec §6.3.2).
constexpr std::uint8_t status_field(std::uint8_t almc, bool ca0 = false,
                                    bool ca1 = false) noexcept {
  std::uint8_t s = 0;
  if (has_alarm(almc, almc_bit::ce)) {
    s = static_cast<std::uint8_t>(s | sf::ea0);
  }
  if ((almc & ea1_alarms) != 0U) {
    s = static_cast<std::uint8_t>(s | sf::ea1);
  }
  if (ca0) {
    s = static_cast<std::uint8_t>(s | sf::ca0);
  }
  if (ca1) {
    s = static_cast<std::uint8_t>(s | sf::ca1);
  }
  return s;
}

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_CODEC_HPP
