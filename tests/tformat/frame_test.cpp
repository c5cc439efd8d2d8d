// T-format frame vocabulary (frame.hpp): control fields (spec Table 1), response layouts
// (Table 2), alarm bits and their symbols, resolutions and the combined position.
#include "motionbus/tformat/frame.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>

#include "../support/tformat.hpp"

using namespace motionbus;
using namespace motionbus::tformat;

using namespace testutil;

TEST_CASE(
    "control field bytes follow the specification's Table 1, sent least significant bit first") {
  for (const auto& row : table1) {
    CAPTURE(static_cast<int>(row.id));
    CHECK(control_field(row.id) == cf_from_table(row));
    CHECK(sync_ok(control_field(row.id)));
    CHECK(parity_ok(control_field(row.id)));
  }
  CHECK(control_field(data_id::read_abs) == 0x02);
  CHECK(control_field(data_id::read_abm) == 0x8A);
  CHECK(control_field(data_id::read_enid) == 0x92);
  CHECK(control_field(data_id::read_all) == 0x1A);
  CHECK(control_field(data_id::eeprom_write) == 0x32);
  CHECK(control_field(data_id::reset_errors) == 0xBA);
  CHECK(control_field(data_id::reset_single_turn) == 0xC2);
  CHECK(control_field(data_id::reset_multi_turn) == 0x62);
  CHECK(control_field(data_id::eeprom_read) == 0xEA);
  CHECK(!parity_ok(0x02 | 0x80));
  CHECK(!sync_ok(0x03));
}

TEST_CASE("layout_of: each response's size is its CF, CRC and the bytes of its fields") {
  for (unsigned code = 0; code < 16U; ++code) {
    const response_layout l = layout_of(static_cast<data_id>(code));
    CAPTURE(code);
    const unsigned bytes = 2U + (l.sf() ? 1U : 0U) + (l.abs() ? 3U : 0U) + (l.enid() ? 1U : 0U) +
                           (l.abm() ? 3U : 0U) + (l.almc() ? 1U : 0U) + (l.eeprom() ? 2U : 0U);
    CHECK(l.size == bytes);
    CHECK(l.size <= max_response_size);
  }
  CHECK(layout_of(data_id::read_all).fields == field_bit::read_all);
  CHECK(layout_of(data_id::eeprom_read).eeprom());
  CHECK(!layout_of(data_id::eeprom_read).sf());
}

TEST_CASE("request_size: the CF alone, but CF ADF CRC for ID D and CF ADF EDF CRC for ID 6") {
  CHECK(request_size(data_id::read_abs) == 1U);
  CHECK(request_size(data_id::reset_multi_turn) == 1U);
  CHECK(request_size(data_id::eeprom_read) == 3U);
  CHECK(request_size(data_id::eeprom_write) == 4U);
}

TEST_CASE("resolution_for_enid and absolute_position: turns above the single-turn bits") {
  CHECK(resolution_for_enid(0x11).single_turn_bits == 17);
  CHECK(resolution_for_enid(0x17).single_turn_bits == 23);
  CHECK(resolution_for_enid(0x0B).single_turn_bits == 11);
  CHECK(resolution_for_enid(0x99, {20, 16}).single_turn_bits == 20);

  CHECK(absolute_position(0x1ABCD, 3) == (3ULL << 17U) + 0x1ABCD);
  CHECK(absolute_position(5, 2, 23) == (2ULL << 23U) + 5);
}

TEST_CASE("alarm symbols: an undefined bit value has none") {
  CHECK(std::strcmp(symbol(almc_bit::ba), "BA") == 0);
  CHECK(std::strcmp(symbol(static_cast<almc_bit>(0x03)), "??") == 0);
}

TEST_CASE("is_known: a code past the 4-bit Data ID field is no Data ID") {
  CHECK(is_known(data_id::read_all));
  CHECK_FALSE(is_known(static_cast<data_id>(9)));
  CHECK_FALSE(is_known(static_cast<data_id>(16)));
  CHECK_FALSE(is_known(static_cast<data_id>(0x13)));  // 3 in its low bits
}

TEST_CASE("control_fields: the control field of each of the 16 codes, defined or not") {
  for (unsigned code = 0; code < 16U; ++code) {
    CAPTURE(code);
    CHECK(control_fields[code] == control_field(static_cast<std::uint8_t>(code)));
    CHECK(data_id_code(control_fields[code]) == code);
    CHECK(sync_ok(control_fields[code]));
    CHECK(parity_ok(control_fields[code]));
    CHECK_FALSE(parity_ok(static_cast<std::uint8_t>(control_fields[code] ^ 0x80U)));
  }
}

TEST_CASE("valid_control_fields: a defined code's control field, 0x00 for the undefined codes") {
  for (unsigned code = 0; code < 16U; ++code) {
    CAPTURE(code);
    const auto id = static_cast<data_id>(code);
    CHECK(valid_control_fields[code] == (is_known(id) ? control_field(id) : std::uint8_t{0x00}));
  }
  // the undefined codes, by number: 4, 5, 9, A, B, E, F
  for (const unsigned code : {0x4U, 0x5U, 0x9U, 0xAU, 0xBU, 0xEU, 0xFU}) {
    CAPTURE(code);
    CHECK(valid_control_fields[code] == 0x00);
  }
}

TEST_CASE("ALMC bits: one bit each, d70 to d77 in the order of the specification's Table 3") {
  const char* const symbols[8] = {"OS", "FS", "CE", "OF", "OH", "ME", "BE", "BA"};
  for (unsigned bit = 0; bit < 8U; ++bit) {
    CAPTURE(bit);
    const almc_bit a = all_alarms[bit];
    CHECK(static_cast<unsigned>(a) == (1U << bit));
    CHECK(std::strcmp(symbol(a), symbols[bit]) == 0);
    CHECK(has_alarm(static_cast<std::uint8_t>(1U << bit), a));
    CHECK_FALSE(has_alarm(static_cast<std::uint8_t>(~(1U << bit)), a));
  }
  CHECK(static_cast<unsigned>(almc_bit::of) == 0x08U);  // counter overflow, d73
  CHECK(static_cast<unsigned>(almc_bit::oh) == 0x10U);  // over-heat, d74
}

TEST_CASE(
    "resolution_for_enid: each known ENID's bits, 16 multi-turn bits, whatever the fallback") {
  // Multi-turn data: 16 bits, 0 to 65,535 (the specification): 16 bits for every ENID.
  const resolution other{20, 12};
  struct known {
    std::uint8_t enid;
    std::uint8_t single_turn_bits;
  };
  for (const known k : {known{0x11, 17}, known{0x17, 23}, known{0x0B, 11}}) {
    CAPTURE(static_cast<int>(k.enid));
    for (const resolution fallback : {resolution{}, other}) {
      const resolution r = resolution_for_enid(k.enid, fallback);
      CHECK(r.single_turn_bits == k.single_turn_bits);
      CHECK(r.multi_turn_bits == 16);
    }
  }
  // an ENID next to a known one is no known code: the fallback
  for (const std::uint8_t enid : {std::uint8_t{0x10}, std::uint8_t{0x12}, std::uint8_t{0x16},
                                  std::uint8_t{0x18}, std::uint8_t{0x0A}, std::uint8_t{0x0C}}) {
    CAPTURE(static_cast<int>(enid));
    CHECK(resolution_for_enid(enid, other).single_turn_bits == 20);
    CHECK(resolution_for_enid(enid, other).multi_turn_bits == 12);
  }
}

TEST_CASE("request and response: a default-constructed one is ID0's, every field 0") {
  const request q;
  CHECK(q.id == data_id::read_abs);
  CHECK(q.cf == 0x02);
  CHECK(q.address == 0);
  CHECK(q.edf == 0);
  CHECK(q.crc == 0);
  const response r;
  CHECK(r.id == data_id::read_abs);
  CHECK(r.cf == 0x02);
  CHECK(r.sf == 0);
  CHECK(r.enid == 0);
  CHECK(r.almc == 0);
  CHECK(r.address == 0);
  CHECK_FALSE(r.busy);
  CHECK(r.edf == 0);
  CHECK(r.crc == 0);
  CHECK(r.abs == 0);
  CHECK(r.abm == 0);
  CHECK_FALSE(r.ea0());
  CHECK_FALSE(r.ea1());
  CHECK_FALSE(r.ca0());
  CHECK_FALSE(r.ca1());
  CHECK(r.layout().size == 6);
}
