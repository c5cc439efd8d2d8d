// Byte order loads and stores: load_le/load_be of 1 to 8 bytes at any offset (the direct load on
// little-endian GCC/clang hosts, the byte loop in constant evaluation) and the 16-bit forms.
#include "motionbus/core/bytes.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using namespace motionbus;

namespace {

constexpr std::uint8_t seq[10] = {0x01, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF, 0xF0, 0x0F};

// Byte-by-byte models of the two orders.
std::uint64_t model_le(const std::uint8_t* p, unsigned n) {
  std::uint64_t v = 0;
  for (unsigned k = n; k-- > 0;) {
    v = (v << 8U) | p[k];
  }
  return v;
}
std::uint64_t model_be(const std::uint8_t* p, unsigned n) {
  std::uint64_t v = 0;
  for (unsigned k = 0; k < n; ++k) {
    v = (v << 8U) | p[k];
  }
  return v;
}

template <unsigned N>
void check_loads() {
  const byte_view in(seq, sizeof seq);
  for (std::size_t at = 0; at + N <= sizeof seq; ++at) {
    CAPTURE(N);
    CAPTURE(at);
    CHECK(load_le<N>(in, at) == model_le(seq + at, N));
    CHECK(load_be<N>(in, at) == model_be(seq + at, N));
  }
}

// The constant-evaluation path (the byte loop) gives the same values.
static_assert(load_le<3>(byte_view(seq, sizeof seq), 1) == 0x674523U, "load_le in constexpr");
static_assert(load_be<3>(byte_view(seq, sizeof seq), 1) == 0x234567U, "load_be in constexpr");
static_assert(load_be<8>(byte_view(seq, sizeof seq), 2) == 0x456789ABCDEFF00FULL, "load_be 8");

}  // namespace

TEST_CASE("load_le and load_be of 1 to 8 bytes at every offset match the byte-order models") {
  check_loads<1>();
  check_loads<2>();
  check_loads<3>();
  check_loads<4>();
  check_loads<5>();
  check_loads<6>();
  check_loads<7>();
  check_loads<8>();
}

TEST_CASE("load_be16 and load_le16 read the two orders of a 16-bit field") {
  const byte_view in(seq, sizeof seq);
  CHECK(load_be16(in, 0) == 0x0123U);
  CHECK(load_le16(in, 0) == 0x2301U);
  CHECK(load_be16(in, 7) == 0xEFF0U);
  CHECK(load_le16(in, 8) == 0x0FF0U);
}

TEST_CASE("store_be16 and store_le16 write two bytes, read back by the loads, nothing else") {
  std::uint8_t out[4] = {0xAA, 0xAA, 0xAA, 0xAA};
  store_be16(mutable_byte_view(out, 4), 1, 0x1234U);
  CHECK(out[0] == 0xAA);
  CHECK(out[1] == 0x12);
  CHECK(out[2] == 0x34);
  CHECK(out[3] == 0xAA);
  CHECK(load_be16(byte_view(out, 4), 1) == 0x1234U);
  store_le16(mutable_byte_view(out, 4), 2, 0xBEEFU);
  CHECK(out[1] == 0x12);
  CHECK(out[2] == 0xEF);
  CHECK(out[3] == 0xBE);
  CHECK(load_le16(byte_view(out, 4), 2) == 0xBEEFU);
}
