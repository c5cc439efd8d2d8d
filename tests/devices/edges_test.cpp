// Device profiles at the edges: every refusal of the SM unit request builders and response
// decoders, the emulator's less common requests, and the TS5700N8500 plans built at run time
// (the static suite builds them at compile time, which coverage does not count).
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "motionbus/devices/sm_unit_emulator.hpp"
#include "motionbus/devices/ts5700n8500.hpp"

using namespace motionbus;
namespace sm = motionbus::devices::sm_unit;
namespace ts = motionbus::devices::ts5700n8500;
namespace mo = motionbus::modbus;
namespace tf = motionbus::tformat;

namespace {

using bytes = std::vector<std::uint8_t>;

// The emulator behind the RTU server dispatch: a request PDU in, the response PDU out.
bytes ask(sm::emulator& unit, const bytes& pdu) {
  std::uint8_t adu[256] = {};
  const auto n = mo::encode_rtu(1, byte_view(pdu.data(), pdu.size()), adu);
  REQUIRE(n.ok());
  std::uint8_t out[256] = {};
  const auto r = mo::serve_rtu(unit, 1, byte_view(adu, n.value()), out);
  REQUIRE(r.ok());
  const auto f = mo::decode_rtu(byte_view(out, r.value()));
  REQUIRE(f.is_complete());
  return bytes(f->pdu.begin(), f->pdu.end());
}

byte_view text(const char* s) {
  return byte_view(reinterpret_cast<const std::uint8_t*>(s), std::strlen(s));
}

}  // namespace

TEST_CASE("SM unit builders: slave 248 and above is refused by every builder") {
  std::uint8_t out[256] = {};
  const mutable_byte_view o(out, sizeof out);
  const std::uint16_t values[2] = {100, 100};
  CHECK(sm::write_setting(248, 36, 700, o).error() == errc::modbus_slave_address);
  CHECK(sm::write_settings(248, 36, span<const std::uint16_t>(values, 2), o).error() ==
        errc::modbus_slave_address);
  CHECK(sm::detail::write_password_block(248, sm::holding::login, text("password"), o).error() ==
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

TEST_CASE("SM unit emulator: coils, short requests, state registers, login block, passwords") {
  sm::emulator unit;
  // FC01 on the coils: both read back OFF (they act and turn themselves off, §8)
  CHECK(ask(unit, {0x01, 0x00, 0x64, 0x00, 0x01}) == bytes{0x01, 0x01, 0x00});
  // too short to carry an address: data error
  CHECK(ask(unit, {0x03, 0x00}) == bytes{0x83, 0x03});
  // input registers outside every block: address error
  CHECK(ask(unit, {0x04, 0x01, 0x90, 0x00, 0x01}) == bytes{0x84, 0x02});
  // state registers 205..207 all read setting 38
  const bytes state = ask(unit, {0x04, 0x00, 0xCD, 0x00, 0x03});
  REQUIRE(state.size() == 8);
  CHECK(state[2] == state[4]);
  CHECK(state[3] == state[5]);
  CHECK(mo::register_at(byte_view(state.data() + 2, 6), 2) == unit.setting(38));
  // the login block reads as NUL characters
  const bytes login = ask(unit, {0x03, 0x00, 0x64, 0x00, 0x08});
  REQUIRE(login.size() == 18);
  CHECK(login[2] == 0);
  CHECK(login[17] == 0);
  // a password with a character after the padding is a data error
  CHECK(ask(unit, {0x10, 0x00, 0xC8, 0x00, 0x08, 0x10, 'a', 'b', 'c', 'd', ' ',
                   ' ',  'e',  'f',  'g',  'h',  'i',  'j', 'k', 'l', 'm', 'n'}) ==
        bytes{0x90, 0x03});
  // logged out, a settings write by FC10 is a login error
  std::uint8_t out[256] = {};
  const auto n = sm::login(1, text("password"), mutable_byte_view(out, sizeof out));
  REQUIRE(n.ok());
  const auto f = mo::decode_rtu(byte_view(out, n.value()));
  REQUIRE(f.is_complete());
  ask(unit, bytes(f->pdu.begin(), f->pdu.end()));
  REQUIRE(!unit.logged_in());
  CHECK(ask(unit, {0x10, 0x00, 0x24, 0x00, 0x01, 0x02, 0x02, 0x58}) == bytes{0x90, 0x04});
}

TEST_CASE("unit and alarm tables: a value outside the enumeration has a neutral entry") {
  volatile int undefined = 99;  // run time, not a constant initialiser
  const sm::unit_info u = sm::unit_of(static_cast<sm::channel>(undefined));
  CHECK(std::strcmp(u.unit, "") == 0);
  CHECK(u.numerator == 1);
  CHECK(u.denominator == 1);
  // an undefined ALMC bit pattern gets the table's first row (the caller passes single bits)
  CHECK(&ts::info(static_cast<tf::almc_bit>(0x03)) == &ts::alarm_table[0]);
}

TEST_CASE("SM unit emulator: changing the password while logged out is a login error") {
  sm::emulator unit;
  std::uint8_t out[256] = {};
  auto send = [&](result<std::size_t> n) {
    REQUIRE(n.ok());
    const auto f = mo::decode_rtu(byte_view(out, n.value()));
    REQUIRE(f.is_complete());
    return ask(unit, bytes(f->pdu.begin(), f->pdu.end()));
  };
  send(sm::login(1, text("password"), mutable_byte_view(out, sizeof out)));
  REQUIRE(!unit.logged_in());
  CHECK(send(sm::change_password(1, text("other-pass"), mutable_byte_view(out, sizeof out))) ==
        bytes{0x90, 0x04});
}

TEST_CASE("TS5700N8500 plans built at run time") {
  for (const tf::data_id id :
       {tf::data_id::reset_errors, tf::data_id::reset_single_turn, tf::data_id::reset_multi_turn}) {
    const auto p = ts::reset_plan(id);
    REQUIRE(p.ok());
    CHECK(p->size == 10);
    CHECK(p->steps[9].wait_after_us ==
          (id == tf::data_id::reset_single_turn ? ts::eeprom_write_us : ts::reset_interval_us));
  }
  volatile std::uint8_t page = 2;  // run time, not a constant initialiser
  const auto w = ts::write_verify_plan(page, 5, 0xA5);
  REQUIRE(w.ok());
  CHECK(w->size == 4);
  CHECK(w->steps[3].verify);
  CHECK(w->steps[3].expected_edf == 0xA5);
  // a plan with no room left, and a request the codec refuses, are refused by add_step
  ts::plan<1> one;
  CHECK(ts::detail::add_step(one, tf::data_id::read_abs, 0) == errc::ok);
  CHECK(ts::detail::add_step(one, tf::data_id::read_abs, 0) == errc::buffer_too_small);
  ts::plan<1> bad;
  CHECK(ts::detail::add_step(bad, static_cast<tf::data_id>(0x5), 0) ==
        errc::tformat_unknown_data_id);
}
