// CRC engine: published check values, every table size against the bitwise form and an
// independent long-division reference, the bit-granular paths, incremental use.
#include "motionbus/core/crc.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "../support/prng.hpp"
#include "../support/reference_crc.hpp"
#include "../support/run_time.hpp"

using namespace motionbus;

namespace {

constexpr std::uint8_t check_input[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

template <class Spec>
ref::model model_of() {
  return ref::model{Spec::width, Spec::poly, Spec::init, Spec::refin, Spec::refout, Spec::xorout};
}

template <class Spec>
std::uint32_t all_tables_agree_bits(std::uint64_t bits, unsigned count) {
  const std::uint32_t a = crc<Spec, crc_table_size::bitwise>::compute_bits(bits, count);
  const std::uint32_t b = crc<Spec, crc_table_size::nibble>::compute_bits(bits, count);
  const std::uint32_t c = crc<Spec, crc_table_size::byte>::compute_bits(bits, count);
  const std::uint32_t d = crc<Spec, crc_table_size::slice4>::compute_bits(bits, count);
  const std::uint32_t e = crc<Spec, crc_table_size::slice8>::compute_bits(bits, count);
  REQUIRE(a == b);
  REQUIRE(a == c);
  REQUIRE(a == d);
  REQUIRE(a == e);
  return a;
}

// The bits of `bits` (low `count`) in the order update_bits feeds them.
template <class Spec>
std::vector<int> fed_order(std::uint64_t bits, unsigned count) {
  std::vector<int> out;
  for (unsigned i = 0; i < count; ++i) {
    const unsigned shift = Spec::refin ? i : count - 1U - i;
    out.push_back(static_cast<int>((bits >> shift) & 1U));
  }
  return out;
}

// Every bit string of length 0..16: reference == bitwise == nibble == byte.
template <class Spec>
void exhaustive_up_to_16_bits() {
  const ref::model m = model_of<Spec>();
  std::size_t checked = 0;
  for (unsigned count = 0; count <= 16U; ++count) {
    for (std::uint64_t v = 0; v < (std::uint64_t{1} << count); ++v) {
      const std::uint32_t engine = all_tables_agree_bits<Spec>(v, count);
      const std::uint32_t reference = ref::crc_of_bits(m, fed_order<Spec>(v, count));
      if (engine != reference) {
        FAIL_CHECK("count=" << count << " value=" << v << " engine=" << engine
                            << " reference=" << reference);
        return;
      }
      ++checked;
    }
  }
  CHECK(checked == (std::size_t{1} << 17U) - 1U);
}

// Random byte strings up to 300 bytes, random split points and random bit-stream offsets.
template <class Spec>
void random_long_inputs(std::uint64_t seed) {
  const ref::model m = model_of<Spec>();
  testutil::splitmix64 rng(seed);
  for (int iteration = 0; iteration < 300; ++iteration) {
    std::vector<std::uint8_t> data(static_cast<std::size_t>(rng.below(301)));
    for (auto& b : data) {
      b = rng.byte();
    }
    const byte_view view(data.data(), data.size());
    const std::uint32_t reference = ref::crc_of_bytes(m, data);
    REQUIRE(crc<Spec, crc_table_size::bitwise>::compute(view) == reference);
    REQUIRE(crc<Spec, crc_table_size::nibble>::compute(view) == reference);
    REQUIRE(crc<Spec, crc_table_size::byte>::compute(view) == reference);
    REQUIRE(crc<Spec, crc_table_size::slice4>::compute(view) == reference);
    REQUIRE(crc<Spec, crc_table_size::slice8>::compute(view) == reference);

    // Incremental: split anywhere, feed byte-wise, then bit-wise in random-sized pieces.
    const std::size_t split =
        data.empty() ? 0 : static_cast<std::size_t>(rng.below(data.size() + 1));
    crc<Spec> inc;
    inc.update(view.first(split)).update(view.subspan(split));
    REQUIRE(inc.value() == reference);

    crc<Spec, crc_table_size::nibble> by_bits;
    for (std::uint8_t b : data) {
      // a byte in CRC order, cut into pieces of 1..8 bits, fed in that order
      unsigned left = 8;
      while (left > 0) {
        const unsigned n = 1U + static_cast<unsigned>(rng.below(left));
        std::uint64_t piece = 0;
        if (Spec::refin) {
          piece = (b >> (8U - left)) & ((1U << n) - 1U);
        } else {
          piece = (b >> (left - n)) & ((1U << n) - 1U);
        }
        by_bits.update_bits(piece, n);
        left -= n;
      }
    }
    REQUIRE(by_bits.value() == reference);

    // A stream whose bits sit at an arbitrary offset: bytes written in the CRC's order.
    if (!data.empty()) {
      const std::size_t offset = static_cast<std::size_t>(rng.below(17));
      const bit_order order = Spec::refin ? bit_order::lsb_first : bit_order::msb_first;
      std::vector<std::uint8_t> stream(data.size() + 3U, 0xA5);
      bit_writer w(mutable_byte_view(stream.data(), stream.size()), order, offset);
      for (std::uint8_t b : data) {
        REQUIRE(w.write(b, 8U) == errc::ok);
      }
      crc<Spec> s;
      REQUIRE(s.update_stream(byte_view(stream.data(), stream.size()), order, offset,
                              data.size() * 8U) == errc::ok);
      REQUIRE(s.value() == reference);
    }
  }
}

}  // namespace

TEST_CASE("named CRCs: published and independent check values, every table size") {
  // CRC-16/MODBUS check value, CRC catalogue (reveng) and Modbus over Serial Line V1.02.
  CHECK(crc16_modbus<crc_table_size::byte>::compute(check_input) == 0x4B37);
  CHECK(crc16_modbus<crc_table_size::nibble>::compute(check_input) == 0x4B37);
  CHECK(crc16_modbus<crc_table_size::bitwise>::compute(check_input) == 0x4B37);
  // Modbus over Serial Line example frame 11 03 00 6B 00 03 -> CRC bytes 76 87 (low first).
  constexpr std::uint8_t frame[] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03};
  CHECK(crc16_modbus<>::compute(frame) == 0x8776);

  // T-format (G = X^8 + 1): the XOR of the bytes.
  std::uint8_t x = 0;
  for (std::uint8_t b : check_input) {
    x = static_cast<std::uint8_t>(x ^ b);
  }
  CHECK(crc8_tformat<crc_table_size::byte>::compute(check_input) == x);
  CHECK(crc8_tformat<crc_table_size::nibble>::compute(check_input) == x);
  CHECK(crc8_tformat<crc_table_size::bitwise>::compute(check_input) == x);
  CHECK(x == 0x31);

  // BiSS CRC6 / CRC4: no catalogue entry; check value from the independent reference.
  CHECK(crc6_biss<>::compute(check_input) ==
        ref::crc_of_bytes(model_of<crc6_biss_spec>(), {check_input, check_input + 9}));
  CHECK(crc4_biss<>::compute(check_input) ==
        ref::crc_of_bytes(model_of<crc4_biss_spec>(), {check_input, check_input + 9}));
  CHECK(crc6_biss<>::compute(check_input) == 0x2E);
  CHECK(crc4_biss<>::compute(check_input) == 0x1);
}

TEST_CASE("BiSS CRC6 of a sensor frame's bits, inverted on the wire") {
  // 32-bit position, nE = 1, nW = 1: 34 bits MSB first. Reference computes the same bits.
  const std::uint64_t position = 0x12345678U;
  const std::uint64_t bits = (position << 2U) | 0x3U;
  const std::uint32_t expected =
      ref::crc_of_bits(model_of<crc6_biss_spec>(), fed_order<crc6_biss_spec>(bits, 34));
  CHECK(crc6_biss<crc_table_size::byte>::compute_bits(bits, 34) == expected);
  CHECK(crc6_biss<crc_table_size::nibble>::compute_bits(bits, 34) == expected);
  CHECK(crc6_biss<crc_table_size::bitwise>::compute_bits(bits, 34) == expected);
  // "Inverted": the raw remainder XOR 0x3F.
  using raw6 = crc<crc_spec<6, 0x03, 0, false, false, 0>>;
  CHECK((raw6::compute_bits(bits, 34) ^ 0x3FU) == expected);
}

namespace {

// update_bits in the byte steps of the MSB-first 8-bit-register kernels (every count of 8 and
// more) after a first field that leaves the register non-zero, against the reference fed the
// same bits: with the count a compile-time constant once inlined (the steps unrolled inline, at
// -O1 and above) and with the same count known only at run time (the shared kernel's loop).
template <class Spec, unsigned Count>
void constant_count_matches_reference(std::uint64_t first, std::uint64_t second) {
  using engine = crc<Spec, crc_table_size::byte>;
  const std::uint32_t got = engine().update_bits(first, 13).update_bits(second, Count).value();
  std::vector<int> bits = fed_order<Spec>(first, 13);
  const std::vector<int> more = fed_order<Spec>(second, Count);
  bits.insert(bits.end(), more.begin(), more.end());
  CHECK(got == ref::crc_of_bits(model_of<Spec>(), bits));
  CHECK(engine::compute_bits(second, Count) ==
        ref::crc_of_bits(model_of<Spec>(), fed_order<Spec>(second, Count)));
  const unsigned run_time_count = testutil::at_run_time(Count);
  CHECK(engine().update_bits(first, 13).update_bits(second, run_time_count).value() == got);
}

template <class Spec, unsigned... Counts>
void every_constant_count(std::integer_sequence<unsigned, Counts...>) {
  testutil::splitmix64 rng(Spec::width);
  for (int round = 0; round < 20; ++round) {
    const std::uint64_t first = rng.next();
    const std::uint64_t second = rng.next();
    (constant_count_matches_reference<Spec, Counts + 8U>(first, second), ...);
  }
}

}  // namespace

TEST_CASE("update_bits with a count of 8..64 bits, constant or not: byte steps vs the reference") {
  every_constant_count<crc6_biss_spec>(std::make_integer_sequence<unsigned, 57>());
  every_constant_count<crc4_biss_spec>(std::make_integer_sequence<unsigned, 57>());
}

namespace {

// compute_bits in constant evaluation (where MOTIONBUS_CONSTANT_P sees the count, as an
// optimiser that inlines a fixed count does) and at run time, against the reference.
template <class Spec, unsigned Count>
void constant_evaluation_matches(std::uint64_t bits) {
  using engine = crc<Spec, crc_table_size::byte>;
  constexpr std::uint64_t fixed = 0x0123456789ABCDEFULL;
  constexpr std::uint32_t folded = engine::compute_bits(fixed, Count);
  constexpr std::uint64_t mask =
      Count == 64U ? ~std::uint64_t{0} : (std::uint64_t{1} << Count) - 1U;
  CHECK(folded == ref::crc_of_bits(model_of<Spec>(), fed_order<Spec>(fixed & mask, Count)));
  CHECK(engine::compute_bits(bits, testutil::at_run_time(Count)) ==
        ref::crc_of_bits(model_of<Spec>(), fed_order<Spec>(bits & mask, Count)));
}

}  // namespace

TEST_CASE("compute_bits with a count known at compile time: every kind of CRC, not only BiSS") {
  // The constant-count byte steps are for MSB-first CRCs in a one-byte register; reflected and
  // wider CRCs must keep the shared kernel however the count is known.
  using xmodem = crc_spec<16, 0x1021, 0x0000, false, false, 0x0000>;
  using crc32 = crc_spec<32, 0x04C11DB7, 0xFFFFFFFF, true, true, 0xFFFFFFFF>;
  constant_evaluation_matches<crc16_modbus_spec, 40>(0x5A5A5A5A5AULL);
  constant_evaluation_matches<crc8_tformat_spec, 24>(0xC0FFEEULL);
  constant_evaluation_matches<xmodem, 33>(0x1DEADBEEFULL);
  constant_evaluation_matches<crc32, 64>(0xFEDCBA9876543210ULL);
  constant_evaluation_matches<crc6_biss_spec, 34>(0x3FFFFFFFFULL);
}

TEST_CASE("exhaustive: every input up to 16 bits, all table sizes vs the reference") {
  SUBCASE("T-format") {
    exhaustive_up_to_16_bits<crc8_tformat_spec>();
  }
  SUBCASE("CRC-16/MODBUS") {
    exhaustive_up_to_16_bits<crc16_modbus_spec>();
  }
  SUBCASE("BiSS CRC6") {
    exhaustive_up_to_16_bits<crc6_biss_spec>();
  }
  SUBCASE("BiSS CRC4") {
    exhaustive_up_to_16_bits<crc4_biss_spec>();
  }
}

TEST_CASE("random longer inputs: tables, reference, incremental and bit-stream paths agree") {
  random_long_inputs<crc8_tformat_spec>(1);
  random_long_inputs<crc16_modbus_spec>(2);
  random_long_inputs<crc6_biss_spec>(3);
  random_long_inputs<crc4_biss_spec>(4);
}

TEST_CASE("polynomial x^W + 1: the T-format CRC's XOR of the bytes at width 8 only") {
  // From width 8 up, the MSB-first table of x^W + 1 is the identity (a byte's register change
  // is the byte itself), yet only at width 8 is the CRC the XOR of the bytes: at the other
  // widths it is the XOR of W-bit words, which the engine must look up. (Reflected, the
  // entries are i << (W - 8): the identity at width 8 only.)
  random_long_inputs<crc_spec<16, 0x0001, 0x0000, true, true, 0x0000>>(6);
  random_long_inputs<crc_spec<16, 0x0001, 0xFFFF, false, false, 0x0000>>(7);
  random_long_inputs<crc_spec<32, 0x00000001, 0x00000000, true, true, 0xFFFFFFFF>>(8);
  random_long_inputs<crc_spec<12, 0x001, 0x000, false, false, 0x000>>(9);
  random_long_inputs<crc_spec<8, 0x01, 0xFF, false, false, 0x00>>(10);
}

TEST_CASE(
    "value_before: the last byte's step run backwards; from 0, init exactly where a frame starts") {
  testutil::splitmix64 rng(5);
  for (int k = 0; k < 2000; ++k) {
    std::vector<std::uint8_t> m(1U + static_cast<std::size_t>(rng.below(40)));
    for (auto& b : m) {
      b = rng.byte();
    }
    const auto all = crc16_modbus<>::compute(byte_view(m.data(), m.size()));
    const auto but_last = crc16_modbus<>::compute(byte_view(m.data(), m.size() - 1U));
    CHECK(crc16_modbus<>::value_before(all, m.back()) == but_last);
    CHECK(crc16_modbus<crc_table_size::bitwise>::value_before(all, m.back()) == but_last);
  }
  // noise, then a message and its CRC (low byte first): taken back from 0 over the bytes, the
  // value is the CRC of nothing (init) where the message starts, and (this seed) nowhere else
  const std::vector<std::uint8_t> message = {0x11, 0x41, 0x01, 0x02};
  const auto c = crc16_modbus<>::compute(byte_view(message.data(), message.size()));
  std::vector<std::uint8_t> line;  // built by push_back (gcc 12's -Warray-bounds and insert())
  for (int k = 0; k < 60; ++k) {
    line.push_back(rng.byte());
  }
  for (const std::uint8_t b : message) {
    line.push_back(b);
  }
  line.push_back(static_cast<std::uint8_t>(c & 0xFFU));
  line.push_back(static_cast<std::uint8_t>(c >> 8U));
  std::vector<std::size_t> starts;
  std::uint32_t v = 0;
  for (std::size_t i = line.size(); i > 0U; --i) {
    v = crc16_modbus<>::value_before(v, line[i - 1U]);
    if (v == crc16_modbus_spec::init) {
      starts.push_back(i - 1U);
    }
  }
  CHECK(starts == std::vector<std::size_t>{60});
  static_assert(crc16_modbus<>::value_before(0x4B37, '9') ==
                    crc16_modbus<>::compute(byte_view(check_input, 8)),
                "constant-evaluated");
}

namespace {

// Catalogued CRCs (reveng CRC catalogue) covering widths 3..32, both reflections, refin !=
// refout, non-zero and asymmetric init and xorout.
template <unsigned W, std::uint32_t P, std::uint32_t I, bool RI, bool RO, std::uint32_t X,
          std::uint32_t Check>
void check_catalogue_entry() {
  using spec = crc_spec<W, P, I, RI, RO, X>;
  CHECK(crc<spec, crc_table_size::byte>::compute(check_input) == Check);
  CHECK(crc<spec, crc_table_size::nibble>::compute(check_input) == Check);
  CHECK(crc<spec, crc_table_size::bitwise>::compute(check_input) == Check);
  CHECK(crc<spec, crc_table_size::slice4>::compute(check_input) == Check);
  CHECK(crc<spec, crc_table_size::slice8>::compute(check_input) == Check);
  CHECK(ref::crc_of_bytes(model_of<spec>(), {check_input, check_input + 9}) == Check);
}

}  // namespace

TEST_CASE("engine parameters: catalogue check values across widths and options") {
  check_catalogue_entry<3, 0x3, 0x0, false, false, 0x7, 0x4>();               // CRC-3/GSM
  check_catalogue_entry<3, 0x3, 0x7, true, true, 0x0, 0x6>();                 // CRC-3/ROHC
  check_catalogue_entry<4, 0x3, 0x0, true, true, 0x0, 0x7>();                 // CRC-4/G-704
  check_catalogue_entry<4, 0x3, 0xF, false, false, 0xF, 0xB>();               // CRC-4/INTERLAKEN
  check_catalogue_entry<5, 0x09, 0x09, false, false, 0x00, 0x00>();           // CRC-5/EPC-C1G2
  check_catalogue_entry<5, 0x05, 0x1F, true, true, 0x1F, 0x19>();             // CRC-5/USB
  check_catalogue_entry<6, 0x27, 0x3F, false, false, 0x00, 0x0D>();           // CRC-6/CDMA2000-A
  check_catalogue_entry<6, 0x03, 0x00, true, true, 0x00, 0x06>();             // CRC-6/G-704
  check_catalogue_entry<6, 0x2F, 0x00, false, false, 0x3F, 0x13>();           // CRC-6/GSM
  check_catalogue_entry<7, 0x09, 0x00, false, false, 0x00, 0x75>();           // CRC-7/MMC
  check_catalogue_entry<7, 0x45, 0x00, false, false, 0x00, 0x61>();           // CRC-7/UMTS
  check_catalogue_entry<8, 0x07, 0x00, false, false, 0x00, 0xF4>();           // CRC-8/SMBUS
  check_catalogue_entry<8, 0x31, 0x00, true, true, 0x00, 0xA1>();             // CRC-8/MAXIM-DOW
  check_catalogue_entry<10, 0x233, 0x000, false, false, 0x000, 0x199>();      // CRC-10/ATM
  check_catalogue_entry<11, 0x385, 0x01A, false, false, 0x000, 0x5A3>();      // CRC-11/FLEXRAY
  check_catalogue_entry<12, 0x80F, 0x000, false, false, 0x000, 0xF5B>();      // CRC-12/DECT
  check_catalogue_entry<12, 0x80F, 0x000, false, true, 0x000, 0xDAF>();       // CRC-12/UMTS
  check_catalogue_entry<12, 0xF13, 0xFFF, false, false, 0x000, 0xD4D>();      // CRC-12/CDMA2000
  check_catalogue_entry<15, 0x4599, 0x0000, false, false, 0x0000, 0x059E>();  // CRC-15/CAN
  check_catalogue_entry<16, 0x8005, 0x0000, true, true, 0x0000, 0xBB3D>();    // CRC-16/ARC
  check_catalogue_entry<16, 0x1021, 0x0000, false, false, 0x0000, 0x31C3>();  // CRC-16/XMODEM
  check_catalogue_entry<16, 0x1021, 0xFFFF, false, false, 0x0000, 0x29B1>();  // CRC-16/IBM-3740
  check_catalogue_entry<16, 0x1021, 0x0000, true, true, 0x0000, 0x2189>();    // CRC-16/KERMIT
  check_catalogue_entry<17, 0x1685B, 0x0, false, false, 0x0, 0x4F03>();       // CRC-17/CAN-FD
  check_catalogue_entry<21, 0x102899, 0x0, false, false, 0x0, 0xED841>();     // CRC-21/CAN-FD
  check_catalogue_entry<32, 0x04C11DB7, 0xFFFFFFFF, true, true, 0xFFFFFFFF, 0xCBF43926>();
  check_catalogue_entry<32, 0x04C11DB7, 0xFFFFFFFF, false, false, 0xFFFFFFFF, 0xFC891918>();
}

namespace {

template <unsigned W, bool Reflected>
void width_sweep_one(testutil::splitmix64& rng) {
  // An arbitrary polynomial with the x^0 term, init and xorout of this width.
  constexpr std::uint32_t mask = W >= 32U ? 0xFFFFFFFFU : ((1U << W) - 1U);
  constexpr std::uint32_t poly = (0x9A3C5E77U & mask) | 1U;
  constexpr std::uint32_t init = 0x5A5A5A5AU & mask;
  constexpr std::uint32_t xorout = 0x0F0F0F0FU & mask;
  using spec = crc_spec<W, poly, init, Reflected, Reflected, xorout>;
  const ref::model m = model_of<spec>();
  for (int i = 0; i < 40; ++i) {
    const unsigned count = static_cast<unsigned>(rng.below(65));
    const std::uint64_t bits = rng.next();
    const std::uint64_t masked = count == 64U ? bits : (bits & ((std::uint64_t{1} << count) - 1U));
    const std::uint32_t engine = all_tables_agree_bits<spec>(bits, count);
    REQUIRE(engine == ref::crc_of_bits(m, fed_order<spec>(masked, count)));
  }
}

template <bool Reflected, unsigned... W>
void width_sweep(testutil::splitmix64& rng, std::integer_sequence<unsigned, W...>) {
  (width_sweep_one<W + 1U, Reflected>(rng), ...);
}

}  // namespace

TEST_CASE("every width 1..32, both reflections: tables and bits vs the reference") {
  testutil::splitmix64 rng(99);
  width_sweep<false>(rng, std::make_integer_sequence<unsigned, 32>{});
  width_sweep<true>(rng, std::make_integer_sequence<unsigned, 32>{});
}

TEST_CASE("update_bits ignores bits above the count; update(byte) == update_bits(byte, 8)") {
  CHECK(crc6_biss<>::compute_bits(0xFFFFFF00U | 0x2DU, 8) == crc6_biss<>::compute_bits(0x2D, 8));
  crc16_modbus<> a;
  crc16_modbus<> b;
  a.update(std::uint8_t{0x5C});
  b.update_bits(0x5C, 8);
  CHECK(a.value() == b.value());
  // counts above 64 are clamped to 64
  CHECK(crc16_modbus<>::compute_bits(0x0123456789ABCDEFULL, 99) ==
        crc16_modbus<>::compute_bits(0x0123456789ABCDEFULL, 64));
  // reset restarts from the initial value
  a.reset();
  CHECK(a.value() == crc16_modbus<>::compute(byte_view{}));
}

TEST_CASE("update_stream: words of 16 and 32 bits, truncation leaves the CRC unchanged") {
  // The 34 BiSS bits of a frame, written MSB first into 32-bit words at offset 5.
  const std::uint64_t bits = (std::uint64_t{0xCAFEF00DU} << 2U) | 0x2U;
  std::uint32_t words[3] = {0, 0, 0};
  basic_bit_writer<std::uint32_t> w(span<std::uint32_t>(words, 3), bit_order::msb_first, 5);
  REQUIRE(w.write(bits, 34) == errc::ok);
  crc6_biss<> c;
  REQUIRE(c.update_stream(span<const std::uint32_t>(words, 3), bit_order::msb_first, 5, 34) ==
          errc::ok);
  CHECK(c.value() == crc6_biss<>::compute_bits(bits, 34));

  std::uint16_t halfwords[3] = {0, 0, 0};
  basic_bit_writer<std::uint16_t> w16(span<std::uint16_t>(halfwords, 3), bit_order::lsb_first, 3);
  REQUIRE(w16.write(0x1234, 16) == errc::ok);
  REQUIRE(w16.write(0x5678, 16) == errc::ok);
  crc16_modbus<> m;
  REQUIRE(m.update_stream(span<const std::uint16_t>(halfwords, 3), bit_order::lsb_first, 3, 32) ==
          errc::ok);
  constexpr std::uint8_t le[] = {0x34, 0x12, 0x78, 0x56};
  CHECK(m.value() == crc16_modbus<>::compute(le));

  crc6_biss<> t;
  const auto before = t.value();
  CHECK(t.update_stream(span<const std::uint32_t>(words, 3), bit_order::msb_first, 60, 37) ==
        errc::truncated);
  CHECK(t.update_stream(span<const std::uint32_t>(words, 3), bit_order::msb_first, 97, 0) ==
        errc::truncated);
  CHECK(t.value() == before);
  // the end is a position: no bits from it, and the last bits up to it, are not truncated
  CHECK(t.update_stream(span<const std::uint32_t>(words, 3), bit_order::msb_first, 96, 0) ==
        errc::ok);
  CHECK(t.value() == before);
  std::uint32_t tail[3] = {0, 0, 0};
  basic_bit_writer<std::uint32_t> wt(span<std::uint32_t>(tail, 3), bit_order::msb_first, 62);
  REQUIRE(wt.write(bits, 34) == errc::ok);
  CHECK(t.update_stream(span<const std::uint32_t>(tail, 3), bit_order::msb_first, 62, 34) ==
        errc::ok);
  CHECK(t.value() == crc6_biss<>::compute_bits(bits, 34));
}

TEST_CASE("dynamic_crc: run-time parameters, every reflection, against the reference model") {
  // Each combination of refin and refout, widths below, at and above a byte, against the
  // independent long division of tests/support/reference_crc.hpp.
  const std::vector<std::uint8_t> msg = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  const crc_parameters cases[] = {
      {16, 0x8005, 0xFFFF, true, true, 0x0000},               // CRC-16/MODBUS: 0x4B37
      {16, 0x1021, 0xFFFF, false, false, 0x0000},             // CRC-16/CCITT-FALSE: 0x29B1
      {16, 0x8005, 0xFFFF, true, false, 0x0000},              // refin alone
      {16, 0x1021, 0x1D0F, false, true, 0x00FF},              // refout alone
      {6, 0x03, 0x00, false, false, 0x3F},                    // BiSS-C's, narrower than a byte
      {5, 0x15, 0x1F, true, true, 0x1F},                      // reflected, narrower than a byte
      {32, 0x04C11DB7, 0xFFFFFFFF, true, true, 0xFFFFFFFF}};  // CRC-32: 0xCBF43926
  for (const crc_parameters& p : cases) {
    CAPTURE(p.width);
    CAPTURE(p.poly);
    CAPTURE(p.refin);
    CAPTURE(p.refout);
    REQUIRE(p.valid());
    dynamic_crc c(p);
    CHECK(c.parameters() == p);
    c.update(byte_view(msg.data(), msg.size()));
    CHECK(c.value() ==
          ref::crc_of_bytes({p.width, p.poly, p.init, p.refin, p.refout, p.xorout}, msg));
  }
  CHECK(dynamic_crc(cases[0]).update(byte_view(msg.data(), msg.size())).value() == 0x4B37U);
  CHECK(dynamic_crc(cases[1]).update(byte_view(msg.data(), msg.size())).value() == 0x29B1U);
  CHECK(dynamic_crc(cases[6]).update(byte_view(msg.data(), msg.size())).value() == 0xCBF43926U);
}

TEST_CASE("crc_parameters: valid() refuses each out-of-range value alone; dynamic_crc clamps") {
  const crc_parameters good{8, 0x07, 0x00, false, false, 0x00};
  CHECK(good.valid());
  // the defaults are this CRC-8 (CRC-8/SMBUS in the CRC catalogue, check value 0xF4)
  constexpr std::uint8_t nine[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  CHECK(crc_parameters{} == good);
  CHECK(dynamic_crc(crc_parameters{}).update(nine).value() == 0xF4U);
  // width 1 is the narrowest valid one, its parameters kept as given
  const crc_parameters one{1, 1, 1, true, false, 1};
  CHECK(one.valid());
  CHECK(dynamic_crc(one).parameters() == one);
  crc_parameters p = good;
  p.width = 0;
  CHECK_FALSE(p.valid());
  p.width = 33;
  CHECK_FALSE(p.valid());
  p = good;
  p.poly = 0x107;
  CHECK_FALSE(p.valid());
  p = good;
  p.init = 0x100;
  CHECK_FALSE(p.valid());
  p = good;
  p.xorout = 0x100;
  CHECK_FALSE(p.valid());
  // invalid parameters become a 1-bit CRC of polynomial 1 (the parity of the bits fed)
  dynamic_crc c(p);
  CHECK(c.parameters() == crc_parameters{1, 1, 0, false, false, 0});
  CHECK(c.update_bits(0x7, 3).value() == 1U);
  CHECK(c.update_bits(0x1, 1).value() == 0U);
}

TEST_CASE("crc_parameters: == compares every field, each one alone") {
  const crc_parameters p{16, 0x8005, 0xFFFF, true, true, 0x0000};
  CHECK(p == crc_parameters{16, 0x8005, 0xFFFF, true, true, 0x0000});
  CHECK(p != crc_parameters{15, 0x8005, 0xFFFF, true, true, 0x0000});
  CHECK(p != crc_parameters{16, 0x8004, 0xFFFF, true, true, 0x0000});
  CHECK(p != crc_parameters{16, 0x8005, 0xFFFE, true, true, 0x0000});
  CHECK(p != crc_parameters{16, 0x8005, 0xFFFF, false, true, 0x0000});
  CHECK(p != crc_parameters{16, 0x8005, 0xFFFF, true, false, 0x0000});
  CHECK(p != crc_parameters{16, 0x8005, 0xFFFF, true, true, 0x0001});
}

TEST_CASE("table_entries: the table a size names, 256 where slices do not apply") {
  // The sizes are the numbers MOTIONBUS_CRC_DEFAULT_TABLE takes (core/config.hpp), each the
  // entries of the table it names (crc_table_size's comment).
  CHECK(crc16_modbus<crc_table_size::bitwise>::table_entries() == 0U);
  CHECK(crc16_modbus<crc_table_size::nibble>::table_entries() == 16U);
  CHECK(crc16_modbus<crc_table_size::byte>::table_entries() == 256U);
  CHECK(crc16_modbus<crc_table_size::slice4>::table_entries() == 1024U);
  CHECK(crc16_modbus<crc_table_size::slice8>::table_entries() == 2048U);
  // CRC-8/MAXIM-DOW: reflected at width 8, so it slices (check value from the CRC catalogue)
  using maxim = crc_spec<8, 0x31, 0x00, true, true, 0x00>;
  CHECK(crc<maxim, crc_table_size::slice4>::table_entries() == 1024U);
  CHECK(crc<maxim, crc_table_size::slice4>::compute(check_input) == 0xA1);
  CHECK(crc6_biss<crc_table_size::slice8>::table_entries() == 2048U);  // MSB first, width <= 8
  // CRC-16/XMODEM: MSB first and wider than 8 bits, so the slices fall back to the byte table
  using xmodem = crc_spec<16, 0x1021, 0x0000, false, false, 0x0000>;
  CHECK(crc<xmodem, crc_table_size::slice4>::table_entries() == 256U);
  CHECK(crc<xmodem, crc_table_size::slice8>::table_entries() == 256U);
  CHECK(crc<xmodem, crc_table_size::slice8>::compute(check_input) == 0x31C3);
}
