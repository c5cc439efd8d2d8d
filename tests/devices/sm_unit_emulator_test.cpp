// The SM unit emulator on the server dispatch: login state, password rules, block access,
// settings limits, error priority 01 > 02 > 03 > 04, broadcasts, time-varying data.
#include "motionbus/devices/sm_unit_emulator.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>
#include "../support/bytes.hpp"
#include "../support/modbus.hpp"

using namespace motionbus;
namespace sm = motionbus::devices::sm_unit;
namespace mo = motionbus::modbus;

using namespace testutil;

namespace {

struct bench {
  sm::emulator unit;
  std::uint8_t own = 1;

  // Sends an RTU request built by `build` (into a buffer) and returns the response PDU
  // (empty: no reply).
  template <class Build>
  bytes ask(Build build) {
    std::uint8_t req[256] = {};
    const auto n = build(mutable_byte_view(req, 256));
    REQUIRE(n.ok());
    return serve(byte_view(req, n.value()));
  }
  bytes serve(byte_view adu) {
    std::uint8_t out[256] = {};
    const auto r = mo::serve_rtu(unit, own, adu, out);
    REQUIRE(r.ok());
    if (r.value() == 0) {
      return {};
    }
    const auto f = mo::decode_rtu(byte_view(out, r.value()));
    REQUIRE(f.is_complete());
    return bytes(f->pdu.begin(), f->pdu.end());
  }
  bytes pdu(std::uint8_t slave, const bytes& p) {
    std::uint8_t adu[256] = {};
    const auto n = mo::encode_rtu(slave, byte_view(p.data(), p.size()), adu);
    REQUIRE(n.ok());
    return serve(byte_view(adu, n.value()));
  }
};

}  // namespace

TEST_CASE("SM unit emulator: login toggles, password rules, login errors") {
  bench b;
  CHECK(b.unit.logged_in());  // at power-on
  // read login status: 0xFF00
  CHECK(b.ask([](auto out) { return sm::read_login_status(1, out); }) ==
        bytes{0x04, 0x02, 0xFF, 0x00});
  // the password is readable while logged in
  auto r = b.ask([](auto out) { return sm::read_holding_block(1, sm::holding::password, 8, out); });
  REQUIRE(r.size() == 18);
  CHECK(std::memcmp(r.data() + 2, "password", 8) == 0);
  // log out with the right password
  CHECK(b.ask([](auto out) { return sm::login(1, text("password"), out); }) ==
        bytes{0x10, 0x00, 0x64, 0x00, 0x08});
  CHECK(!b.unit.logged_in());
  CHECK(b.ask([](auto out) { return sm::read_login_status(1, out); }) ==
        bytes{0x04, 0x02, 0x00, 0x00});
  // logged out: password unreadable, writes refused (04), reads of data still fine
  CHECK(b.ask([](auto out) { return sm::read_holding_block(1, sm::holding::password, 8, out); }) ==
        bytes{0x83, 0x04});
  CHECK(b.ask([](auto out) { return sm::write_setting(1, 36, 700, out); }) == bytes{0x86, 0x04});
  CHECK(b.ask([](auto out) { return sm::set_coil(1, sm::coil::warning_reset, out); }) ==
        bytes{0x85, 0x04});
  CHECK(b.ask([](auto out) { return sm::read_instantaneous(1, out); }).size() == 20);
  // product code and MFG number are readable whatever the state
  r = b.ask([](auto out) { return sm::read_holding_block(1, sm::holding::product_code, 2, out); });
  CHECK(r.size() == 6);
  CHECK(b.ask([](auto out) {
           return sm::read_holding_block(1, sm::holding::mfg_number, 5, out);
         }).size() == 12);
  // a wrong password: login error
  CHECK(b.ask([](auto out) { return sm::login(1, text("wrongpass"), out); }) == bytes{0x90, 0x04});
  CHECK(!b.unit.logged_in());
  // log in again, change the password, and the old one no longer works
  CHECK(b.ask([](auto out) { return sm::login(1, text("password"), out); }).size() == 5);
  CHECK(b.unit.logged_in());
  CHECK(b.ask([](auto out) { return sm::change_password(1, text("N3w-Pass!"), out); }) ==
        bytes{0x10, 0x00, 0xC8, 0x00, 0x08});
  CHECK(b.ask([](auto out) { return sm::login(1, text("password"), out); }) == bytes{0x90, 0x04});
  CHECK(b.ask([](auto out) { return sm::login(1, text("N3w-Pass!"), out); }).size() == 5);
  CHECK(!b.unit.logged_in());
  // a password of 7 characters (SP padded) is a data error even while logged out: 03 > 04
  CHECK(b.pdu(1, {0x10, 0x00, 0xC8, 0x00, 0x08, 0x10, 'a', 'b', 'c', 'd', 'e',
                  'f',  'g',  ' ',  ' ',  ' ',  ' ',  ' ', ' ', ' ', ' ', ' '}) ==
        bytes{0x90, 0x03});
}

TEST_CASE("SM unit emulator: blocks whole, settings limits, error priority") {
  bench b;
  // 01: unsupported function, whatever else is wrong
  CHECK(b.pdu(1, {0x16, 0x01, 0x2C, 0x00, 0x00, 0x00, 0x00}) == bytes{0x96, 0x01});
  CHECK(b.pdu(1, {0x07}) == bytes{0x87, 0x01});
  // 02 before 03: an unknown address with a bad quantity
  CHECK(b.pdu(1, {0x03, 0x01, 0xF4, 0x00, 0x00}) == bytes{0x83, 0x02});
  // 03 at a supported address: quantity 0, more than a PDU holds, a byte count that disagrees
  // (guideline §5: "the number of registers and bytes are invalid")
  CHECK(b.pdu(1, {0x03, 0x00, 0x00, 0x00, 0x00}) == bytes{0x83, 0x03});
  CHECK(b.pdu(1, {0x04, 0x00, 0x64, 0x00, 0x00}) == bytes{0x84, 0x03});
  CHECK(b.pdu(1, {0x10, 0x00, 0x24, 0x00, 0x00, 0x00}) == bytes{0x90, 0x03});
  CHECK(b.pdu(1, {0x03, 0x00, 0xC8, 0x00, 0x00}) == bytes{0x83, 0x03});  // a block's start
  CHECK(b.pdu(1, {0x04, 0x00, 0x64, 0x00, 0x7E}) == bytes{0x84, 0x03});  // 126 registers
  CHECK(b.pdu(1, {0x10, 0x00, 0x24, 0x00, 0x01, 0x04, 0x00, 0x01}) == bytes{0x90, 0x03});
  // blocks: one address alone, a partial block, a block from its middle
  CHECK(b.pdu(1, {0x03, 0x00, 0xC8, 0x00, 0x01}) == bytes{0x83, 0x02});
  CHECK(b.pdu(1, {0x03, 0x00, 0xC8, 0x00, 0x07}) == bytes{0x83, 0x02});
  CHECK(b.pdu(1, {0x03, 0x01, 0x2D, 0x00, 0x01}) == bytes{0x83, 0x02});
  CHECK(b.pdu(1, {0x06, 0x01, 0x2C, 0x00, 0x01}) == bytes{0x86, 0x02});  // read-only block
  CHECK(b.pdu(1, {0x02, 0x00, 0x00, 0x00, 0x01}) == bytes{0x82, 0x02});  // no inputs
  // 03: values
  CHECK(b.pdu(1, {0x06, 0x00, 0x00, 0x00, 0xC9}) == bytes{0x86, 0x03});        // torque 201 %
  CHECK(b.pdu(1, {0x05, 0x00, 0x64, 0x12, 0x34}) == bytes{0x85, 0x03});        // coil value
  CHECK(b.pdu(1, {0x04, 0x00, 0x64, 0x00, 0x09, 0x00}) == bytes{0x84, 0x03});  // extra byte
  // settings written and read back, limits respected
  CHECK(b.pdu(1, {0x06, 0x00, 0x24, 0x03, 0x20}) == bytes{0x06, 0x00, 0x24, 0x03, 0x20});
  CHECK(b.unit.setting(36) == 800);
  CHECK(b.pdu(1, {0x03, 0x00, 0x24, 0x00, 0x01}) == bytes{0x03, 0x02, 0x03, 0x20});
  CHECK(b.pdu(1, {0x10, 0x00, 0x26, 0x00, 0x02, 0x04, 0x00, 0x05, 0x00, 0x3C}) ==
        bytes{0x10, 0x00, 0x26, 0x00, 0x02});
  CHECK(b.unit.setting(39) == 60);
  // input registers 0..8 mirror the settings of DIP switch No.1
  CHECK(b.pdu(1, {0x04, 0x00, 0x04, 0x00, 0x01}) == bytes{0x04, 0x02, 0x00, 0x01});
  // FC11 in the SM unit's layout
  CHECK(b.pdu(1, {0x11}) == bytes{0x11, 0x01, 0x00});
}

TEST_CASE("SM unit emulator: broadcasts, other addresses, warnings, data over time") {
  bench b;
  CHECK(b.pdu(0, {0x06, 0x00, 0x24, 0x02, 0x58}).empty());  // broadcast: executed, no reply
  CHECK(b.unit.setting(36) == 600);
  CHECK(b.pdu(2, {0x06, 0x00, 0x24, 0x01, 0x00}).empty());  // another unit
  CHECK(b.unit.setting(36) == 600);
  b.unit.inject_warning(sm::warning::overheat);
  b.unit.inject_warning(sm::warning::torque_upper_b);
  CHECK(b.pdu(1, {0x04, 0x00, 0xC8, 0x00, 0x05}) ==
        bytes{0x04, 0x0A, 0x00, 0x02, 0x00, 0x22, 0x00, 0x02, 0x00, 0x20, 0x00, 0x00});
  CHECK(b.ask([](auto out) { return sm::set_coil(1, sm::coil::warning_reset, out); }).size() == 5);
  CHECK(b.unit.warning_status() == 0);
  CHECK(b.unit.warning_count() == 2);
  CHECK(b.ask([](auto out) {
           return sm::set_coil(1, sm::coil::warning_count_clear, out);
         }).size() == 5);
  CHECK(b.unit.warning_count() == 0);
  // instantaneous data changes with time, and decodes with the profile
  const auto at = [&](std::uint32_t ms) {
    b.unit.set_time_ms(ms);
    std::uint8_t req[256] = {};
    const std::size_t n = sm::read_instantaneous(1, req).value();
    const bytes resp = b.serve(byte_view(req, n));
    const auto r =
        mo::decode_response_for(byte_view(req + 1, n - 3), byte_view(resp.data(), resp.size()));
    REQUIRE(r.is_complete());
    return sm::decode_instantaneous(r.value()).value();
  };
  const auto v0 = at(0);
  const auto v1 = at(1500);
  CHECK(v0[sm::channel::voltage] != v1[sm::channel::voltage]);
  CHECK(v0[sm::channel::voltage] >= 2000);
  CHECK(v0[sm::channel::acceleration_x] < 0);  // signed channel below zero
  CHECK(v0[sm::channel::frequency] == 50);
  // a log channel: 20 samples
  CHECK(b.ask([](auto out) { return sm::read_log(1, 3, sm::channel::torque, out); }).size() == 42);
}

TEST_CASE("SM unit emulator: coils, short requests, state registers, login block, passwords") {
  sm::emulator unit;
  // FC01 on the coils: both read back OFF (they act and turn themselves off, §8)
  CHECK(serve_pdu(unit, 1, {0x01, 0x00, 0x64, 0x00, 0x01}) == bytes{0x01, 0x01, 0x00});
  // too short to carry an address: data error
  CHECK(serve_pdu(unit, 1, {0x03, 0x00}) == bytes{0x83, 0x03});
  // input registers outside every block: address error
  CHECK(serve_pdu(unit, 1, {0x04, 0x01, 0x90, 0x00, 0x01}) == bytes{0x84, 0x02});
  // state registers 205..207 all read setting 38
  const bytes state = serve_pdu(unit, 1, {0x04, 0x00, 0xCD, 0x00, 0x03});
  REQUIRE(state.size() == 8);
  CHECK(state[2] == state[4]);
  CHECK(state[3] == state[5]);
  CHECK(mo::register_at(byte_view(state.data() + 2, 6), 2) == unit.setting(38));
  // the login block reads as NUL characters
  const bytes login = serve_pdu(unit, 1, {0x03, 0x00, 0x64, 0x00, 0x08});
  REQUIRE(login.size() == 18);
  CHECK(login[2] == 0);
  CHECK(login[17] == 0);
  // a password with a character after the padding is a data error
  CHECK(serve_pdu(unit, 1, {0x10, 0x00, 0xC8, 0x00, 0x08, 0x10, 'a', 'b', 'c', 'd', ' ',
                            ' ',  'e',  'f',  'g',  'h',  'i',  'j', 'k', 'l', 'm', 'n'}) ==
        bytes{0x90, 0x03});
  // ...and so is one with a character outside the printable 0x21..0x7E (a control
  // character, DEL), where the padding does not come in
  CHECK(serve_pdu(unit, 1, {0x10, 0x00, 0xC8, 0x00, 0x08, 0x10, 'a', 'b', 'c', 0x07, 'e',
                            'f',  'g',  'h',  'i',  'j',  'k',  'l', 'm', 'n', 'o',  'p'}) ==
        bytes{0x90, 0x03});
  CHECK(serve_pdu(unit, 1, {0x10, 0x00, 0xC8, 0x00, 0x08, 0x10, 'a', 'b', 'c', 'd', 'e',
                            'f',  'g',  'h',  0x7F, 'j',  'k',  'l', 'm', 'n', 'o', 'p'}) ==
        bytes{0x90, 0x03});
  // logged out, a settings write by FC10 is a login error
  std::uint8_t out[256] = {};
  const auto n = sm::login(1, text("password"), mutable_byte_view(out, sizeof out));
  REQUIRE(n.ok());
  const auto f = mo::decode_rtu(byte_view(out, n.value()));
  REQUIRE(f.is_complete());
  serve_pdu(unit, 1, bytes(f->pdu.begin(), f->pdu.end()));
  REQUIRE(!unit.logged_in());
  CHECK(serve_pdu(unit, 1, {0x10, 0x00, 0x24, 0x00, 0x01, 0x02, 0x02, 0x58}) == bytes{0x90, 0x04});
}

TEST_CASE("SM unit emulator: changing the password while logged out is a login error") {
  sm::emulator unit;
  std::uint8_t out[256] = {};
  auto send = [&](result<std::size_t> n) {
    REQUIRE(n.ok());
    const auto f = mo::decode_rtu(byte_view(out, n.value()));
    REQUIRE(f.is_complete());
    return serve_pdu(unit, 1, bytes(f->pdu.begin(), f->pdu.end()));
  };
  send(sm::login(1, text("password"), mutable_byte_view(out, sizeof out)));
  REQUIRE(!unit.logged_in());
  CHECK(send(sm::change_password(1, text("other-pass"), mutable_byte_view(out, sizeof out))) ==
        bytes{0x90, 0x04});
}

namespace {

// What the emulator holds, as a client can see it: the settings, the login state, the warning
// status and count, and the password (read after logging in with the default password, which
// fails if the password changed).
bytes state_of(sm::emulator unit) {
  bytes s;
  for (std::uint16_t i = 0; i < sm::holding::setting_count; ++i) {
    s.push_back(static_cast<std::uint8_t>(unit.setting(i) >> 8U));
    s.push_back(static_cast<std::uint8_t>(unit.setting(i) & 0xFFU));
  }
  s.push_back(unit.logged_in() ? 1 : 0);
  s.push_back(static_cast<std::uint8_t>(unit.warning_status()));
  s.push_back(static_cast<std::uint8_t>(unit.warning_count()));
  if (!unit.logged_in()) {
    serve_pdu(unit, 1, {0x10, 0x00, 0x64, 0x00, 0x08, 0x10, 'p', 'a', 's', 's', 'w',
                        'o',  'r',  'd',  0,    0,    0,    0,   0,   0,   0,   0});
  }
  const bytes password = serve_pdu(unit, 1, {0x03, 0x00, 0xC8, 0x00, 0x08});
  s.insert(s.end(), password.begin(), password.end());
  return s;
}

// Write requests of every kind the unit serves, valid and not: settings within and past their
// limits and their area, the login and password blocks with good, wrong and malformed
// passwords, the coils.
std::vector<bytes> sm_unit_writes() {
  const std::uint8_t starts[] = {0, 1, 35, 36, 39, 40, 100, 200};
  const std::uint16_t values[] = {0, 1, 800, 0xFFFF};
  std::vector<bytes> out;
  for (const std::uint8_t a : starts) {
    for (const std::uint16_t v : values) {
      out.push_back({0x06, 0x00, a, static_cast<std::uint8_t>(v >> 8U),
                     static_cast<std::uint8_t>(v & 0xFFU)});
    }
    out.push_back({0x10, 0x00, a, 0x00, 0x02, 0x04, 0x00, 0x01, 0x03, 0x20});
    out.push_back({0x10, 0x00, a, 0x00, 0x02, 0x04, 0x00, 0x01, 0xFF, 0xFF});
    for (const char* pw : {"password", "other-pass", "short", "pass word"}) {
      bytes q = {0x10, 0x00, a, 0x00, 0x08, 0x10};
      for (std::size_t i = 0; i < 16U; ++i) {
        q.push_back(i < std::strlen(pw) ? static_cast<std::uint8_t>(pw[i]) : 0U);
      }
      out.push_back(q);
    }
    out.push_back({0x05, 0x00, a, 0xFF, 0x00});
    out.push_back({0x0F, 0x00, a, 0x00, 0x01, 0x01, 0x01});
    out.push_back({0x0F, 0x00, a, 0x00, 0x02, 0x01, 0x03});
  }
  return out;
}

}  // namespace

TEST_CASE("SM unit emulator: an exception leaves the unit as it was, unicast or broadcast") {
  int exceptions = 0;
  for (bool logged_in : {true, false}) {
    for (const bytes& q : sm_unit_writes()) {
      CAPTURE(logged_in);
      CAPTURE(static_cast<int>(q[0]));
      CAPTURE(static_cast<int>(q[2]));
      sm::emulator start;
      start.inject_warning(sm::warning::overheat);
      if (!logged_in) {
        serve_pdu(start, 1, {0x10, 0x00, 0x64, 0x00, 0x08, 0x10, 'p', 'a', 's', 's', 'w',
                             'o',  'r',  'd',  0,    0,    0,    0,   0,   0,   0,   0});
        REQUIRE(!start.logged_in());
      }
      sm::emulator unicast = start;
      const bytes answer = serve_pdu(unicast, 1, q);
      REQUIRE(answer.size() >= 2U);
      sm::emulator broadcast = start;
      CHECK(serve_adu(broadcast, 1, view(rtu(0, q))).empty());
      if ((answer[0] & 0x80U) != 0U) {
        ++exceptions;
        CHECK(state_of(unicast) == state_of(start));
        CHECK(state_of(broadcast) == state_of(start));
      } else {
        CHECK(state_of(broadcast) == state_of(unicast));
      }
    }
  }
  CHECK(exceptions > 50);
}

TEST_CASE("SM unit emulator: a setting below its lower limit, a coil written OFF, odd passwords") {
  bench b;
  // setting 4 (a start time, 1..300): 0 is below its lower limit, 03
  CHECK(b.pdu(1, {0x06, 0x00, 0x04, 0x00, 0x00}) == bytes{0x86, 0x03});
  CHECK(b.pdu(1, {0x10, 0x00, 0x04, 0x00, 0x01, 0x02, 0x00, 0x00}) == bytes{0x90, 0x03});
  CHECK(b.unit.setting(sm::holding::setting_count) == 0);  // no setting there
  // logged in (at power-on), a coil written OFF (0x0000) clears nothing
  REQUIRE(b.unit.logged_in());
  b.unit.inject_warning(static_cast<std::uint16_t>(sm::warning::excessive_shock));
  REQUIRE(b.unit.warning_count() == 1);
  CHECK(b.pdu(1, {0x05, 0x00, 0x00, 0x00, 0x00}) == bytes{0x05, 0x00, 0x00, 0x00, 0x00});
  CHECK(b.pdu(1, {0x05, 0x00, 0x64, 0x00, 0x00}) == bytes{0x05, 0x00, 0x64, 0x00, 0x00});
  CHECK(b.unit.warning_count() == 1);
  CHECK(b.unit.warning_status() != 0);
  // a password with a control character (0x1F) or DEL (0x7F) in it, or a character after the
  // padding, is malformed: 03, the login state kept
  const bytes control = {0x10, 0x00, 0x64, 0x00, 0x08, 0x10, 'p', 'a', 's', 's', 'w', 'o', 'r',
                         0x1F, 0,    0,    0,    0,    0,    0,   0,   0,   0,   0,   0};
  CHECK(b.pdu(1, control) == bytes{0x90, 0x03});
  bytes del = control;
  del[13] = 0x7F;
  CHECK(b.pdu(1, del) == bytes{0x90, 0x03});
  bytes gap = control;
  gap[13] = 'd';
  gap[14] = 0x20;
  gap[15] = 'x';  // a character after a space
  CHECK(b.pdu(1, gap) == bytes{0x90, 0x03});
  CHECK(b.unit.logged_in());
}

TEST_CASE("SM unit emulator: a channel outside the enumeration reads 0") {
  const sm::emulator unit;
  CHECK(unit.instantaneous_register(static_cast<sm::channel>(sm::channel_count)) == 0);
  CHECK(unit.instantaneous_register(sm::channel::frequency) == 50);
}

TEST_CASE("SM unit emulator: the factory settings at power-on") {
  // the header's power-on state: every limit off (0) but those whose lower limit is 1 (the
  // start times, the log interval), overheat at 80.0 degC, excessive shock at 50.00 m/s2, a
  // log interval of 1.0 s
  const sm::emulator unit;
  for (std::uint16_t i = 0; i < sm::holding::setting_count; ++i) {
    CAPTURE(i);
    if (i == 36) {
      CHECK(unit.setting(i) == 800);
    } else if (i == 37) {
      CHECK(unit.setting(i) == 5000);
    } else if (i == 38) {
      CHECK(unit.setting(i) == 10);
    } else {
      CHECK(unit.setting(i) == sm::setting_limits(i).value().lower);
    }
  }
  // the acquisition intervals of logs 1..3 (input 205..207, §9) are that 1.0 s
  sm::emulator copy = unit;
  CHECK(serve_pdu(copy, 1, {0x04, 0x00, 0xCD, 0x00, 0x03}) ==
        bytes{0x04, 0x06, 0x00, 0x0A, 0x00, 0x0A, 0x00, 0x0A});
}

TEST_CASE("SM unit emulator: warning factor logs 1..3 hold the last three warnings (§9)") {
  sm::emulator unit;
  unit.inject_warning(sm::warning::torque_upper_a);
  unit.inject_warning(sm::warning::torque_lower_b);
  unit.inject_warning(sm::warning::overheat);
  unit.inject_warning(sm::warning::excessive_shock);
  // 200 count, 201 status, 202 the last factor, 203 the one before, 204 three times before
  CHECK(serve_pdu(unit, 1, {0x04, 0x00, 0xC8, 0x00, 0x05}) ==
        bytes{0x04, 0x0A, 0x00, 0x04, 0x00, 0x69, 0x00, 0x40, 0x00, 0x20, 0x00, 0x08});
}

TEST_CASE("SM unit emulator: the functions of §6, an address before the data, FC11 alone") {
  sm::emulator unit;
  // FC0F (Force Multiple Coils, §6) on the warning reset coil: served, the warning reset
  unit.inject_warning(sm::warning::overheat);
  CHECK(serve_pdu(unit, 1, {0x0F, 0x00, 0x64, 0x00, 0x01, 0x01, 0x01}) ==
        bytes{0x0F, 0x00, 0x64, 0x00, 0x01});
  CHECK(unit.warning_status() == 0);
  // FC07 is not in §6: a function error, even with an address and a quantity
  CHECK(serve_pdu(unit, 1, {0x07, 0x00, 0x00, 0x00, 0x01}) == bytes{0x87, 0x01});
  // cut after an unsupported address (500): the address error comes first (02 before 03, §5)
  CHECK(serve_pdu(unit, 1, {0x03, 0x01, 0xF4}) == bytes{0x83, 0x02});
  // cut inside the address: the number of bytes is invalid (03), whatever follows the PDU
  const std::uint8_t cut[] = {0x03, 0x01, 0xF4};
  std::uint8_t out[256] = {};
  const auto n = mo::serve_pdu(unit, byte_view(cut, 2), mutable_byte_view(out, sizeof out));
  REQUIRE(n.ok());
  CHECK(bytes(out, out + n.value()) == bytes{0x83, 0x03});
  // FC11 has no data (§11): bytes after its code are a data error, not an address error
  CHECK(serve_pdu(unit, 1, {0x11, 0x00, 0x00}) == bytes{0x91, 0x03});
}

TEST_CASE("SM unit emulator: the areas of §7 to their last address, and not one past it") {
  sm::emulator unit;
  // holding 0..39: 39 alone is a setting, 39..40 runs past the area
  CHECK(serve_pdu(unit, 1, {0x03, 0x00, 0x27, 0x00, 0x01}) == bytes{0x03, 0x02, 0x00, 0x00});
  CHECK(serve_pdu(unit, 1, {0x03, 0x00, 0x27, 0x00, 0x02}) == bytes{0x83, 0x02});
  CHECK(serve_pdu(unit, 1, {0x06, 0x00, 0x27, 0x00, 0x3C}) == bytes{0x06, 0x00, 0x27, 0x00, 0x3C});
  CHECK(unit.setting(39) == 60);
  // input 300 (login status) is one register
  CHECK(serve_pdu(unit, 1, {0x04, 0x01, 0x2C, 0x00, 0x02}) == bytes{0x84, 0x02});
  // logs 1..3, channels 0 (voltage) .. 8 (torque): 1000 and 3800 taken, 4000 and 1900 not
  CHECK(serve_pdu(unit, 1, {0x04, 0x03, 0xE8, 0x00, 0x14}).size() == 42);
  CHECK(serve_pdu(unit, 1, {0x04, 0x0E, 0xD8, 0x00, 0x14}).size() == 42);
  CHECK(serve_pdu(unit, 1, {0x04, 0x0F, 0xA0, 0x00, 0x14}) == bytes{0x84, 0x02});
  CHECK(serve_pdu(unit, 1, {0x04, 0x07, 0x6C, 0x00, 0x14}) == bytes{0x84, 0x02});
}

TEST_CASE("SM unit emulator: settings at both their limits are written (§10)") {
  sm::emulator unit;
  CHECK(serve_pdu(unit, 1, {0x06, 0x00, 0x00, 0x00, 0xC8}) == bytes{0x06, 0x00, 0x00, 0x00, 0xC8});
  CHECK(unit.setting(0) == 200);  // torque upper limit: 0..200 %
  CHECK(serve_pdu(unit, 1, {0x06, 0x00, 0x00, 0x00, 0x00}) == bytes{0x06, 0x00, 0x00, 0x00, 0x00});
  CHECK(unit.setting(0) == 0);
  CHECK(serve_pdu(unit, 1, {0x06, 0x00, 0x26, 0x00, 0x01}) == bytes{0x06, 0x00, 0x26, 0x00, 0x01});
  CHECK(unit.setting(38) == 1);  // log interval: 1..100
  CHECK(serve_pdu(unit, 1, {0x10, 0x00, 0x25, 0x00, 0x02, 0x04, 0x3A, 0x98, 0x00, 0x64}) ==
        bytes{0x10, 0x00, 0x25, 0x00, 0x02});
  CHECK(unit.setting(37) == 15000);  // excessive shock: 0..15000
  CHECK(unit.setting(38) == 100);
  // a block of settings writes those it names and no other
  CHECK(serve_pdu(unit, 1, {0x10, 0x00, 0x23, 0x00, 0x02, 0x04, 0x00, 0x07, 0x00, 0x08}) ==
        bytes{0x10, 0x00, 0x23, 0x00, 0x02});
  CHECK(unit.setting(35) == 7);
  CHECK(unit.setting(36) == 8);
  CHECK(unit.setting(37) == 15000);
}

TEST_CASE("SM unit emulator: the product code and MFG number it answers") {
  // §10: product-specific numbers set at shipment, which the guideline does not give; the
  // emulator's are "SM01" and "2611220042", two ASCII characters per register, high byte
  // first (pinned here: a client of the emulator sees these)
  sm::emulator unit;
  CHECK(serve_pdu(unit, 1, {0x03, 0x01, 0x2C, 0x00, 0x02}) ==
        bytes{0x03, 0x04, 'S', 'M', '0', '1'});
  CHECK(serve_pdu(unit, 1, {0x03, 0x01, 0x5E, 0x00, 0x05}) ==
        bytes{0x03, 0x0A, '2', '6', '1', '1', '2', '2', '0', '0', '4', '2'});
}

TEST_CASE("SM unit emulator: every password character checked, and the settings kept") {
  bench b;
  // setting 0 not 0, to see that the password's changes leave the settings alone
  CHECK(b.pdu(1, {0x06, 0x00, 0x00, 0x00, 0x64}).size() == 5);
  // a password differing from "password" in its first character only: 04
  CHECK(b.ask([](auto out) { return sm::login(1, text("Password"), out); }) == bytes{0x90, 0x04});
  CHECK(b.unit.logged_in());
  // '~' (0x7E), the last character allowed (§10), in a new password of 16 characters
  CHECK(b.ask([](auto out) { return sm::change_password(1, text("~pass~word~16ch~"), out); }) ==
        bytes{0x10, 0x00, 0xC8, 0x00, 0x08});
  CHECK(b.unit.setting(0) == 100);
  CHECK(b.ask([](auto out) { return sm::login(1, text("~pass~word~16ch~"), out); }).size() == 5);
  CHECK(!b.unit.logged_in());
  CHECK(b.ask([](auto out) { return sm::login(1, text("~pass~word~16ch~"), out); }).size() == 5);
  CHECK(b.unit.logged_in());
  // and one of 8 characters again
  CHECK(b.ask([](auto out) { return sm::change_password(1, text("pass~ord"), out); }).size() == 5);
  CHECK(b.unit.setting(0) == 100);
  CHECK(b.ask([](auto out) { return sm::login(1, text("pass~ord"), out); }).size() == 5);
  CHECK(!b.unit.logged_in());
}

TEST_CASE("SM unit emulator: the accessors touch no register past the span they are given") {
  sm::emulator unit;
  // reads fill `out`, not the register after it
  std::uint16_t regs[10] = {};
  regs[3] = 0xABCD;
  CHECK(unit.read_registers(0x03, 36, span<std::uint16_t>(regs, 3)) == 0);
  CHECK(regs[0] == 800);
  CHECK(regs[2] == 10);
  CHECK(regs[3] == 0xABCD);
  regs[9] = 0xABCD;
  CHECK(unit.read_registers(0x04, 100, span<std::uint16_t>(regs, 9)) == 0);
  CHECK(regs[7] == 50);  // frequency
  CHECK(regs[9] == 0xABCD);
  // writes take the values of `values`, not the one after it
  const std::uint16_t values[3] = {900, 6000, 77};
  CHECK(unit.write_registers(36, span<const std::uint16_t>(values, 2)) == 0);
  CHECK(unit.setting(36) == 900);
  CHECK(unit.setting(37) == 6000);
  CHECK(unit.setting(38) == 10);
  // the login block reads 8 registers, not a 9th after them: "password" padded with NUL logs
  // out, whatever follows
  const std::uint16_t login[9] = {0x7061, 0x7373, 0x776F, 0x7264, 0, 0, 0, 0, 0x5858};
  CHECK(unit.write_registers(sm::holding::login, span<const std::uint16_t>(login, 8)) == 0);
  CHECK(!unit.logged_in());
  // a password block of another length than 8 registers is a data error, for a caller that
  // does not go through admit() (the header keeps the check for such callers)
  CHECK(unit.write_registers(sm::holding::login, span<const std::uint16_t>(login, 4)) ==
        sm::emulator::data_error);
  CHECK(!unit.logged_in());
  // FC11's two bytes both written
  std::uint8_t id[4] = {0xAA, 0xAA, 0xAA, 0xAA};
  std::size_t size = 0;
  CHECK(unit.report_server_id(mutable_byte_view(id, sizeof id), size) == 0);
  CHECK(size == 2);
  CHECK(id[0] == 0x01);
  CHECK(id[1] == 0x00);
}

namespace {

// A channel's waveform: a triangle of `period` tenths of a second from `low` at time 0 up to
// `low + amplitude` at half the period and back, in whole register steps (x * amplitude /
// (period / 2), truncated).
struct wave {
  sm::channel c;
  std::int32_t low;
  std::uint32_t period;
  std::int32_t amplitude;
};

std::int32_t triangle(const wave& w, std::uint32_t tenths) {
  const std::int32_t half = static_cast<std::int32_t>(w.period / 2U);
  const std::int32_t p = static_cast<std::int32_t>(tenths % w.period);
  const std::int32_t rise = p <= half ? p : static_cast<std::int32_t>(w.period) - p;
  return w.low + rise * w.amplitude / half;
}

}  // namespace

TEST_CASE("SM unit emulator: instantaneous data, triangle waves in the header's ranges") {
  // The ranges of the header's comments (200.0..206.0 V, 1.50..1.90 A, 260.0..290.0 W,
  // 35.0..43.0 degC, -0.30..0.30 m/s2, 12.0..15.0 N.m); Y's (-0.10..0.10 m/s2), Z's
  // (9.79..9.83 m/s2), the frequency's (50 Hz) and the periods (5, 8, 8, 60, 2, 3, 1 and 4 s)
  // are the emulator's own choice (its header says "slow triangle waves"), pinned here with
  // the steps; they give the transcript of docs/modbus.md §6 at 0.5 s.
  const wave waves[] = {
      {sm::channel::voltage, 2000, 50, 60},       {sm::channel::current, 150, 80, 40},
      {sm::channel::power, 2600, 80, 300},        {sm::channel::temperature, 350, 600, 80},
      {sm::channel::acceleration_x, -30, 20, 60}, {sm::channel::acceleration_y, -10, 30, 20},
      {sm::channel::acceleration_z, 979, 10, 4},  {sm::channel::frequency, 50, 10, 0},
      {sm::channel::torque, 120, 40, 30},
  };
  sm::emulator unit;
  for (const wave& w : waves) {
    CAPTURE(static_cast<int>(w.c));
    std::int32_t lowest = 1 << 20;
    std::int32_t highest = -(1 << 20);
    for (std::uint32_t tenths = 0; tenths <= 2U * w.period + 1U; ++tenths) {
      CAPTURE(tenths);
      unit.set_time_ms(100U * tenths + 99U);  // 0.1 s steps: the same all through the step
      const std::int32_t v = sm::raw_value(w.c, unit.instantaneous_register(w.c));
      CHECK(v == triangle(w, tenths));
      lowest = v < lowest ? v : lowest;
      highest = v > highest ? v : highest;
    }
    CHECK(lowest == w.low);
    CHECK(highest == w.low + w.amplitude);
  }
  // docs/modbus.md §6: "voltage=201.2 V current=1.55 A power=263.7 W temperature=35.1 degC
  // acceleration_x=0 m/s2 acceleration_y=-0.04 m/s2 acceleration_z=9.83 m/s2 frequency=50 Hz
  // torque=12.7 N.m" (a transcript of a real-time run: these are the values at 0.5 s)
  unit.set_time_ms(500);
  const std::int32_t docs[] = {2012, 155, 2637, 351, 0, -4, 983, 50, 127};
  for (std::size_t i = 0; i < sm::channel_count; ++i) {
    CAPTURE(i);
    const auto c = static_cast<sm::channel>(i);
    CHECK(sm::raw_value(c, unit.instantaneous_register(c)) == docs[i]);
  }
}

TEST_CASE("SM unit emulator: read_registers() reads 0 just past each holding block (§7)") {
  // the accessor, as a caller that does not go through admit() uses it: the register after
  // each block (settings 0..39, password 200..207, product code 300..301, MFG number 350..354)
  // is no register of the unit
  sm::emulator unit;
  REQUIRE(unit.logged_in());             // at power-on (§6 note *1): setting 0 may be written
  const std::uint16_t first[1] = {100};  // setting 0 nonzero: the bytes behind the password
  REQUIRE(unit.write_registers(0, span<const std::uint16_t>(first, 1)) == 0);
  for (const unsigned last : {39U, 207U, 301U, 354U}) {
    CAPTURE(last);
    std::uint16_t regs[2] = {0xABCD, 0xABCD};
    CHECK(unit.read_registers(0x03, static_cast<std::uint16_t>(last),
                              span<std::uint16_t>(regs, 2)) == 0);
    CHECK(regs[1] == 0);
  }
}

TEST_CASE("SM unit emulator: read_registers() reads 0 for an input outside the areas of §7") {
  // the accessor, as a caller that does not go through admit() uses it: set parameters 0..8,
  // instantaneous data 100..108, logs 1..3 (channel 0..8, sample 0..19) and the others of §7;
  // any other input is no register of the unit, as a holding register outside §7 is not
  sm::emulator unit;
  const std::uint16_t tenth[1] = {7};  // setting 9: nonzero, behind the set parameters
  REQUIRE(unit.write_registers(9, span<const std::uint16_t>(tenth, 1)) == 0);
  std::uint16_t regs[1] = {};
  for (const unsigned outside : {9U, 109U, 1020U, 1900U, 1905U, 2919U, 3999U, 4000U, 999U}) {
    CAPTURE(outside);
    regs[0] = 0xABCD;
    CHECK(unit.read_registers(0x04, static_cast<std::uint16_t>(outside),
                              span<std::uint16_t>(regs, 1)) == 0);
    CHECK(regs[0] == 0);
  }
  // inside: the last sample of log 3's torque, and the first of log 1's voltage
  unit.set_time_ms(0);
  CHECK(unit.read_registers(0x04, 3819, span<std::uint16_t>(regs, 1)) == 0);
  CHECK(regs[0] == unit.instantaneous_register(sm::channel::torque) + 19U * 3U);
  CHECK(unit.read_registers(0x04, 1000, span<std::uint16_t>(regs, 1)) == 0);
  CHECK(regs[0] == unit.instantaneous_register(sm::channel::voltage));
}
