// Compile-time suite for T-format: spec vectors encoded and decoded by the compiler.
#include <cstdint>

#include "motionbus/devices/ts5700n8500.hpp"
#include "motionbus/devices/ts5700n8500_emulator.hpp"
#include "motionbus/tformat.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;
namespace ts = motionbus::devices::ts5700n8500;

namespace {

// Control fields (TS5700N8500 specification Table 1; docs/tformat.md §2, §7).
static_assert(tf::control_field(tf::data_id::read_abs) == 0x02, "ID0");
static_assert(tf::control_field(tf::data_id::read_abm) == 0x8A, "ID1");
static_assert(tf::control_field(tf::data_id::read_enid) == 0x92, "ID2");
static_assert(tf::control_field(tf::data_id::read_all) == 0x1A, "ID3");
static_assert(tf::control_field(tf::data_id::eeprom_write) == 0x32, "ID6");
static_assert(tf::control_field(tf::data_id::reset_errors) == 0xBA, "ID7");
static_assert(tf::control_field(tf::data_id::reset_single_turn) == 0xC2, "ID8");
static_assert(tf::control_field(tf::data_id::reset_multi_turn) == 0x62, "IDC");
static_assert(tf::control_field(tf::data_id::eeprom_read) == 0xEA, "IDD");

// The T-format CRC needs no table: x^8 + 1 makes the byte table the identity.
static_assert(mb::detail::crc_kernel<8, 0x01, true>::identity_table<8>(), "identity table");
static_assert(!mb::detail::crc_kernel<16, 0x8005, true>::identity_table<8>(), "real table");

// An ID3 response: 1A 00 | 45 23 01 | 11 | 34 12 00 | 80 | CRC = XOR of the ten bytes.
constexpr std::uint8_t id3[] = {0x1A,
                                0x00,
                                0x45,
                                0x23,
                                0x01,
                                0x11,
                                0x34,
                                0x12,
                                0x00,
                                0x80,
                                0x1A ^ 0x45 ^ 0x23 ^ 0x01 ^ 0x11 ^ 0x34 ^ 0x12 ^ 0x80};
constexpr auto id3_decoded = tf::decode_response(id3);
static_assert(id3_decoded.is_complete() && id3_decoded.consumed() == 11, "ID3 decodes");
static_assert(id3_decoded.value().abs == 0x012345 && id3_decoded.value().abm == 0x1234, "ID3 data");
static_assert(id3_decoded.value().enid == 0x11 && id3_decoded.value().almc == 0x80,
              "ID3 ENID/ALMC");
static_assert(tf::decode_response(mb::byte_view(id3, 10)).is_incomplete(), "prefix");

constexpr bool id3_reencodes() {
  std::uint8_t out[11] = {};
  const auto n = tf::encode_response(id3_decoded.value(), out);
  if (!n.ok() || n.value() != 11) {
    return false;
  }
  for (int i = 0; i < 11; ++i) {
    if (out[i] != id3[i]) {
      return false;
    }
  }
  return true;
}
static_assert(id3_reencodes(), "decode -> encode gives the same bytes");

constexpr std::uint8_t id3_bad_crc[] = {0x1A, 0x00, 0x45, 0x23, 0x01, 0x11,
                                        0x34, 0x12, 0x00, 0x80, 0x00};
static_assert(tf::decode_response(id3_bad_crc).error() == mb::errc::crc_mismatch, "CRC");

// EEPROM request and its encoder-side decode.
constexpr bool eeprom_round_trip() {
  std::uint8_t req[4] = {};
  const auto n = tf::encode_request(tf::data_id::eeprom_write, 5, 0x12, req);
  const auto q = tf::decode_request(mb::byte_view(req, n.value()));
  return n.value() == 4 && req[3] == (0x32 ^ 0x05 ^ 0x12) && q.is_complete() &&
         q.value().address == 5 && q.value().edf == 0x12;
}
static_assert(eeprom_round_trip(), "ID6 request");

// The encoder model answers a request inside a constant expression.
constexpr bool model_answers() {
  motionbus::devices::ts5700n8500::emulator enc;
  enc.set_position(42, 1);
  const std::uint8_t req[] = {0x02};
  const motionbus::devices::ts5700n8500::reply r = enc.respond(req, 0);
  const auto d = tf::decode_response(r.view());
  return r.size == 6 && d.is_complete() && d.value().abs == 42;
}
static_assert(model_answers(), "encoder model");

// Line coding: an ID0 request after 3 idle bits, decoded back by the encoder side.
constexpr bool line_round_trip() {
  std::uint8_t bits[4] = {};
  const std::uint8_t req[] = {0x02};
  const auto n = tf::encode_line(mb::byte_view(req), mb::span<std::uint8_t>(bits),
                                 mb::bit_order::msb_first, 0, 3);
  const auto q = tf::decode_request_line(mb::span<const std::uint8_t>(bits),
                                         mb::bit_order::msb_first, n.value());
  return n.value() == 13 && q.is_complete() && q.value().start_bit == 3 &&
         q.value().frame.id == tf::data_id::read_abs;
}
static_assert(line_round_trip(), "line coding");

// The Data IDs the protocol defines, from the spec's list (§6.2, Table 5) and no other code.
constexpr bool known_ids_exact() {
  constexpr std::uint8_t defined[] = {0x0, 0x1, 0x2, 0x3, 0x6, 0x7, 0x8, 0xC, 0xD};
  unsigned known = 0;
  for (unsigned code = 0; code < 256U; ++code) {
    known += tf::is_known(static_cast<tf::data_id>(code)) ? 1U : 0U;
  }
  for (const std::uint8_t code : defined) {
    if (!tf::is_known(static_cast<tf::data_id>(code))) {
      return false;
    }
  }
  return known == 9U;
}
static_assert(known_ids_exact(), "known Data IDs");

// Each layout's size is its fields counted (CF, SF or ADF+EDF, ABS 3, ENID 1, ABM 3, ALMC 1,
// CRC), and the codes the encoder does not know carry ID3's layout (spec §8.4).
constexpr bool layout_sizes_count_their_fields() {
  for (std::uint8_t code = 0; code < 16U; ++code) {
    const tf::response_layout l = tf::layout_of(static_cast<tf::data_id>(code));
    const unsigned counted = 1U + (l.sf() ? 1U : 0U) + (l.eeprom() ? 2U : 0U) +
                             (l.abs() ? 3U : 0U) + (l.enid() ? 1U : 0U) + (l.abm() ? 3U : 0U) +
                             (l.almc() ? 1U : 0U) + 1U;
    if (counted != l.size) {
      return false;
    }
    if (!tf::is_known(static_cast<tf::data_id>(code)) &&
        l.fields != tf::layout_of(tf::data_id::read_all).fields) {
      return false;
    }
  }
  return true;
}
static_assert(layout_sizes_count_their_fields(), "response_layouts");

// The receiver's per-byte step in a constant expression: a request, its echo, garbage, an ID0
// response byte by byte through put(); the response settles at its last byte.
constexpr bool receiver_put_settles_at_the_last_byte() {
  tf::receiver rx(tf::receiver_options{tf::echo::expected});
  const std::uint8_t request[1] = {0x02};
  rx.sent(motionbus::byte_view(request, 1));
  const std::uint8_t line[] = {0x02, 0xFF, 0x02, 0x00, 0x21, 0x43, 0x01, 0x61};  // CRC: XOR
  int settled = 0;
  for (const std::uint8_t b : line) {
    settled += rx.put(b) ? 1 : 0;
  }
  return settled == 1 && rx.result().is_complete() && rx.result()->abs == 0x014321 &&
         rx.echoes_skipped() == 1 && rx.dropped() == 1;
}
static_assert(receiver_put_settles_at_the_last_byte(), "receiver::put");

// TS5700N8500 helpers.
static_assert(ts::encode_overheat_threshold(90).value() == 0xDA, "90 °C");
static_assert(ts::decode_temperature(0x3C) == 60 && ts::decode_temperature(0xFF) == -1, "temp");
static_assert(ts::transaction_ns(tf::data_id::read_all) == 48000, "ID3 48 us");
// CE by the magnitude of a signed speed (spec §6.5): -150 min^-1 case I, -50 case II.
static_assert(!ts::info(tf::almc_bit::ce).latched_at(-150), "reverse, case I: non-latched");
static_assert(ts::info(tf::almc_bit::ce).latched_at(-50), "reverse, case II: latched");
static_assert(ts::reset_plan(tf::data_id::reset_errors).value().size == 10, "10 requests");

}  // namespace

int main() {
  return 0;
}
