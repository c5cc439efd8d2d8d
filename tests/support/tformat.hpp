// T-format frames shared by the doctest suites: one valid response of every layout, written out
// from the specification's tables, CRCs computed here (the XOR of the fields); the control
// field bits of every Data ID (spec Table 1).
#ifndef MOTIONBUS_TESTS_TFORMAT_HPP
#define MOTIONBUS_TESTS_TFORMAT_HPP

#include <cstdint>
#include <vector>

#include "bytes.hpp"
#include "motionbus/tformat/frame.hpp"

namespace testutil {

// Spec Table 1: cc0..cc4 for each Data ID.
struct table1_row {
  motionbus::tformat::data_id id;
  int cc[5];
};
inline constexpr table1_row table1[] = {
    {motionbus::tformat::data_id::read_abs, {0, 0, 0, 0, 0}},
    {motionbus::tformat::data_id::read_abm, {1, 0, 0, 0, 1}},
    {motionbus::tformat::data_id::read_enid, {0, 1, 0, 0, 1}},
    {motionbus::tformat::data_id::read_all, {1, 1, 0, 0, 0}},
    {motionbus::tformat::data_id::eeprom_write, {0, 1, 1, 0, 0}},
    {motionbus::tformat::data_id::eeprom_read, {1, 0, 1, 1, 1}},
    {motionbus::tformat::data_id::reset_errors, {1, 1, 1, 0, 1}},
    {motionbus::tformat::data_id::reset_single_turn, {0, 0, 0, 1, 1}},
    {motionbus::tformat::data_id::reset_multi_turn, {0, 0, 1, 1, 0}},
};

inline std::uint8_t cf_from_table(const table1_row& row) {
  // sync 010 in bits 0..2, cc0..cc4 in bits 3..7 (docs/tformat.md §7: bit order on the line)
  unsigned v = 0x02;
  for (unsigned i = 0; i < 5; ++i) {
    v |= static_cast<unsigned>(row.cc[i]) << (3U + i);
  }
  return static_cast<std::uint8_t>(v);
}

inline std::vector<bytes> valid_responses() {
  return {
      with_crc({0x02, 0x00, 0x40, 0xE2, 0x01}),                                // ID0 abs 123456
      with_crc({0x8A, 0x00, 0x34, 0x12, 0x00}),                                // ID1 abm 0x1234
      with_crc({0x92, 0x00, 0x11}),                                            // ID2 enid 0x11
      with_crc({0x1A, 0x20, 0xFF, 0xFF, 0x01, 0x11, 0xFF, 0xFF, 0x00, 0xC0}),  // ID3
      with_crc({0x32, 0x05, 0x12}),                                            // ID6 echo
      with_crc({0xEA, 0x05, 0x77}),                                            // IDD data
      with_crc({0xEA, 0x85, 0x00}),                                            // IDD busy
      with_crc({0xBA, 0x10, 0x00, 0x00, 0x00}),                                // ID7
      with_crc({0xC2, 0x00, 0x01, 0x00, 0x00}),                                // ID8
      with_crc({0x62, 0x00, 0x02, 0x00, 0x00}),                                // IDC
  };
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_TFORMAT_HPP
