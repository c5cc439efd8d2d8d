// The encoder model: abnormal requests (spec Tables 5 and 6), EEPROM pages, busy windows,
// page 7 registers, resets after 10 requests, latched and non-latched alarms.
#include "motionbus/devices/ts5700n8500_emulator.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#if defined(__has_include)
#if __has_include(<unistd.h>)
#include <unistd.h>  // POSIX declares alarm(): the names below must not collide with it
#endif
#endif
#include <vector>

#include "motionbus/devices/ts5700n8500.hpp"

using namespace motionbus;
using namespace motionbus::tformat;
namespace ts = motionbus::devices::ts5700n8500;

namespace {

struct master {
  ts::emulator& enc;
  std::uint32_t now = 0;

  decode_result<response> ask(data_id id, std::uint8_t address = 0, std::uint8_t data = 0,
                              std::uint32_t advance_us = 100) {
    std::uint8_t req[4] = {};
    const std::size_t n = encode_request(id, address, data, req).value();
    now += advance_us;
    const ts::reply rep = enc.respond(byte_view(req, n), now);
    return decode_response_for(byte_view(req, n), rep.view());
  }
};

}  // namespace

TEST_CASE("abnormal requests: no reply on a bad sync code, ID3 data otherwise") {
  ts::emulator enc;
  enc.set_position(1000, 7);
  const std::uint8_t bad_sync[] = {0x03};
  CHECK(enc.respond(bad_sync, 0).size == 0);
  CHECK(enc.respond(byte_view{}, 0).size == 0);

  const std::uint8_t bad_parity[] = {0x82};  // ID0 with the parity bit flipped
  ts::reply r = enc.respond(bad_parity, 0);
  REQUIRE(r.size == 11);
  auto d = decode_response(r.view());
  REQUIRE(d.is_complete());
  CHECK(d->id == data_id::read_all);
  CHECK(d->ca0());
  CHECK(!d->ca1());
  CHECK(d->abs == 1000);

  const std::uint8_t id0[] = {0x02};
  r = enc.respond(id0, 0, ts::request_line::delimiter_error);  // the UART saw a bad delimiter
  d = decode_response(r.view());
  CHECK(d->id == data_id::read_all);
  CHECK(d->ca1());
  CHECK(!d->ca0());

  const std::uint8_t unknown[] = {control_field(std::uint8_t{0x4})};
  d = decode_response(enc.respond(unknown, 0).view());
  CHECK(d->id == data_id::read_all);
  CHECK(!d->ca0());
  CHECK(!d->ca1());

  std::uint8_t eeprom[3] = {};
  (void)encode_request(data_id::eeprom_read, 3, 0, eeprom);
  eeprom[2] ^= 0x01;  // bad CRC
  CHECK(decode_response(enc.respond(eeprom, 0).view())->id == data_id::read_all);
  CHECK(decode_response(enc.respond(byte_view(eeprom, 2), 0).view())->id == data_id::read_all);
}

TEST_CASE("EEPROM: pages, page select at 127, busy 18 ms, closed addresses, page 7") {
  ts::emulator enc;
  master m{enc};
  // write then read on page 0
  auto w = m.ask(data_id::eeprom_write, 10, 0x42);
  REQUIRE(w.is_complete());
  CHECK(!w->busy);
  // still busy 1 ms later: busy, EDF 00, and a write is not performed
  auto b = m.ask(data_id::eeprom_write, 11, 0x43, 1000);
  REQUIRE(b.is_complete());
  CHECK(b->busy);
  CHECK(b->edf == 0);
  CHECK(enc.eeprom(0, 11) == 0);
  auto rd = m.ask(data_id::eeprom_read, 10, 0, 1000);
  CHECK(rd->busy);
  rd = m.ask(data_id::eeprom_read, 10, 0, 18000);
  REQUIRE(rd.is_complete());
  CHECK(!rd->busy);
  CHECK(rd->edf == 0);  // written, but readable only once the page is specified again (§10)
  CHECK(enc.eeprom(0, 10) == 0x42);
  CHECK(m.ask(data_id::eeprom_write, 127, 0, 100).is_complete());
  rd = m.ask(data_id::eeprom_read, 10, 0, 18000);
  REQUIRE(rd.is_complete());
  CHECK(rd->edf == 0x42);
  // page change to 3, busy after it, data separate per page
  CHECK(m.ask(data_id::eeprom_write, 127, 3, 18000).is_complete());
  CHECK(enc.page() == 3);
  CHECK(m.ask(data_id::eeprom_read, 10, 0, 100)->busy);
  CHECK(m.ask(data_id::eeprom_read, 10, 0, 18000)->edf == 0);
  CHECK(m.ask(data_id::eeprom_read, 127, 0, 100)->edf == 3);  // reading 127: current page
  CHECK(m.ask(data_id::eeprom_write, 126, 0x99, 100).is_complete());
  CHECK(enc.eeprom(3, 126) == 0x99);
  CHECK(enc.eeprom(0, 10) == 0x42);
  // invalid page number: ID3 data (the master sees a CF mismatch)
  CHECK(m.ask(data_id::eeprom_write, 127, 6, 18000).error() == errc::tformat_cf_mismatch);
  CHECK(enc.page() == 3);
  // page 7: over-heat threshold (r/w), temperature (read only), others closed
  CHECK(m.ask(data_id::eeprom_write, 127, 7, 18000).is_complete());
  CHECK(m.ask(data_id::eeprom_read, 4, 0, 18000)->edf == 0xDA);
  enc.set_temperature(-5);
  CHECK(ts::decode_temperature(m.ask(data_id::eeprom_read, 5, 0, 100)->edf) == -5);
  CHECK(m.ask(data_id::eeprom_write, 5, 1, 100).error() == errc::tformat_cf_mismatch);
  CHECK(m.ask(data_id::eeprom_read, 6, 0, 100).error() == errc::tformat_cf_mismatch);
  CHECK(m.ask(data_id::eeprom_write, 4, ts::encode_overheat_threshold(50).value(), 100)
            .is_complete());
  CHECK(enc.overheat_threshold() == 178);
  CHECK(m.ask(data_id::eeprom_read, 4, 0, 18000)->edf == 0xDA);  // not yet: the page as loaded
  CHECK(m.ask(data_id::eeprom_write, 127, 7, 100).is_complete());
  CHECK(m.ask(data_id::eeprom_read, 4, 0, 18000)->edf == 178);
}

TEST_CASE("over-heat latches above the threshold and clears only by reset once cool") {
  ts::emulator enc;
  master m{enc};
  enc.set_temperature(91);
  CHECK(has_alarm(enc.almc(), almc_bit::oh));
  enc.set_temperature(40);
  CHECK(has_alarm(enc.almc(), almc_bit::oh));  // latched
  auto r = m.ask(data_id::read_abs);
  CHECK(r->ea1());
  for (int i = 0; i < 10; ++i) {
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
  }
  CHECK(!has_alarm(enc.almc(), almc_bit::oh));
  CHECK(!m.ask(data_id::read_abs)->ea1());
}

TEST_CASE("alarms: latched flags stay until reset, non-latched follow their condition") {
  ts::emulator enc;
  master m{enc};
  for (almc_bit a : all_alarms) {
    enc.set_condition(a, true);
  }
  CHECK(enc.almc() == 0xFF);
  for (almc_bit a : all_alarms) {
    enc.set_condition(a, false);
  }
  // FS and BA cleared with their condition; CE latched, as the shaft is still (case II)
  const std::uint8_t held = 0x7D;  // OS, CE, OF, OH, ME, BE (spec §6.5)
  CHECK(enc.almc() == held);
  auto all = m.ask(data_id::read_all);
  REQUIRE(all.is_complete());
  CHECK(all->almc == held);
  CHECK(all->ea0());
  CHECK(all->ea1());
  // a latched alarm whose condition persists survives the reset
  enc.set_condition(almc_bit::be, true);
  for (int i = 0; i < 10; ++i) {
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
  }
  CHECK(enc.almc() == static_cast<std::uint8_t>(almc_bit::be));
}

TEST_CASE("counting error: non-latched at 100 rpm or more (case I), latched below (case II)") {
  // spec §6.5, CE: "I (Non-latched) When the shaft ... is rotated at 100 min^-1 or more ... The
  // flag is automatically released at every 45°"; "II (Latched during main power-on) When the
  // shaft ... is rotated at less than 100 min^-1"
  ts::emulator enc;
  master m{enc};
  const auto ce = static_cast<std::uint8_t>(almc_bit::ce);
  enc.set_speed_rpm(3000);  // case I
  enc.set_condition(almc_bit::ce, true);
  CHECK(enc.almc() == ce);
  CHECK(m.ask(data_id::read_abs)->ea0());
  enc.set_condition(almc_bit::ce, false);  // the next 45° check finds the deviation gone
  CHECK(enc.almc() == 0);
  CHECK(!m.ask(data_id::read_abs)->ea0());
  CHECK(m.ask(data_id::read_all)->almc == 0);
  enc.set_speed_rpm(100);  // 100 min^-1 is still case I
  enc.set_condition(almc_bit::ce, true);
  enc.set_condition(almc_bit::ce, false);
  CHECK(enc.almc() == 0);

  enc.set_speed_rpm(99);  // case II: latched until a reset
  enc.set_condition(almc_bit::ce, true);
  enc.set_condition(almc_bit::ce, false);
  CHECK(enc.almc() == ce);
  CHECK(m.ask(data_id::read_abs)->ea0());
  enc.set_speed_rpm(0);  // resets are sent with the shaft still (spec §10)
  for (int i = 0; i < 10; ++i) {
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
  }
  CHECK(enc.almc() == 0);

  // raised at speed, still present when the shaft slows below 100 min^-1: now case II
  enc.set_speed_rpm(500);
  enc.set_condition(almc_bit::ce, true);
  enc.set_speed_rpm(50);
  enc.set_condition(almc_bit::ce, false);
  CHECK(enc.almc() == ce);
  // a reset while the error is still present leaves it latched
  enc.set_speed_rpm(0);
  enc.set_condition(almc_bit::ce, true);
  for (int i = 0; i < 10; ++i) {
    (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  }
  enc.set_condition(almc_bit::ce, false);
  CHECK(enc.almc() == ce);
  // once the condition has gone, a reset at standstill releases it
  for (int i = 0; i < 10; ++i) {
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
  }
  CHECK(enc.almc() == 0);
}

TEST_CASE("counting error: a reverse speed counts by its magnitude") {
  // spec §6.5 gives the cases by speed, not direction: -150 min^-1 is case I, -50 case II
  ts::emulator enc;
  const auto ce = static_cast<std::uint8_t>(almc_bit::ce);
  enc.set_speed_rpm(-150);  // case I: released with its condition
  enc.set_condition(almc_bit::ce, true);
  enc.set_condition(almc_bit::ce, false);
  CHECK(enc.almc() == 0);
  enc.set_speed_rpm(-50);  // case II: latched
  enc.set_condition(almc_bit::ce, true);
  enc.set_condition(almc_bit::ce, false);
  CHECK(enc.almc() == ce);
  CHECK(!ts::info(almc_bit::ce).latched_at(-150));
  CHECK(!ts::info(almc_bit::ce).latched_at(-100));
  CHECK(ts::info(almc_bit::ce).latched_at(-99));
  CHECK(ts::info(almc_bit::ce).latched_at(-50));
  CHECK(!ts::info(almc_bit::ce).latched_at(INT32_MIN));  // no overflow in the magnitude
  CHECK(ts::speed_magnitude(-50) == 50U);
  CHECK(ts::speed_magnitude(INT32_MIN) == 0x80000000U);
}

TEST_CASE("resets count only with the shaft still (spec §10: \"at stationary of the shaft\")") {
  // The spec does not say what the encoder does with a reset sent while the shaft turns; the
  // emulator does not count it (ts5700n8500_emulator.hpp), in either direction.
  for (const std::int32_t rpm : {200, 1, -1, -200}) {
    CAPTURE(rpm);
    ts::emulator enc;
    master m{enc};
    enc.set_position(5000, 9);
    enc.set_condition(almc_bit::os, true);
    enc.set_condition(almc_bit::os, false);
    enc.set_speed_rpm(rpm);
    for (int i = 0; i < 10; ++i) {
      CHECK(m.ask(data_id::reset_errors, 0, 0, 50).is_complete());  // still answered
    }
    CHECK(has_alarm(enc.almc(), almc_bit::os));
    for (int i = 0; i < 10; ++i) {
      (void)m.ask(data_id::reset_single_turn, 0, 0, 50);
    }
    CHECK(enc.abs() == 5000);
    for (int i = 0; i < 10; ++i) {
      (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
    }
    CHECK(enc.abm() == 9);
    // nine requests while turning, the shaft stops, one more: the count restarted at the stop
    for (int i = 0; i < 9; ++i) {
      (void)m.ask(data_id::reset_errors, 0, 0, 50);
    }
    enc.set_speed_rpm(0);
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
    CHECK(has_alarm(enc.almc(), almc_bit::os));
    for (int i = 0; i < 9; ++i) {
      (void)m.ask(data_id::reset_errors, 0, 0, 50);
    }
    CHECK(enc.almc() == 0);
  }
}

TEST_CASE("resets act on the 10th request of the same ID, at least 40 us apart") {
  ts::emulator enc;
  master m{enc};
  enc.set_position(5000, 9);
  for (int i = 0; i < 9; ++i) {
    CHECK(m.ask(data_id::reset_single_turn, 0, 0, 50)->abs == 5000);
  }
  // a request 10 us after the previous one does not count
  CHECK(m.ask(data_id::reset_single_turn, 0, 0, 10)->abs == 5000);
  CHECK(enc.abs() == 5000);
  // the 10th counted request: replies with the data of the moment it was received; zero after
  CHECK(m.ask(data_id::reset_single_turn, 0, 0, 50)->abs == 5000);
  CHECK(enc.abs() == 0);
  enc.set_position(5100, 9);
  CHECK(m.ask(data_id::read_abs, 0, 0, 20000)->abs == 100);
  // an interruption restarts the count
  for (int i = 0; i < 5; ++i) {
    (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  }
  (void)m.ask(data_id::read_abm);
  for (int i = 0; i < 9; ++i) {
    (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  }
  CHECK(enc.abm() == 9);
  (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  CHECK(enc.abm() == 0);
}

TEST_CASE("rotation wraps turns and latches counter overflow") {
  ts::emulator enc;
  enc.set_position(0x1FFFF, 0xFFFF);
  enc.rotate(1);
  CHECK(enc.abs() == 0);
  CHECK(enc.abm() == 0);
  CHECK(has_alarm(enc.almc(), almc_bit::of));
  enc.rotate(-1);
  CHECK(enc.abs() == 0x1FFFF);
  CHECK(enc.abm() == 0xFFFF);
  enc.rotate(3 * 131072 + 5);  // 0x1FFFF + 3 turns + 5 = 4 turns + 4 counts
  CHECK(enc.abm() == 3);       // 0xFFFF + 4 wraps to 3
  CHECK(enc.abs() == 4);
}

TEST_CASE("TS5700N8500: plans executed against the model") {
  ts::emulator enc;
  std::uint32_t now = 0;
  enc.set_position(777, 3);
  auto run = [&](const auto& plan) {
    std::vector<response> out;
    for (const auto& step : plan) {
      const ts::reply rep = enc.respond(step.view(), now);
      const auto d = decode_response_for(step.view(), rep.view());
      REQUIRE(d.is_complete());
      if (step.verify) {
        CHECK(d->edf == step.expected_edf);
      }
      out.push_back(d.value());
      now += step.wait_after_us;
    }
    return out;
  };
  const auto zero = ts::reset_plan(data_id::reset_single_turn);
  REQUIRE(zero.ok());
  CHECK(zero->size == 10);
  CHECK(zero->steps[0].wait_after_us == 40);
  CHECK(zero->steps[9].wait_after_us == 18000);
  run(zero.value());
  CHECK(enc.abs() == 0);
  CHECK(ts::reset_plan(data_id::read_abs).error() == errc::invalid_argument);

  // write and verify, step by step: page 2 specified, written, specified again, read back
  const auto wv = ts::write_verify_plan(2, 100, 0xC3);
  REQUIRE(wv.ok());
  REQUIRE(wv->size == 4);
  const auto responses = run(wv.value());
  CHECK(enc.page() == 2);
  CHECK(responses[0].address == 127);
  CHECK(responses[1].address == 100);
  CHECK(responses[1].edf == 0xC3);
  CHECK(!responses[1].busy);  // 18 ms after the page change
  CHECK(responses[2].address == 127);
  CHECK(!responses[2].busy);  // 18 ms after the write
  CHECK(responses[3].edf == 0xC3);
  CHECK(!responses[3].busy);
  CHECK(enc.eeprom(2, 100) == 0xC3);
  // without the second page step, a read does not see the write: the plan needs that step
  const auto other = ts::write_verify_plan(2, 100, 0x3C);
  REQUIRE(other.ok());
  (void)enc.respond(other->steps[1].view(), now);
  now += ts::eeprom_write_us;
  const auto stale =
      decode_response_for(other->steps[3].view(), enc.respond(other->steps[3].view(), now).view());
  REQUIRE(stale.is_complete());
  CHECK(stale->edf == 0xC3);
  // page 7: the over-heat threshold only
  const auto oh = ts::write_verify_plan(7, 4, 0xB2);
  REQUIRE(oh.ok());
  CHECK(run(oh.value()).back().edf == 0xB2);
  CHECK(ts::writable(7, 4));
  for (const int closed : {0, 3, 5, 10, 126}) {
    CAPTURE(closed);
    const auto address = static_cast<std::uint8_t>(closed);
    CHECK(!ts::writable(7, address));
    CHECK(ts::write_verify_plan(7, address, 1).error() == errc::out_of_range);
  }
  CHECK(ts::write_verify_plan(6, 1, 1).error() == errc::out_of_range);
  CHECK(ts::write_verify_plan(8, 1, 1).error() == errc::out_of_range);
  CHECK(ts::write_verify_plan(0, 127, 1).error() == errc::out_of_range);
  CHECK(ts::page_change_plan(7).value().steps[0].request[1] == 127);
  CHECK(ts::page_change_plan(8).error() == errc::out_of_range);
}

TEST_CASE("TS5700N8500: over-heat threshold, temperature, alarms, timing") {
  CHECK(ts::encode_overheat_threshold(90).value() == 0xDA);  // spec §7.2.1
  CHECK(ts::encode_overheat_threshold(0).error() == errc::out_of_range);
  CHECK(ts::encode_overheat_threshold(128).error() == errc::out_of_range);
  CHECK(ts::decode_overheat_threshold(0xDA).enabled);
  CHECK(ts::decode_overheat_threshold(0xDA).celsius == 90);
  CHECK(!ts::decode_overheat_threshold(0x00).enabled);
  CHECK(!ts::decode_overheat_threshold(0x5A).enabled);  // "X" bits, MSB clear: off
  CHECK(ts::decode_temperature(0x3C) == 60);            // spec §7.3.1
  CHECK(ts::decode_temperature(0x01) == 1);             // misprinted as -1 in the spec table
  CHECK(ts::decode_temperature(0xFF) == -1);
  CHECK(ts::decode_temperature(0x80) == -128);
  CHECK(ts::decode_temperature(0x7F) == 127);
  // spec §6.5, flag by flag: held until a reset when raised below 100 min^-1 and at 100 or
  // more (OS, OF, OH, BE "Latched", ME "Latched during main power-on", CE case II / case I,
  // FS and BA "Non-latched")
  struct row {
    almc_bit flag;
    bool latched_still;
    bool latched_at_speed;
  };
  const row spec[] = {
      {almc_bit::os, true, true}, {almc_bit::fs, false, false}, {almc_bit::ce, true, false},
      {almc_bit::of, true, true}, {almc_bit::oh, true, true},   {almc_bit::me, true, true},
      {almc_bit::be, true, true}, {almc_bit::ba, false, false},
  };
  for (const row& r : spec) {
    CAPTURE(symbol(r.flag));
    CHECK(std::string(ts::info(r.flag).symbol) == symbol(r.flag));
    CHECK(ts::info(r.flag).latched_at(0) == r.latched_still);
    CHECK(ts::info(r.flag).latched_at(99) == r.latched_still);
    CHECK(ts::info(r.flag).latched_at(100) == r.latched_at_speed);
    CHECK(ts::info(r.flag).latched_at(6000) == r.latched_at_speed);
  }
  // spec §6.5: OS, OF, OH, BE "Latched", ME "Latched during main power-on", FS, BA
  // "Non-latched"; CE case I (100 min^-1 or more) non-latched, case II (below) latched
  CHECK(ts::latched_alarms == 0x79);
  CHECK(ts::speed_latched_alarms == static_cast<std::uint8_t>(almc_bit::ce));
  CHECK(ts::alarm_mask(ts::latch_rule::none) == 0x82);
  CHECK(ts::info(almc_bit::ce).latch == ts::latch_rule::by_speed);
  CHECK(!ts::info(almc_bit::ce).latched_at(ts::counting_error_case_i_rpm));
  CHECK(ts::info(almc_bit::ce).latched_at(ts::counting_error_case_i_rpm - 1U));
  // docs/tformat.md §7 (timing): ID0 28 us, ID3 48 us, IDD 28 us, ID6 32 us at 2.5 Mbps
  CHECK(ts::transaction_ns(data_id::read_abs) == 28000);
  CHECK(ts::transaction_ns(data_id::read_all) == 48000);
  CHECK(ts::transaction_ns(data_id::eeprom_read) == 28000);
  CHECK(ts::transaction_ns(data_id::eeprom_write) == 32000);
  CHECK(ts::field_ns(ts::standard_bit_rate) == 4000);
  CHECK(ts::field_ns(ts::fast_bit_rate) == 2000);
  CHECK(ts::transaction_ns(data_id::read_all, ts::fast_bit_rate) == 24000);
}

TEST_CASE("EEPROM outside the user pages reads 0; an over-heat threshold without bit 7 is off") {
  ts::emulator enc;
  master m{enc};
  CHECK(m.ask(data_id::eeprom_write, 10, 0x42).is_complete());
  CHECK(enc.eeprom(0, 10) == 0x42);
  CHECK(enc.eeprom(6, 10) == 0);   // page 6 holds nothing
  CHECK(enc.eeprom(0, 127) == 0);  // 127 is the page select, no cell
  // page 7, threshold 0x7F: bit 7 clear, the check is off however hot the encoder is
  CHECK(m.ask(data_id::eeprom_write, 127, 7, 18000).is_complete());
  CHECK(m.ask(data_id::eeprom_write, 4, 0x7F, 18000).is_complete());
  CHECK(enc.overheat_threshold() == 0x7F);
  enc.set_temperature(120);
  CHECK(!has_alarm(enc.almc(), almc_bit::oh));
}

TEST_CASE("emulator resolution: the readings keep their bits, up to 32 (no 32-bit shift)") {
  ts::emulator factory;
  factory.set_position(0xFFFFFFFFU, 0xFFFFFFFFU);
  CHECK(factory.abs() == 0x1FFFFU);  // 17 bits
  CHECK(factory.abm() == 0xFFFFU);   // 16 bits
  ts::emulator_config cfg;
  cfg.res = resolution{32, 32};  // beyond the 24 bits a T-format field holds: the emulator's own
  ts::emulator wide(cfg);
  wide.set_position(0xFFFFFFFFU, 0xFFFFFFFFU);
  CHECK(wide.abs() == 0xFFFFFFFFU);
  CHECK(wide.abm() == 0xFFFFFFFFU);
}

TEST_CASE("rotation within the 16-bit turn range raises no counter overflow") {
  // spec §6.5: OF when the multi-turn counter overflows; turn 0 is in its range (0~65,535)
  ts::emulator enc;
  enc.rotate(5);
  CHECK(enc.abm() == 0);
  CHECK(!has_alarm(enc.almc(), almc_bit::of));
  enc.set_position(0, 1);
  enc.rotate(-131072);  // back one whole turn, to turn 0
  CHECK(enc.abm() == 0);
  CHECK(enc.abs() == 0);
  CHECK(!has_alarm(enc.almc(), almc_bit::of));
  enc.rotate(-1);  // below turn 0: wraps, OF latches
  CHECK(enc.abm() == 0xFFFF);
  CHECK(has_alarm(enc.almc(), almc_bit::of));
}

TEST_CASE("EEPROM: eeprom() shows pages 0 to 5 at addresses 0 to 126 only; address 0 reads back") {
  ts::emulator enc;
  master m{enc};
  CHECK(m.ask(data_id::eeprom_write, 127, 1, 100).is_complete());
  CHECK(m.ask(data_id::eeprom_write, 0, 0x11, 18000).is_complete());  // page 1, address 0
  CHECK(m.ask(data_id::eeprom_write, 127, 5, 18000).is_complete());
  CHECK(m.ask(data_id::eeprom_write, 126, 0x55, 18000).is_complete());  // page 5, address 126
  CHECK(m.ask(data_id::eeprom_write, 127, 0, 18000).is_complete());
  CHECK(m.ask(data_id::eeprom_write, 0, 0x42, 18000).is_complete());  // page 0, address 0
  CHECK(m.ask(data_id::eeprom_write, 10, 0x24, 18000).is_complete());
  CHECK(m.ask(data_id::eeprom_write, 127, 0, 18000).is_complete());  // page 0 specified again
  // the page as specified again reads back from its first address on (spec §10)
  CHECK(m.ask(data_id::eeprom_read, 0, 0, 18000)->edf == 0x42);
  CHECK(m.ask(data_id::eeprom_read, 10, 0, 100)->edf == 0x24);
  CHECK(enc.eeprom(1, 0) == 0x11);
  CHECK(enc.eeprom(5, 126) == 0x55);
  CHECK(enc.eeprom(0, 127) == 0);  // the page select, not page 1's first byte
  CHECK(enc.eeprom(6, 0) == 0);    // no page 6 (spec §6.1.1: pages 0~5)
  CHECK(enc.eeprom(6, 10) == 0);
  CHECK(enc.eeprom(7, 4) == 0);  // page 7 is not a user page
}

TEST_CASE("resets: any other request restarts the count of 10 (spec §10: \"in one sequence\")") {
  // Each case: five reset-errors requests, then the request that breaks the sequence, then nine
  // more reset-errors requests: the latched over-speed flag stays; a tenth releases it.
  enum class breaker { eeprom_read, eeprom_write, abnormal, turning, too_soon_after_read };
  for (const breaker b : {breaker::eeprom_read, breaker::eeprom_write, breaker::abnormal,
                          breaker::turning, breaker::too_soon_after_read}) {
    CAPTURE(static_cast<int>(b));
    ts::emulator enc;
    master m{enc};
    enc.set_condition(almc_bit::os, true);
    enc.set_condition(almc_bit::os, false);
    for (int i = 0; i < 5; ++i) {
      (void)m.ask(data_id::reset_errors, 0, 0, 50);
    }
    switch (b) {
      case breaker::eeprom_read: (void)m.ask(data_id::eeprom_read, 1, 0, 50); break;
      case breaker::eeprom_write: (void)m.ask(data_id::eeprom_write, 1, 0x33, 50); break;
      case breaker::abnormal: {
        const std::uint8_t bad_parity[] = {0x82};
        m.now += 50;
        CHECK(enc.respond(bad_parity, m.now).size == 11);
        break;
      }
      case breaker::turning:  // one request while the shaft turns, then it stops
        enc.set_speed_rpm(200);
        (void)m.ask(data_id::reset_errors, 0, 0, 50);
        enc.set_speed_rpm(0);
        break;
      case breaker::too_soon_after_read:
        // a read 10 us after the fifth reset request: the new sequence's first request, 20 us
        // after the old sequence's last one, has no previous request of its own sequence to
        // keep 40 us from, and counts
        (void)m.ask(data_id::read_abs, 0, 0, 10);
        (void)m.ask(data_id::reset_errors, 0, 0, 10);
        for (int i = 0; i < 8; ++i) {
          (void)m.ask(data_id::reset_errors, 0, 0, 50);
        }
        CHECK(has_alarm(enc.almc(), almc_bit::os));
        (void)m.ask(data_id::reset_errors, 0, 0, 50);  // the tenth of the new sequence
        CHECK(!has_alarm(enc.almc(), almc_bit::os));
        continue;
    }
    for (int i = 0; i < 9; ++i) {
      (void)m.ask(data_id::reset_errors, 0, 0, 50);
    }
    CHECK(has_alarm(enc.almc(), almc_bit::os));
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
    CHECK(!has_alarm(enc.almc(), almc_bit::os));
  }
}

TEST_CASE("resets: another reset ID restarts the count; after a reset, the next takes 10 again") {
  ts::emulator enc;
  master m{enc};
  enc.set_position(5000, 9);
  for (int i = 0; i < 5; ++i) {
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
  }
  for (int i = 0; i < 9; ++i) {
    (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  }
  CHECK(enc.abm() == 9);  // nine of IDC: not yet
  (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  CHECK(enc.abm() == 0);
  // a second sequence of the same ID counts from 0 again
  enc.set_position(5000, 9);
  (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  CHECK(enc.abm() == 9);  // one request does not reset
  for (int i = 0; i < 8; ++i) {
    (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  }
  CHECK(enc.abm() == 9);
  (void)m.ask(data_id::reset_multi_turn, 0, 0, 50);
  CHECK(enc.abm() == 0);
}

TEST_CASE("a single-turn reset writes EEPROM: busy 18 ms after the tenth request (spec §10)") {
  ts::emulator enc;
  master m{enc};
  enc.set_position(5000, 9);
  for (int i = 0; i < 10; ++i) {
    (void)m.ask(data_id::reset_single_turn, 0, 0, 50);
  }
  CHECK(enc.abs() == 0);
  CHECK(enc.busy(m.now));
  CHECK(m.ask(data_id::eeprom_read, 1, 0, 100)->busy);
  CHECK(m.ask(data_id::eeprom_read, 1, 0, ts::eeprom_write_us)->busy == false);
  // the other resets write nothing: not busy after them
  for (int i = 0; i < 10; ++i) {
    (void)m.ask(data_id::reset_errors, 0, 0, 50);
  }
  CHECK(!enc.busy(m.now));
}

TEST_CASE("over-heat: the threshold temperature itself is not over it; a new threshold acts") {
  // spec §6.5: OH when the temperature "exceeds" the detection temperature (§7.2.1: 0xDA, 90 °C)
  ts::emulator enc;
  enc.set_temperature(90);
  CHECK(!has_alarm(enc.almc(), almc_bit::oh));
  enc.set_temperature(91);
  CHECK(has_alarm(enc.almc(), almc_bit::oh));
  // 60 °C, below the factory 90 °C: no over-heat until a 50 °C threshold is written
  ts::emulator cool;
  master c{cool};
  cool.set_temperature(60);
  CHECK(!has_alarm(cool.almc(), almc_bit::oh));
  CHECK(c.ask(data_id::eeprom_write, 127, 7, 100).is_complete());
  CHECK(c.ask(data_id::eeprom_write, 4, ts::encode_overheat_threshold(50).value(), 18000)
            .is_complete());
  CHECK(has_alarm(cool.almc(), almc_bit::oh));
}

TEST_CASE("a new emulator: 25 °C, at 0, not busy; a static one is all zeros, 932 bytes") {
  // The header's firmware contract: a default-constructed model is all zeros (a `static` one
  // lands in .bss) and the emulator is 932 bytes (no pointer or wider member: the same on
  // 64-bit hosts as on the Cortex-M4). Its substrate starts at 25 °C (the header's
  // default_celsius), the temperature a demo or bench reads before it sets one.
  static ts::emulator blank;
  const auto* bytes = reinterpret_cast<const unsigned char*>(&blank);
  std::size_t nonzero = 0;
  for (std::size_t i = 0; i < sizeof blank; ++i) {
    nonzero += bytes[i] != 0U ? 1U : 0U;
  }
  CHECK(nonzero == 0);
  CHECK(sizeof(ts::emulator) == 932);
  ts::emulator enc;
  master m{enc};
  CHECK(enc.abs() == 0);
  CHECK(enc.abm() == 0);
  CHECK(enc.almc() == 0);
  CHECK(!enc.busy(0));
  CHECK(m.ask(data_id::eeprom_write, 127, 7, 100).is_complete());
  CHECK(ts::decode_temperature(m.ask(data_id::eeprom_read, 5, 0, 18000)->edf) == 25);
}

TEST_CASE("a reading too wide for T-format's 24-bit fields gets no reply, not a partial one") {
  // resolution{32, 32} is the emulator's own (the fields hold 24 bits): a position it cannot
  // encode leaves the reply empty, as the encoder staying silent (reply: size 0)
  ts::emulator_config cfg;
  cfg.res = resolution{32, 32};
  ts::emulator wide(cfg);
  wide.set_position(0x01000000U, 0);
  const std::uint8_t id0[] = {0x02};
  CHECK(wide.respond(id0, 0).size == 0);
  wide.set_position(0x00FFFFFFU, 0);
  CHECK(wide.respond(id0, 100).size == 6);
}
