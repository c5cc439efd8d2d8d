// The configuration macros may be overridden: with MOTIONBUS_COLD and MOTIONBUS_INLINE defined
// empty, no compile-time specialisation (MOTIONBUS_CONSTANT_P 0) and bitwise CRCs by default,
// every header still compiles and computes the same.
#define MOTIONBUS_COLD
#define MOTIONBUS_INLINE
#define MOTIONBUS_CONSTANT_P(x) 0
#define MOTIONBUS_CRC_DEFAULT_TABLE 0

#include <cstdint>

#include "motionbus/motionbus.hpp"

namespace {

constexpr std::uint8_t id3[] = {0x1A, 0x00, 0x45, 0x23, 0x01, 0x11, 0x34, 0x12, 0x00, 0x00, 0x00};
constexpr std::uint8_t crc_of_id3() {
  std::uint8_t x = 0;
  for (std::size_t i = 0; i < 10; ++i) {
    x = static_cast<std::uint8_t>(x ^ id3[i]);
  }
  return x;
}
constexpr bool decodes() {
  std::uint8_t f[11] = {};
  for (std::size_t i = 0; i < 10; ++i) {
    f[i] = id3[i];
  }
  f[10] = crc_of_id3();
  const auto r = motionbus::tformat::decode_response(motionbus::byte_view(f, 11));
  return r.is_complete() && r->abs == 0x12345 && r->abm == 0x1234;
}
static_assert(decodes(), "T-format decode with the macros overridden");
static_assert(motionbus::crc6_biss<>::table_entries() == 0, "bitwise by default");
static_assert(motionbus::crc6_biss<>::compute_bits(0x3, 34) == 0x3A, "same CRC6 bitwise");
static_assert(motionbus::crc6_biss<motionbus::crc_table_size::byte>::compute_bits(0x3, 34) == 0x3A,
              "same CRC6 with the byte table and no constant-count steps");

}  // namespace

int main() {
  return 0;
}
