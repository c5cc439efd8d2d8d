// AMO ABSYS profile: EDS bytes from the vendor tables (§2.8, §2.9), position-with-offset
// arithmetic (§2.3), the error status, serial number and device ID decoders (§2.4, §2.5).
// The emulator's own suite is absys_emulator_test.cpp.
#include "motionbus/devices/absys.hpp"

#include <doctest/doctest.h>

#include <climits>
#include <cstdint>

#include "motionbus/biss.hpp"

using namespace motionbus;
namespace bs = motionbus::biss;
namespace ab = motionbus::devices::absys;

TEST_CASE("EDS banks: the bytes of the vendor tables, parsed back") {
  std::uint8_t common[64] = {};
  REQUIRE(bs::encode_eds_common(bs::eds_common{}, mutable_byte_view(common, 64)) == errc::ok);
  // §2.8 defaults
  CHECK(common[0x00] == 0x01);
  CHECK(common[0x01] == 0x02);
  CHECK(common[0x02] == 0x84);
  CHECK(common[0x03] == 0x84);
  CHECK(common[0x10] == 0x01);
  CHECK(common[0x11] == 0x01);
  CHECK(common[0x12] == 0x80);
  CHECK(common[0x14] == 0x81);
  CHECK(common[0x15] == 0x20);
  CHECK(common[0x17] == 0x21);
  const auto c = bs::decode_eds_common(byte_view(common, 64), {true});
  REQUIRE(c.is_complete());
  CHECK(*c == bs::eds_common{});
  CHECK(bs::crc_from_eds(c->crc_poly) == bs::crc6_43);

  std::uint8_t bp3[64] = {};
  const auto def = ab::default_bp3(bs::encoder_type::rotary, 512, 10);
  REQUIRE(bs::encode_bp3(def, mutable_byte_view(bp3, 64)) == errc::ok);
  // §2.9 defaults, multi-byte values big-endian
  const std::uint8_t head[] = {0x02, 0x01, 0x63, 0x20, 0x01, 0x02, 0xFF, 0x00,
                               0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x20, 0x00};
  for (std::size_t i = 0; i < sizeof head; ++i) {
    CHECK(bp3[i] == head[i]);
  }
  CHECK(bp3[0x14] == 0x00);
  CHECK(bp3[0x16] == 0x02);  // 512 = 0x00000200
  CHECK(bp3[0x1B] == 10);
  CHECK(bp3[0x1F] == 0x21);  // CPOLY 0x00000021
  const auto p = bs::decode_bp3(byte_view(bp3, 64), {true});
  REQUIRE(p.is_complete());
  CHECK(*p == def);
  CHECK(p->pulses_per_revolution() == 512U * 1024U);
  CHECK(p->layout().frame_bits() == ab::layout.frame_bits());
  CHECK(p->layout().crc == bs::crc6_43);

  bs::bp3_profile lin = ab::default_bp3(bs::encoder_type::linear, 1000, 3);
  CHECK(lin.lsb_nm() == doctest::Approx(125.0));
}

TEST_CASE("EDS errors: truncated, inconsistent fields, checksum") {
  std::uint8_t bank[64] = {};
  CHECK(bs::decode_bp3(byte_view(bank, 63)).needed() == 1U);  // a short bank needs the rest
  CHECK(bs::decode_eds_common(byte_view(bank, 10)).needed() == 54U);
  CHECK(bs::decode_eds_common(byte_view(bank, 64)).error() == errc::biss_eds);  // all zero
  REQUIRE(bs::encode_bp3(bs::bp3_profile{}, mutable_byte_view(bank, 64)) == errc::ok);
  CHECK(bs::decode_bp3(byte_view(bank, 64)).is_complete());
  const auto broken = [&](std::size_t at, std::uint8_t v) {
    std::uint8_t b[64];
    for (std::size_t i = 0; i < 64; ++i) {
      b[i] = bank[i];
    }
    b[at] = v;
    return bs::decode_bp3(byte_view(b, 64)).error();
  };
  CHECK(broken(0x00, 0x07) == errc::biss_eds);  // version
  CHECK(broken(0x08, 0x02) == errc::biss_eds);  // encoder type
  CHECK(broken(0x1B, 21) == errc::biss_eds);    // SIP_RES
  CHECK(broken(0x0E, 0x00) == errc::biss_eds);  // no data bits
  CHECK(broken(0x0E, 65) == errc::biss_eds);    // too many
  CHECK(broken(0x1F, 0x00) == errc::biss_eds);  // no CRC polynomial
  CHECK(broken(0x23, 0x40) == errc::biss_eds);  // start value wider than CRC6
  CHECK(broken(0x30, 0x01) == errc::ok);        // undefined byte: fine without verification
  std::uint8_t b[64];
  for (std::size_t i = 0; i < 64; ++i) {
    b[i] = bank[i];
  }
  b[0x30] = 1;
  CHECK(bs::decode_bp3(byte_view(b, 64), {true}).error() == errc::biss_eds);
  std::uint8_t small[10] = {};
  CHECK(bs::encode_bp3(bs::bp3_profile{}, mutable_byte_view(small, 10)) == errc::buffer_too_small);
}

TEST_CASE("position with offset: linear signed, rotary modulo pulses per revolution") {
  CHECK(ab::linear_position(1000, 100) == 900);
  CHECK(ab::linear_position(100, 1000) == -900);
  CHECK(ab::linear_position(0x80000000U, 0) == INT_MIN);
  CHECK(ab::linear_position(0, 1) == -1);
  CHECK(ab::rotary_position(1000, 100, 524288) == 900);
  CHECK(ab::rotary_position(100, 1000, 524288) == 524288 - 900);
  CHECK(ab::rotary_position(524289, 0, 524288) == 1);
  CHECK(ab::rotary_position(5, 0xFFFFFFFFU, 0) == 6U);
}

TEST_CASE("ABSYS error status decoder: active low, undefined bits kept apart") {
  CHECK(ab::status_healthy == 0x03);
  const auto healthy = ab::decode_error_status(0x03);
  CHECK(!healthy.error);
  CHECK(!healthy.warning);
  CHECK(healthy.undefined == 0);
  const auto err = ab::decode_error_status(0x01);
  CHECK(err.error);
  CHECK(!err.warning);
  const auto warn = ab::decode_error_status(0x02);
  CHECK(!warn.error);
  CHECK(warn.warning);
  const auto both = ab::decode_error_status(0x00);
  CHECK(both.error);
  CHECK(both.warning);
  const auto odd = ab::decode_error_status(0xA7);
  CHECK(!odd.error);
  CHECK(!odd.warning);
  CHECK(odd.undefined == 0xA4);
  CHECK(ab::status_of(true, true) == ab::status_healthy);
  CHECK(ab::status_of(false, true) == 0x01);
  CHECK(ab::status_of(true, false) == 0x02);
}

TEST_CASE("ABSYS serial number and device ID decoders (§2.4, §2.5)") {
  // the text's example: 0x00BC614E between ASCII bytes
  const std::uint8_t regs[] = {'A', 'T', 'J', 0x00, 0xBC, 0x61, 0x4E, 'C'};
  const auto sn = ab::decode_serial_number(regs);
  REQUIRE(sn.is_complete());
  CHECK(sn->prefix[0] == 'A');
  CHECK(sn->prefix[1] == 'T');
  CHECK(sn->prefix[2] == 'J');
  CHECK(sn->number == 0x00BC614EU);
  CHECK(sn->number == 12345678U);
  CHECK(sn->suffix == 'C');
  const std::uint8_t msb[] = {'x', 'y', 'z', 0xFE, 0x01, 0x02, 0x03, '9', 0xFF};  // 9th ignored
  const auto m = ab::decode_serial_number(msb);
  REQUIRE(m.is_complete());
  CHECK(m->number == 0xFE010203U);
  CHECK(m->suffix == '9');
  CHECK(ab::decode_serial_number(byte_view(regs, 7)).needed() == 1U);
  CHECK(ab::decode_serial_number(byte_view{}).needed() == 8U);
  const std::size_t ascii_at[] = {0, 1, 2, 7};
  for (const std::size_t at : ascii_at) {  // the ASCII positions refuse bytes above 0x7F
    std::uint8_t bad[8] = {'A', 'T', 'J', 0x00, 0xBC, 0x61, 0x4E, 'C'};
    bad[at] = 0x80;
    CAPTURE(at);
    CHECK(ab::decode_serial_number(bad).error() == errc::out_of_range);
  }
  std::uint8_t del[8] = {0x7F, 'T', 'J', 0x00, 0xBC, 0x61, 0x4E, 0x7F};  // 0x7F is ASCII (DEL)
  const auto with_del = ab::decode_serial_number(del);
  REQUIRE(with_del.is_complete());
  CHECK(with_del->prefix[0] == '\x7F');
  CHECK(with_del->suffix == '\x7F');
  const std::uint8_t dev[] = {'X', 'X', 0x00, 0x11, 0xF5, 0x8E, '0', '1'};
  const auto d = ab::decode_device_id(dev);
  REQUIRE(d.is_complete());
  CHECK(d->prefix[0] == 'X');
  CHECK(d->number == 0x0011F58EU);
  CHECK(d->suffix[0] == '0');
  CHECK(d->suffix[1] == '1');
  CHECK(ab::decode_device_id(byte_view(dev, 7)).needed() == 1U);
  std::uint8_t bad_dev[8] = {'X', 'X', 0x00, 0x11, 0xF5, 0x8E, '0', 0xC1};
  CHECK(ab::decode_device_id(bad_dev).error() == errc::out_of_range);
  bad_dev[7] = '1';
  bad_dev[1] = 0x80;
  CHECK(ab::decode_device_id(bad_dev).error() == errc::out_of_range);
}

TEST_CASE("the register map (§2.1), the banks (§2.2) and the command and preset values (§2.3)") {
  // the addresses and values of the vendor's tables: a firmware that names a register by the
  // profile's constant reaches the register the manual lists
  CHECK(ab::reg::bank_window == 0x00);
  CHECK(ab::reg::bank_select == 0x40);
  CHECK(ab::reg::eds_bank == 0x41);
  CHECK(ab::reg::profile_id == 0x42);
  CHECK(ab::reg::serial_number == 0x44);
  CHECK(ab::reg::offset == 0x4C);
  CHECK(ab::reg::command == 0x60);
  CHECK(ab::reg::position == 0x63);
  CHECK(ab::reg::preset_mode == 0x6A);
  CHECK(ab::reg::error_status == 0x6B);
  CHECK(ab::reg::functional_reserve == 0x6F);
  CHECK(ab::reg::functional_reserve_indicator == 0x70);
  CHECK(ab::reg::device_id == 0x75);
  CHECK(ab::reg::revision == 0x7D);
  CHECK(ab::reg::manufacturer_id == 0x7E);
  CHECK(ab::bank::eds_common == 0x80);
  CHECK(ab::bank::eds_bp3 == 0x81);
  CHECK(ab::bank::eds_reserved_3 == 0x82);
  CHECK(ab::bank::eds_reserved_4 == 0x83);
  CHECK(ab::bank::user == 0x84);
  CHECK(ab::bank::not_allowed == 0xFF);
  CHECK(static_cast<int>(ab::command::set_offset_to_position) == 0x02);
  CHECK(static_cast<int>(ab::command::reset_offset) == 0x03);
  CHECK(static_cast<int>(ab::command::reset_errors) == 0x06);
  CHECK(static_cast<int>(ab::preset_mode::with_offset) == 0x00);
  CHECK(static_cast<int>(ab::preset_mode::actual) == 0x01);
}

TEST_CASE("ABSYS records default-constructed hold no error and no figure") {
  const ab::error_status s;
  CHECK(!s.error);
  CHECK(!s.warning);
  CHECK(s.undefined == 0);
  const ab::serial_number sn;
  CHECK(sn.prefix[0] == 0);
  CHECK(sn.number == 0U);
  CHECK(sn.suffix == 0);
  const ab::device_id id;
  CHECK(id.prefix[0] == 0);
  CHECK(id.number == 0U);
  CHECK(id.suffix[1] == 0);
}

TEST_CASE("ABSYS device ID: any 32-bit ID between the ASCII pairs, a ninth byte ignored (§2.5)") {
  // §2.5: two ASCII bytes, the ID on four bytes (most significant first, any value: here one
  // with bit 31 set), two ASCII bytes; decode_device_id reads 8 bytes and ignores more
  const std::uint8_t dev[] = {'Q', 'R', 0x80, 0x11, 0xF5, 0x8E, '0', '1', 0xFF};
  const auto d = ab::decode_device_id(dev);
  REQUIRE(d.is_complete());
  CHECK(d.consumed() == 8U);
  CHECK(d->prefix[0] == 'Q');
  CHECK(d->prefix[1] == 'R');
  CHECK(d->number == 0x8011F58EU);
  CHECK(d->suffix[0] == '0');
  CHECK(d->suffix[1] == '1');
}

TEST_CASE("ABSYS timings: §3.4's register access times and Table 1's power-on delay") {
  // §3.4: persistent registers ">4 ms" to write, "0x02 or 0x03 ... four EEPROM Write
  // operations (17 ms delay)", other registers ">0.05 ms" to read; §1, Table 1: "Power-on
  // Delay 1.8 sec"
  CHECK(ab::persistent_write_us == 4000U);
  CHECK(ab::offset_command_us == 17000U);
  CHECK(ab::eeprom_read_us == 50U);
  CHECK(ab::power_on_delay_ms == 1800U);
  CHECK(ab::write_time_us(ab::reg::offset, 0x12) == 4000U);
  CHECK(ab::write_time_us(ab::reg::command, 0x02) == 17000U);
}

TEST_CASE("linear position with offset: the largest positive difference, 0x7FFFFFFF (§2.3)") {
  // signed two's complement on 32 bits: 0x7FFFFFFF is INT32_MAX, 0x80000000 the first negative
  CHECK(ab::linear_position(0x7FFFFFFFU, 0) == INT_MAX);
  CHECK(ab::linear_position(0xFFFFFFFFU, 0x80000000U) == INT_MAX);
  CHECK(ab::linear_position(0x80000000U, 0) == INT_MIN);
}
