// Typed values over registers (modbus/values.hpp) against a plain reference written from the
// table of docs/modbus.md ("Typed values"): the registers of each order spelled as letters,
// A the most significant byte. Every order, both directions, the special values of
// tests/support/value_samples.hpp (NaN payloads, infinities, -0.0, subnormals, integer extremes).
#include "motionbus/modbus/values.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "../support/value_samples.hpp"
#include "motionbus/modbus.hpp"
#include "motionbus/modbus/pdu_client.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

namespace {

constexpr word_order all_orders[] = {word_order::abcd, word_order::cdab, word_order::badc,
                                     word_order::dcba};

// The registers of each order as the documentation writes them.
std::string pattern(word_order o, std::size_t bytes) {
  if (bytes == 4U) {
    switch (o) {
      case word_order::abcd: return "ABCD";
      case word_order::cdab: return "CDAB";
      case word_order::badc: return "BADC";
      case word_order::dcba: return "DCBA";
    }
  }
  switch (o) {
    case word_order::abcd: return "ABCDEFGH";
    case word_order::cdab: return "GHEFCDAB";
    case word_order::badc: return "BADCFEHG";
    case word_order::dcba: return "HGFEDCBA";
  }
  return "";
}

// Reference: the value's bytes, most significant first (A, B, ...), placed by the pattern.
std::vector<std::uint16_t> reference(std::uint64_t bits, std::size_t bytes, word_order o) {
  std::vector<std::uint8_t> be(bytes);
  for (std::size_t i = 0; i < bytes; ++i) {
    be[i] = static_cast<std::uint8_t>(bits >> (8U * (bytes - 1U - i)));
  }
  const std::string p = pattern(o, bytes);
  std::vector<std::uint16_t> regs;
  for (std::size_t k = 0; k < bytes / 2U; ++k) {
    const auto hi = be[static_cast<std::size_t>(p[2U * k] - 'A')];
    const auto lo = be[static_cast<std::size_t>(p[2U * k + 1U] - 'A')];
    regs.push_back(static_cast<std::uint16_t>((hi << 8U) | lo));
  }
  return regs;
}

template <class T, class U>
U bits_of(T v) {
  U u = 0;
  std::memcpy(&u, &v, sizeof(u));
  return u;
}
template <class T, class U>
T of_bits(U u) {
  T v{};
  std::memcpy(&v, &u, sizeof(v));
  return v;
}

// Both directions for one value: to_registers, put_value (both images) against the reference;
// from_registers, value_at (both images, a read response) back to the same bits.
template <class T, class U>
void check_value(T v) {
  const std::uint64_t bits = bits_of<T, U>(v);
  for (const word_order o : all_orders) {
    CAPTURE(static_cast<int>(o));
    CAPTURE(bits);
    const std::vector<std::uint16_t> want = reference(bits, sizeof(T), o);
    const auto regs = to_registers(v, o);
    CHECK(std::vector<std::uint16_t>(regs.begin(), regs.end()) == want);
    CHECK(bits_of<T, U>(from_registers<T>(regs, o)) == bits);

    std::uint16_t image[6] = {};
    REQUIRE(put_value(span<std::uint16_t>(image), 1, v, o).value_or(0) == registers_of<T>);
    CHECK(std::vector<std::uint16_t>(image + 1, image + 1 + registers_of<T>) == want);
    const result<T> back = value_at<T>(span<const std::uint16_t>(image), 1, o);
    REQUIRE(back.ok());
    CHECK(bits_of<T, U>(back.value()) == bits);

    // a read response carrying the registers after one other register
    std::uint8_t pdu[2 + 2 * 5] = {0x03, static_cast<std::uint8_t>(2U * (1U + registers_of<T>))};
    REQUIRE(put_value(mutable_byte_view(pdu + 2, 2U * (1U + registers_of<T>)), 1, v, o).ok());
    for (std::size_t k = 0; k < registers_of<T>; ++k) {
      CHECK(load_be16(byte_view(pdu), 4U + 2U * k) == want[k]);
    }
    const auto quantity = static_cast<std::uint16_t>(1U + registers_of<T>);
    std::uint8_t sent[5] = {};
    REQUIRE(encode_read(function_code::read_holding_registers, 0, quantity, sent).ok());
    const auto r = decode_response_for(sent, byte_view(pdu, 2U + 2U * quantity));
    REQUIRE(r.is_complete());
    const result<T> read = value_at<T>(r.value(), 1, o);
    REQUIRE(read.ok());
    CHECK(bits_of<T, U>(read.value()) == bits);
  }
}

}  // namespace

TEST_CASE("values: 32-bit integers and floats in every order, both directions") {
  for (const std::uint32_t v : testutil::u32_samples()) {
    check_value<std::uint32_t, std::uint32_t>(v);
  }
  for (const std::int32_t v : testutil::i32_samples()) {
    check_value<std::int32_t, std::uint32_t>(v);
  }
  for (const std::uint32_t b : testutil::f32_bit_samples()) {
    check_value<float, std::uint32_t>(of_bits<float>(b));
  }
}

TEST_CASE("values: 64-bit integers and doubles in every order, both directions") {
  for (const std::uint64_t v : testutil::u64_samples()) {
    check_value<std::uint64_t, std::uint64_t>(v);
  }
  for (const std::int64_t v : testutil::i64_samples()) {
    check_value<std::int64_t, std::uint64_t>(v);
  }
  for (const std::uint64_t b : testutil::f64_bit_samples()) {
    check_value<double, std::uint64_t>(of_bits<double>(b));
  }
}

TEST_CASE("values: the issue's example, 123456.0f, in each order") {
  using regs = std::array<std::uint16_t, 2>;
  CHECK(to_registers(123456.0f, word_order::abcd) == regs{0x47F1, 0x2000});
  CHECK(to_registers(123456.0f, word_order::cdab) == regs{0x2000, 0x47F1});
  CHECK(to_registers(123456.0f, word_order::badc) == regs{0xF147, 0x0020});
  CHECK(to_registers(123456.0f, word_order::dcba) == regs{0x0020, 0xF147});
  // what libmodbus 3.1.6's modbus_set_float_abcd writes is BADC here
  CHECK(from_registers<float>(regs{0xF147, 0x0020}, word_order::badc) == 123456.0f);
}

TEST_CASE("values: integers are constant expressions; floats too with std::bit_cast") {
  static_assert(to_registers(std::uint32_t{0x11223344}, word_order::cdab)[0] == 0x3344, "");
  static_assert(to_registers(std::uint64_t{0x1122334455667788}, word_order::cdab)[0] == 0x7788, "");
  static_assert(to_registers(std::uint64_t{0x1122334455667788}, word_order::badc)[3] == 0x8877, "");
  static_assert(from_registers<std::int32_t>({0xFFFF, 0xFFFE}, word_order::abcd) == -2, "");
  static_assert(from_registers<std::int64_t>({0x0000, 0x0000, 0x0000, 0x0080}, word_order::dcba) ==
                    std::numeric_limits<std::int64_t>::min(),
                "");
  static_assert(registers_of<float> == 2U && registers_of<double> == 4U, "");
#if MOTIONBUS_CONSTEXPR_FLOAT_VALUES
  static_assert(to_registers(123456.0f, word_order::abcd)[0] == 0x47F1, "");
  static_assert(from_registers<double>({0x40FE, 0x2400, 0, 0}, word_order::abcd) == 123456.0, "");
#endif
  // and the same at run time
  const std::uint32_t v = 0x11223344U;
  CHECK(to_registers(v, word_order::dcba) == std::array<std::uint16_t, 2>{0x4433, 0x2211});
}

TEST_CASE("values: out_of_range when the value's registers are not all there; nothing written") {
  std::uint16_t image[3] = {7, 7, 7};
  CHECK(put_value(span<std::uint16_t>(image), 2, 1.0f, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(put_value(span<std::uint16_t>(image), 4, 1.0f, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(put_value(span<std::uint16_t>(image), 0, 1.0, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(image[0] == 7);
  CHECK(image[2] == 7);
  CHECK(put_value(span<std::uint16_t>(image), 1, 1.0f, word_order::abcd).value_or(0) == 2U);
  CHECK(value_at<float>(span<const std::uint16_t>(image), 2, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(value_at<double>(span<const std::uint16_t>(image), 0, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(value_at<float>(span<const std::uint16_t>(image), 9, word_order::abcd).error() ==
        errc::out_of_range);
  std::uint8_t bytes[7] = {};  // three registers and an odd byte
  CHECK(put_value(mutable_byte_view(bytes), 2, std::uint32_t{1}, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(put_value(mutable_byte_view(bytes), 5, std::uint32_t{1}, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(value_at<std::uint32_t>(byte_view(bytes), 2, word_order::abcd).error() ==
        errc::out_of_range);
  CHECK(value_at<std::uint32_t>(byte_view(bytes), 4, word_order::abcd).error() ==
        errc::out_of_range);
  const response exception_response{};  // no data
  CHECK(value_at<float>(exception_response, 0, word_order::abcd).error() == errc::out_of_range);
}

TEST_CASE("values at the last registers; put_value writes its registers and no more") {
  // a 32-bit value in the last two registers of six is there; put_value into big-endian
  // bytes leaves the registers after it as they were
  const std::uint16_t regs[6] = {0, 0, 0, 0, 0x1234, 0x5678};
  CHECK(value_at<std::uint32_t>(span<const std::uint16_t>(regs, 6), 4, word_order::abcd).value() ==
        0x12345678U);
  CHECK(value_at<std::uint32_t>(span<const std::uint16_t>(regs, 6), 5, word_order::abcd).error() ==
        errc::out_of_range);
  std::uint8_t be[12] = {0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5};
  CHECK(put_value<std::uint32_t>(mutable_byte_view(be, 12), 1, 0x12345678U, word_order::abcd)
            .value() == 2U);
  CHECK(std::vector<std::uint8_t>(be, be + 12) ==
        std::vector<std::uint8_t>{0xA5, 0xA5, 0x12, 0x34, 0x56, 0x78, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5,
                                  0xA5});
  CHECK(value_at<std::uint32_t>(byte_view(be, 12), 1, word_order::abcd).value() == 0x12345678U);
  std::uint16_t image[4] = {0xA5A5, 0xA5A5, 0xA5A5, 0xA5A5};
  CHECK(put_value<std::int32_t>(span<std::uint16_t>(image, 4), 1, -2, word_order::abcd).value() ==
        2U);
  CHECK(image[3] == 0xA5A5);
  CHECK(image[0] == 0xA5A5);
}

TEST_CASE("signed values at their limits: the largest and the smallest of each width") {
  // from_bits' two branches meet at the largest value: both sides of it, in each width
  const std::uint16_t i32max[2] = {0x7FFF, 0xFFFF};
  const std::uint16_t i32min[2] = {0x8000, 0x0000};
  CHECK(value_at<std::int32_t>(span<const std::uint16_t>(i32max, 2), 0, word_order::abcd).value() ==
        std::numeric_limits<std::int32_t>::max());
  CHECK(value_at<std::int32_t>(span<const std::uint16_t>(i32min, 2), 0, word_order::abcd).value() ==
        std::numeric_limits<std::int32_t>::min());
  const std::uint16_t i64max[4] = {0x7FFF, 0xFFFF, 0xFFFF, 0xFFFF};
  const std::uint16_t i64min[4] = {0x8000, 0, 0, 0};
  CHECK(value_at<std::int64_t>(span<const std::uint16_t>(i64max, 4), 0, word_order::abcd).value() ==
        std::numeric_limits<std::int64_t>::max());
  CHECK(value_at<std::int64_t>(span<const std::uint16_t>(i64min, 4), 0, word_order::abcd).value() ==
        std::numeric_limits<std::int64_t>::min());
}
