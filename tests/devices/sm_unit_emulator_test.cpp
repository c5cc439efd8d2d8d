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
