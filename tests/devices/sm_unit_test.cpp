// Tsubaki SM unit profile: register map, units, limits, password rules, request builders and
// response decoders. Expected frames are written from the vendor text (§6–§11) with CRCs from an
// independent bitwise CRC-16/MODBUS.
#include "motionbus/devices/sm_unit.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>

using namespace motionbus;
namespace sm = motionbus::devices::sm_unit;
namespace mo = motionbus::modbus;

namespace {

using bytes = std::vector<std::uint8_t>;

bytes built(const result<std::size_t>& n, const std::uint8_t* out) {
  REQUIRE(n.ok());
  return bytes(out, out + n.value());
}

byte_view text(const char* s) {
  return byte_view(reinterpret_cast<const std::uint8_t*>(s), std::strlen(s));
}

}  // namespace

TEST_CASE("SM unit: request frames for the documented operations") {
  std::uint8_t out[256] = {};
  // FC04 100..108 from slave 1: 01 04 00 64 00 09 + CRC
  CHECK(built(sm::read_instantaneous(1, out), out) ==
        bytes{0x01, 0x04, 0x00, 0x64, 0x00, 0x09, 0x71, 0xD3});
  CHECK(built(sm::read_login_status(1, out), out) ==
        bytes{0x01, 0x04, 0x01, 0x2C, 0x00, 0x01, 0xF1, 0xFF});
  CHECK(built(sm::read_version(1, out), out) == bytes{0x01, 0x11, 0xC0, 0x2C});
  CHECK(built(sm::set_coil(1, sm::coil::warning_reset, out), out) ==
        bytes{0x01, 0x05, 0x00, 0x64, 0xFF, 0x00, 0xCD, 0xE5});
  // login with the default password "password": 8 registers, padded with NUL
  const auto n = sm::login(1, text("password"), out);
  REQUIRE(n.ok());
  const bytes frame = built(n, out);
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
  const auto r = mo::decode_response(byte_view(pdu.data(), pdu.size()), byte_view(req + 1, n - 3));
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
  const auto vr = mo::decode_response(byte_view(version_pdu.data(), 3), byte_view(fc11.data(), 1),
                                      mo::report_id_format::two_bytes_no_count);
  REQUIRE(vr.is_complete());
  CHECK(sm::decode_version(vr.value()).value().upper == 1);
  CHECK(sm::decode_version(vr.value()).value().lower == 0);

  const bytes login_error = {0x90, 0x04};
  std::uint16_t regs[8] = {};
  std::uint8_t wreq[64] = {};
  const std::size_t wn = mo::encode_write_multiple_registers(200, regs, wreq).value();
  const auto le = mo::decode_response(byte_view(login_error.data(), 2), byte_view(wreq, wn));
  REQUIRE(le.is_complete());
  CHECK(sm::is_login_error(le.value()));
  CHECK(sm::decode_instantaneous(le.value()).error() == errc::modbus_mismatch);

  CHECK(std::strcmp(sm::warning_name(sm::warning::overheat), "overheat") == 0);
  CHECK(sm::warning_name(0x0010) == nullptr);
}
