// The values the typed-value tests convert (tests/modbus/values_test.cpp and the pymodbus and
// libmodbus comparison, tests/interop/values_dump.cpp): integer extremes, and for floats the
// special values given by their bits (NaNs with payloads, quiet and signalling, either sign;
// the infinities; -0.0; the smallest and largest subnormals; the extremes of the normals).
#ifndef MOTIONBUS_TESTS_SUPPORT_VALUE_SAMPLES_HPP
#define MOTIONBUS_TESTS_SUPPORT_VALUE_SAMPLES_HPP

#include <cstdint>
#include <limits>
#include <vector>

namespace testutil {

inline std::vector<std::uint32_t> u32_samples() {
  return {0U, 1U, 0x12345678U, 0x80000000U, 0x7FFFFFFFU, 0xFFFFFFFFU, 0x47F12000U};
}
inline std::vector<std::int32_t> i32_samples() {
  return {0,
          1,
          -1,
          123456,
          -123456,
          std::numeric_limits<std::int32_t>::min(),
          std::numeric_limits<std::int32_t>::max()};
}
inline std::vector<std::uint64_t> u64_samples() {
  return {0U,
          1U,
          0x0123456789ABCDEFULL,
          0x8000000000000000ULL,
          0x7FFFFFFFFFFFFFFFULL,
          0xFFFFFFFFFFFFFFFFULL};
}
inline std::vector<std::int64_t> i64_samples() {
  return {0,
          1,
          -1,
          -1234567890123LL,
          std::numeric_limits<std::int64_t>::min(),
          std::numeric_limits<std::int64_t>::max()};
}
/// binary32 bit patterns
inline std::vector<std::uint32_t> f32_bit_samples() {
  return {
      0x47F12000U,  // 123456.0
      0x3F800000U,  // 1.0
      0xBF800000U,  // -1.0
      0x00000000U,  // +0.0
      0x80000000U,  // -0.0
      0x7F800000U,  // +inf
      0xFF800000U,  // -inf
      0x7FC00000U,  // quiet NaN
      0x7FC00001U,  // quiet NaN, payload 1
      0xFFC12345U,  // negative quiet NaN with a payload
      0x7FA00005U,  // signalling NaN with a payload
      0x00000001U,  // smallest subnormal
      0x807FFFFFU,  // largest subnormal, negative
      0x00800000U,  // smallest normal
      0x7F7FFFFFU,  // largest finite
      0xFF7FFFFFU,  // lowest finite
  };
}
/// binary64 bit patterns
inline std::vector<std::uint64_t> f64_bit_samples() {
  return {
      0x40FE240000000000ULL,  // 123456.0
      0x3FF0000000000000ULL,  // 1.0
      0x0000000000000000ULL,  // +0.0
      0x8000000000000000ULL,  // -0.0
      0x7FF0000000000000ULL,  // +inf
      0xFFF0000000000000ULL,  // -inf
      0x7FF8000000000000ULL,  // quiet NaN
      0x7FF8000000000001ULL,  // quiet NaN, payload 1
      0xFFF80000DEADBEEFULL,  // negative quiet NaN with a payload
      0x7FF4000000000005ULL,  // signalling NaN with a payload
      0x0000000000000001ULL,  // smallest subnormal
      0x800FFFFFFFFFFFFFULL,  // largest subnormal, negative
      0x0010000000000000ULL,  // smallest normal
      0x7FEFFFFFFFFFFFFFULL,  // largest finite
      0xFFEFFFFFFFFFFFFFULL,  // lowest finite
  };
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_SUPPORT_VALUE_SAMPLES_HPP
