// Tsubaki SM unit profile: register map, units, limits, password rules, request builders and
// response decoders. Expected frames are written from the vendor text (§6–§11) with CRCs from an
// independent bitwise CRC-16/MODBUS.
#include "motionbus/devices/sm_unit.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>
#include "../support/bytes.hpp"

using namespace motionbus;
namespace sm = motionbus::devices::sm_unit;
namespace mo = motionbus::modbus;

using namespace testutil;

TEST_CASE("SM unit: request frames for the documented operations") {
  std::uint8_t out[256] = {};
  // FC04 100..108 from slave 1: 01 04 00 64 00 09 + CRC
  CHECK(output(sm::read_instantaneous(1, out), out) ==
        bytes{0x01, 0x04, 0x00, 0x64, 0x00, 0x09, 0x71, 0xD3});
  CHECK(output(sm::read_login_status(1, out), out) ==
        bytes{0x01, 0x04, 0x01, 0x2C, 0x00, 0x01, 0xF1, 0xFF});
  CHECK(output(sm::read_version(1, out), out) == bytes{0x01, 0x11, 0xC0, 0x2C});
  CHECK(output(sm::set_coil(1, sm::coil::warning_reset, out), out) ==
        bytes{0x01, 0x05, 0x00, 0x64, 0xFF, 0x00, 0xCD, 0xE5});
  // login with the default password "password": 8 registers, padded with NUL
  const auto n = sm::login(1, text("password"), out);
  REQUIRE(n.ok());
  const bytes frame = output(n, out);
  CHECK(frame.size() == 1 + 6 + 16 + 2);
  CHECK(bytes(frame.begin(), frame.begin() + 15) ==
        bytes{0x01, 0x10, 0x00, 0x64, 0x00, 0x08, 0x10, 'p', 'a', 's', 's', 'w', 'o', 'r', 'd'});
  CHECK(frame[15] == 0x00);
  // log 2, temperature, 20 samples from 2300
  const auto log = sm::read_log(1, 2, sm::channel::temperature, out);
  REQUIRE(log.ok());
  CHECK(out[2] == 0x08);  // 2300 = 0x08FC
  CHECK(out[3] == 0xFC);
  CHECK(out[5] == 20);
  CHECK(sm::read_log(1, 4, sm::channel::voltage, out).error() == errc::out_of_range);
  CHECK(sm::log_address(3, sm::channel::torque, 19).value() == 3819);
  // slave addresses: 1..16, broadcast only for writes
  CHECK(sm::read_instantaneous(0, out).error() == errc::modbus_slave_address);
  CHECK(sm::read_instantaneous(17, out).error() == errc::modbus_slave_address);
  CHECK(sm::write_setting(0, 36, 900, out).ok());
}

TEST_CASE("SM unit: settings are range-checked before anything is sent") {
  std::uint8_t out[256] = {};
  CHECK(sm::write_setting(1, 0, 200, out).ok());
  CHECK(sm::write_setting(1, 0, 201, out).error() == errc::out_of_range);
  CHECK(sm::write_setting(1, 4, 0, out).error() == errc::out_of_range);  // start time >= 1
  CHECK(sm::write_setting(1, 5, 0, out).ok());                           // shock time 0 = off
  CHECK(sm::write_setting(1, 37, 15000, out).ok());
  CHECK(sm::write_setting(1, 37, 15001, out).error() == errc::out_of_range);
  CHECK(sm::write_setting(1, 38, 0, out).error() == errc::out_of_range);
  CHECK(sm::write_setting(1, 40, 0, out).error() == errc::out_of_range);
  const std::uint16_t ok[] = {100, 100, 50, 50, 10};
  CHECK(sm::write_settings(1, 9, ok, out).ok());
  const std::uint16_t bad[] = {100, 100, 50, 50, 0};  // index 13 is a start time
  CHECK(sm::write_settings(1, 9, bad, out).error() == errc::out_of_range);
  // the address is checked before the values (mutation testing: docs/testing.md)
  CHECK(sm::write_settings(248, 9, bad, out).error() == errc::modbus_slave_address);
  for (std::uint16_t i = 0; i < 40; ++i) {
    const auto l = sm::setting_limits(i);
    REQUIRE(l.ok());
    CHECK(l->lower <= l->upper);
  }
}

TEST_CASE("SM unit: password rules") {
  CHECK(sm::check_password(text("password")) == errc::ok);
  CHECK(sm::check_password(text("1234567")) == errc::out_of_range);
  CHECK(sm::check_password(text("12345678901234567")) == errc::out_of_range);
  CHECK(sm::check_password(text("pass word")) == errc::invalid_argument);
  CHECK(sm::check_password(text("!~!~!~!~!~!~!~!~")) == errc::ok);
  std::uint8_t out[256] = {};
  CHECK(sm::change_password(1, text("short"), out).error() == errc::out_of_range);
  std::uint16_t regs[8] = {};
  sm::password_registers(text("abcdefghi"), regs);
  CHECK(regs[0] == 0x6162);
  CHECK(regs[4] == 0x6900);
  CHECK(regs[7] == 0x0000);
}

TEST_CASE("SM unit: instantaneous data with units and signedness, version, login error") {
  // 230.5 V, 1.23 A, 283.5 W, -5.0 degC, -0.25 m/s2, 0.10, 9.81, 50 Hz, 12.3 N.m
  const bytes pdu = {0x04, 0x12, 0x09, 0x01, 0x00, 0x7B, 0x0B, 0x13, 0xFF, 0xCE,
                     0xFF, 0xE7, 0x00, 0x0A, 0x03, 0xD5, 0x00, 0x32, 0x00, 0x7B};
  std::uint8_t req[256] = {};
  const std::size_t n = sm::read_instantaneous(1, req).value();
  const auto r =
      mo::decode_response_for(byte_view(req + 1, n - 3), byte_view(pdu.data(), pdu.size()));
  REQUIRE(r.is_complete());
  const auto v = sm::decode_instantaneous(r.value());
  REQUIRE(v.ok());
  CHECK(v.value()[sm::channel::voltage] == 2305);
  CHECK(v.value()[sm::channel::current] == 123);
  CHECK(v.value()[sm::channel::power] == 2835);
  CHECK(v.value()[sm::channel::temperature] == -50);
  CHECK(v.value()[sm::channel::acceleration_x] == -25);
  CHECK(v.value()[sm::channel::acceleration_z] == 981);
  CHECK(v.value()[sm::channel::frequency] == 50);
  CHECK(v.value()[sm::channel::torque] == 123);
  CHECK(sm::unit_of(sm::channel::current).denominator == 100);
  CHECK(!sm::unit_of(sm::channel::voltage).is_signed);
  CHECK(sm::unit_of(sm::channel::acceleration_y).is_signed);
  CHECK(sm::raw_value(sm::channel::voltage, 0xFFFF) == 65535);  // unsigned channel

  const bytes version_pdu = {0x11, 0x01, 0x00};
  const bytes fc11 = {0x11};
  const auto vr =
      mo::decode_response_for(byte_view(fc11.data(), 1), byte_view(version_pdu.data(), 3),
                              mo::report_id_format::two_bytes_no_count);
  REQUIRE(vr.is_complete());
  CHECK(sm::decode_version(vr.value()).value().upper == 1);
  CHECK(sm::decode_version(vr.value()).value().lower == 0);

  const bytes login_error = {0x90, 0x04};
  std::uint16_t regs[8] = {};
  std::uint8_t wreq[64] = {};
  const std::size_t wn = mo::encode_write_multiple_registers(200, regs, wreq).value();
  const auto le = mo::decode_response_for(byte_view(wreq, wn), byte_view(login_error.data(), 2));
  REQUIRE(le.is_complete());
  CHECK(sm::is_login_error(le.value()));
  CHECK(sm::decode_instantaneous(le.value()).error() == errc::modbus_mismatch);

  CHECK(std::strcmp(sm::warning_name(sm::warning::overheat), "overheat") == 0);
  CHECK(sm::warning_name(0x0010) == nullptr);
}

TEST_CASE("SM unit builders: slave 248 and above is refused by every builder") {
  std::uint8_t out[256] = {};
  const mutable_byte_view o(out, sizeof out);
  const std::uint16_t values[2] = {100, 100};
  CHECK(sm::write_setting(248, 36, 700, o).error() == errc::modbus_slave_address);
  CHECK(sm::write_settings(248, 36, span<const std::uint16_t>(values, 2), o).error() ==
        errc::modbus_slave_address);
  CHECK(sm::read_holding_block(0, sm::holding::settings, 1, o).error() ==
        errc::modbus_slave_address);  // no broadcast of a read
  CHECK(sm::set_coil(248, sm::coil::warning_reset, o).error() == errc::modbus_slave_address);
  CHECK(sm::read_version(0, o).error() == errc::modbus_slave_address);
  // a PDU the codec refuses is refused through the wrapper: 124 settings exceed FC10's 123
  const std::vector<std::uint16_t> many(124, 0);
  CHECK(sm::write_settings(1, 0, span<const std::uint16_t>(many.data(), many.size()), o).error() !=
        errc::ok);
  // a quantity the PDU encoder refuses (0 registers) comes back through the wrapper
  CHECK(sm::read_inputs(1, 0, 0, o).error() == errc::modbus_quantity);
}

TEST_CASE("SM unit decoders: warning names, and responses of the wrong shape") {
  CHECK(std::strcmp(sm::warning_name(sm::warning::torque_upper_a), "torque_upper_limit_a") == 0);
  CHECK(std::strcmp(sm::warning_name(sm::warning::torque_upper_b), "torque_upper_limit_b") == 0);
  CHECK(std::strcmp(sm::warning_name(sm::warning::torque_lower_a), "torque_lower_limit_a") == 0);
  CHECK(std::strcmp(sm::warning_name(sm::warning::torque_lower_b), "torque_lower_limit_b") == 0);
  CHECK(std::strcmp(sm::warning_name(sm::warning::excessive_shock), "excessive_shock") == 0);
  CHECK(sm::warning_name(0x0100) == nullptr);
  mo::response r;
  r.function = 0x04;
  const bytes eight(8, 0);
  r.data = byte_view(eight.data(), eight.size());
  CHECK(sm::decode_instantaneous(r).error() == errc::modbus_byte_count);  // 4 registers, not 9
  r.function = 0x11;
  CHECK(sm::decode_version(r).error() == errc::modbus_byte_count);
  r.exception = true;
  CHECK(sm::decode_version(r).error() == errc::modbus_mismatch);
}

TEST_CASE("unit table: a channel outside the enumeration has a neutral entry") {
  volatile int undefined = 99;  // run time, not a constant initialiser
  const sm::unit_info u = sm::unit_of(static_cast<sm::channel>(undefined));
  CHECK(std::strcmp(u.unit, "") == 0);
  CHECK(u.numerator == 1);
  CHECK(u.denominator == 1);
}

TEST_CASE("SM unit: each bound of the request helpers alone") {
  // log 1..3 and sample 0..19, each out of range alone
  CHECK(sm::log_address(1, sm::channel::voltage, 0).ok());
  CHECK(sm::log_address(0, sm::channel::voltage, 0).error() == errc::out_of_range);
  CHECK(sm::log_address(4, sm::channel::voltage, 0).error() == errc::out_of_range);
  CHECK(sm::log_address(1, sm::channel::voltage, 20).error() == errc::out_of_range);
  // a password character above 0x7E, one below 0x21
  CHECK(sm::check_password(text("abcdefg\x7f")) == errc::invalid_argument);
  CHECK(sm::check_password(text("abcdefg\x20")) == errc::invalid_argument);
  // password_registers fills no more registers than `out` holds
  std::uint16_t regs[4] = {1, 2, 3, 4};
  sm::password_registers(text("abcdefghijklmnop"), span<std::uint16_t>(regs, 3));
  CHECK(regs[0] == 0x6162);
  CHECK(regs[2] == 0x6566);
  CHECK(regs[3] == 4);
  // write_settings: an index past the settings, a value below its lower limit
  std::uint8_t out[256] = {};
  const std::uint16_t one[] = {100};
  CHECK(sm::write_settings(1, 40, one, out).error() == errc::out_of_range);
  const std::uint16_t zero_start[] = {0};
  CHECK(sm::write_settings(1, 4, zero_start, out).error() == errc::out_of_range);
  // ...and a value above its upper limit (a torque limit: 0..200 %), 200 itself taken
  const std::uint16_t torque_over[] = {200, 201};
  CHECK(sm::write_settings(1, 0, torque_over, out).error() == errc::out_of_range);
  CHECK(sm::write_settings(1, 0, span<const std::uint16_t>(torque_over, 1), out).ok());
}

TEST_CASE("SM unit: responses of another function or another exception are no match") {
  mo::response r;
  r.function = 0x03;  // not FC04, not FC11, no exception
  CHECK(sm::decode_instantaneous(r).error() == errc::modbus_mismatch);
  CHECK(sm::decode_version(r).error() == errc::modbus_mismatch);
  CHECK_FALSE(sm::is_login_error(r));
  r.function = 0x04;
  r.exception = true;
  r.exception_code = 0x02;  // an exception, but not the login error (04)
  CHECK_FALSE(sm::is_login_error(r));
  CHECK(sm::decode_instantaneous(r).error() == errc::modbus_mismatch);
  r.exception_code = 0x04;
  CHECK(sm::is_login_error(r));
}

TEST_CASE("SM unit: password_registers pads with NUL, whatever follows the password in memory") {
  // "password12" (10 characters) the start of a longer buffer: the registers past it are 0
  const std::uint8_t memory[] = {'p', 'a', 's', 's', 'w', 'o', 'r', 'd', '1', '2', 'X', 'Y'};
  std::uint16_t regs[8] = {};
  sm::password_registers(byte_view(memory, 10), regs);
  CHECK(regs[0] == 0x7061);  // "pa"
  CHECK(regs[4] == 0x3132);  // "12"
  for (std::size_t r = 5; r < 8; ++r) {
    CAPTURE(r);
    CHECK(regs[r] == 0);
  }
}

TEST_CASE("SM unit: the line (§2–§4), the address list (§7, §9, §10) and the warning bits (§9)") {
  // the values of the guideline's tables: a firmware that names a register or a bit by the
  // profile's constant reaches what the guideline lists
  CHECK(sm::baud == 9600U);   // §2: 9600 bps, 8 bits, EVEN, 1 stop bit
  CHECK(sm::min_slave == 1);  // §2: slave addresses 1-16
  CHECK(sm::max_slave == 16);
  CHECK(sm::min_silent_interval_us == 5000U);     // §4 note *1: 5 ms or longer
  CHECK(sm::min_command_interval_us == 100000U);  // §3: at least 0.1 second between commands
  CHECK(sm::coil::warning_count_clear == 0);      // §8
  CHECK(sm::coil::warning_reset == 100);
  CHECK(sm::input::set_parameters == 0);  // §7, §9: 0-8
  CHECK(sm::input::set_parameter_count == 9);
  CHECK(sm::input::instantaneous == 100);  // 100-108
  CHECK(sm::input::instantaneous_count == 9);
  CHECK(sm::input::state == 200);  // 200-207
  CHECK(sm::input::state_count == 8);
  CHECK(sm::input::login_status == 300);
  CHECK(sm::input::logged_in == 0xFF00);  // §9: login 0xFF00, logout 0x0000
  CHECK(sm::input::logged_out == 0x0000);
  CHECK(sm::input::log_samples == 20);  // xx00-xx19
  CHECK(sm::holding::settings == 0);    // §7, §10: 0-39
  CHECK(sm::holding::setting_count == 40);
  CHECK(sm::holding::login == 100);     // 100-107
  CHECK(sm::holding::password == 200);  // 200-207
  CHECK(sm::holding::password_registers == 8);
  CHECK(sm::holding::product_code == 300);  // 300-301
  CHECK(sm::holding::product_code_registers == 2);
  CHECK(sm::holding::mfg_number == 350);  // 350-354
  CHECK(sm::holding::mfg_number_registers == 5);
  // §9 note *1: bit 0 torque upper limit A, 1 upper B, 2 lower A, 3 lower B, 5 overheat,
  // 6 excessive shock; bits 4 and 7..15 are not used
  CHECK(sm::warning::torque_upper_a == 0x0001);
  CHECK(sm::warning::torque_upper_b == 0x0002);
  CHECK(sm::warning::torque_lower_a == 0x0004);
  CHECK(sm::warning::torque_lower_b == 0x0008);
  CHECK(sm::warning::overheat == 0x0020);
  CHECK(sm::warning::excessive_shock == 0x0040);
  CHECK(sm::warning::defined == 0x006F);
  // the read of the state parameters asks for exactly 200..207
  std::uint8_t out[256] = {};
  REQUIRE(sm::read_state(1, out).ok());
  CHECK(out[2] == 0x00);
  CHECK(out[3] == 0xC8);
  CHECK(out[4] == 0x00);
  CHECK(out[5] == 0x08);
}

TEST_CASE("SM unit: the signed channels at the limits of two's complement (§9)") {
  CHECK(sm::raw_value(sm::channel::temperature, 0x8000) == -32768);
  CHECK(sm::raw_value(sm::channel::temperature, 0x7FFF) == 32767);
  CHECK(sm::raw_value(sm::channel::acceleration_x, 0x8000) == -32768);
  CHECK(sm::raw_value(sm::channel::acceleration_z, 0xFFFF) == -1);
  CHECK(sm::raw_value(sm::channel::torque, 0x8000) == 32768);  // unsigned
}

TEST_CASE("SM unit builders: slaves 1..16 only (§2), whatever the builder") {
  std::uint8_t out[256] = {};
  const mutable_byte_view o(out, sizeof out);
  const std::uint16_t values[2] = {100, 100};
  const span<const std::uint16_t> two(values, 2);
  // 16, the last address, is taken by each
  CHECK(sm::read_instantaneous(16, o).ok());
  CHECK(sm::write_setting(16, 36, 700, o).ok());
  CHECK(sm::write_settings(16, 36, two, o).ok());
  CHECK(sm::login(16, text("password"), o).ok());
  CHECK(sm::change_password(16, text("password"), o).ok());
  CHECK(sm::read_holding_block(16, sm::holding::product_code, 2, o).ok());
  CHECK(sm::set_coil(16, sm::coil::warning_reset, o).ok());
  CHECK(sm::read_version(16, o).ok());
  // 17, an address the Modbus frame could carry but no SM unit has, is refused by each
  CHECK(sm::read_instantaneous(17, o).error() == errc::modbus_slave_address);
  CHECK(sm::write_setting(17, 36, 700, o).error() == errc::modbus_slave_address);
  CHECK(sm::write_settings(17, 36, two, o).error() == errc::modbus_slave_address);
  CHECK(sm::login(17, text("password"), o).error() == errc::modbus_slave_address);
  CHECK(sm::change_password(17, text("password"), o).error() == errc::modbus_slave_address);
  CHECK(sm::read_holding_block(17, sm::holding::product_code, 2, o).error() ==
        errc::modbus_slave_address);
  CHECK(sm::set_coil(17, sm::coil::warning_reset, o).error() == errc::modbus_slave_address);
  CHECK(sm::read_version(17, o).error() == errc::modbus_slave_address);
  // broadcast (0) for the writes only (§6 note *2)
  CHECK(sm::write_settings(0, 36, two, o).ok());
  CHECK(sm::login(0, text("password"), o).ok());
  CHECK(sm::set_coil(0, sm::coil::warning_reset, o).ok());
  CHECK(sm::read_holding_block(0, sm::holding::product_code, 2, o).error() ==
        errc::modbus_slave_address);
}

TEST_CASE("SM unit: settings at their lower limits, and the first password character checked") {
  std::uint8_t out[256] = {};
  // §10: torque limits 0..200, start time 1..300: each lower limit itself is taken
  const std::uint16_t lowest[] = {0, 0, 0, 0, 1, 0, 0, 0, 0};
  CHECK(sm::write_settings(1, 0, lowest, out).ok());
  const std::uint16_t log_interval[] = {1};  // setting 38: 1..100
  CHECK(sm::write_settings(1, 38, log_interval, out).ok());
  // §10: every character 0x21..0x7E, the first as the others
  CHECK(sm::check_password(text(" bcdefgh")) == errc::invalid_argument);
  CHECK(sm::check_password(text("\x7f"
                                "bcdefgh")) == errc::invalid_argument);
  CHECK(sm::login(1, text(" bcdefgh"), out).error() == errc::invalid_argument);
}

TEST_CASE("SM unit: password_registers writes 8 registers at most, reads no character past") {
  // `out` longer than 8 registers: the 9th is left as it was
  std::uint16_t regs[9] = {};
  regs[8] = 0xABCD;
  sm::password_registers(text("abcdefghijklmnop"), regs);
  CHECK(regs[7] == 0x6F70);  // "op"
  CHECK(regs[8] == 0xABCD);
  // an odd length (9 characters) in a longer buffer: the last register is "i" and a NUL
  const std::uint8_t memory[] = {'a', 'b', 'c', 'd', 'e', 'f', 'g', 'h', 'i', 'X', 'Y'};
  std::uint16_t odd[8] = {};
  sm::password_registers(byte_view(memory, 9), odd);
  CHECK(odd[3] == 0x6768);  // "gh"
  CHECK(odd[4] == 0x6900);  // "i", NUL
  CHECK(odd[5] == 0);
}

TEST_CASE("SM unit: a version record, default-constructed or of a failed decode, is 0.0") {
  const sm::version v;
  CHECK(v.upper == 0);
  CHECK(v.lower == 0);
  mo::response r;
  r.function = 0x03;  // not FC11
  const auto failed = sm::decode_version(r);
  REQUIRE(!failed.ok());
  CHECK(failed.value().upper == 0);
  CHECK(failed.value().lower == 0);
}
