// T-format frames shared by the doctest suites: one valid response of every layout, written out
// from the specification's tables, CRCs computed here (the XOR of the fields).
#ifndef MOTIONBUS_TESTS_TFORMAT_HPP
#define MOTIONBUS_TESTS_TFORMAT_HPP

#include <vector>

#include "bytes.hpp"

namespace testutil {

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
