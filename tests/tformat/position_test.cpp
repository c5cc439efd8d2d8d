// T-format position and link health against the TS5700N8500 emulator: ID3 across the
// multi-turn counter's wrap and ID0 across the single-turn rollover on random trajectories,
// injected CRC errors, missing and corrupted responses, alarms; the response deadlines.
#include "motionbus/tformat/position.hpp"

#include <doctest/doctest.h>

#include <cstdint>

#include "../support/prng.hpp"
#include "motionbus/devices/ts5700n8500.hpp"
#include "motionbus/devices/ts5700n8500_emulator.hpp"
#include "motionbus/tformat/codec.hpp"

using namespace motionbus;
using namespace motionbus::tformat;
namespace ts = motionbus::devices::ts5700n8500;

namespace {

enum class fault { none, crc, silent, cut, parity };

// One transaction: the request for `id` to the emulator at `now_us`, the reply damaged as
// `f` says, decoded as a master does with the request (decode_response_frame: the bytes up to
// the line's idle, then checked against the request).
decode_result<response> transact(ts::emulator& enc, data_id id, std::uint32_t now_us, fault f) {
  std::uint8_t req[max_request_size] = {};
  std::size_t n = encode_request(id, mutable_byte_view(req, sizeof req)).value();
  if (f == fault::parity) {
    req[0] = static_cast<std::uint8_t>(req[0] ^ 0x80U);  // cc4 wrong: ID3 data with ca0
  }
  ts::reply rep = enc.respond(byte_view(req, n), now_us);
  std::size_t size = rep.size;
  if (f == fault::crc && size > 0U) {
    rep.bytes[size - 1U] = static_cast<std::uint8_t>(rep.bytes[size - 1U] ^ 0x5AU);
  } else if (f == fault::silent) {
    size = 0;  // no response by the deadline
  } else if (f == fault::cut) {
    size /= 2U;  // the response stops short of its deadline
  }
  std::uint8_t sent[max_request_size] = {};
  n = encode_request(id, mutable_byte_view(sent, sizeof sent)).value();
  return check_response(byte_view(sent, n), decode_response_frame(byte_view(rep.bytes, size)));
}

}  // namespace

TEST_CASE("ID3 on random trajectories: the position through the counter's wrap 65535 -> 0") {
  // 6000 min^-1 read every 50 µs: 6000 / 60 x 2^17 x 50e-6 = 655 counts a read at most.
  const std::uint64_t max_step = 700;
  int wraps = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    testutil::splitmix64 rng(seed);
    ts::emulator enc;
    // within two turns of the counter's end, or of its start
    const bool top = (seed & 1U) != 0U;
    enc.set_position(static_cast<std::uint32_t>(rng.below(ts::counts_per_turn)), top ? 65534U : 1U);
    position_tracker t(position_config_for(ts::resolution, data_id::read_all, max_step));
    link_health h;
    std::int64_t truth = 0;  // the simulated axis, relative to the first reading
    std::int64_t speed = 0;
    std::uint32_t now = 0;
    std::uint32_t last_abm = enc.abm();
    std::int64_t first = -1;
    for (int i = 0; i < 4000; ++i, now += 50) {
      const auto r = transact(enc, data_id::read_all, now, fault::none);
      REQUIRE(r.is_complete());
      const position_status st = update_position(t, r);
      (void)record(h, r);
      if (first < 0) {
        REQUIRE(st == position_status::seeded);
        first = t.counts();
      } else {
        REQUIRE(st == position_status::accepted);
      }
      REQUIRE(t.counts() - first == truth);
      wraps += (last_abm == 65535U && enc.abm() == 0U) || (last_abm == 0U && enc.abm() == 65535U);
      last_abm = enc.abm();
      speed += static_cast<std::int64_t>(rng.below(41)) - 20;
      const std::int64_t cap = static_cast<std::int64_t>(max_step) - 45;
      speed = speed > cap ? cap : (speed < -cap ? -cap : speed);
      // Towards the wrap for the first 1500 reads (at least 327 counts each: more than the two
      // turns to go), then wherever the speed goes.
      const std::int64_t toward = top ? 1 : -1;
      const std::int64_t step =
          i < 1500 ? toward * (cap / 2 + (speed < 0 ? -speed : speed) / 2) : speed;
      enc.rotate(step);
      truth += step;
    }
    CHECK(h.counters().frames == 4000);
    CHECK(h.counters().good == 4000);
    CHECK(h.state() == link_state::up);
  }
  CHECK(wraps >= 8);  // every trajectory crossed the counter's wrap
}

TEST_CASE("ID0 (single-turn only): the rollover unwrapped, an impossible jump reported") {
  testutil::splitmix64 rng(27);
  ts::emulator enc;
  position_tracker t(position_config_for(ts::resolution, data_id::read_abs, 3000));
  std::int64_t truth = 0;
  std::int64_t first = 0;
  int rollovers = 0;
  std::uint32_t now = 0;
  REQUIRE(update_position(t, transact(enc, data_id::read_abs, now, fault::none)) ==
          position_status::seeded);
  first = t.counts();
  for (int i = 0; i < 3000; ++i, now += 30) {
    const std::int64_t step = static_cast<std::int64_t>(rng.below(3501)) - 500;  // mostly up
    const std::uint32_t before = enc.abs();
    enc.rotate(step);
    truth += step;
    rollovers += (step > 0 && enc.abs() < before) || (step < 0 && enc.abs() > before);
    if (i % 500 == 250) {
      // an impossible jump: half a turn in one read (the encoder glitched or was reset)
      ts::emulator glitch;
      glitch.set_position((enc.abs() + ts::counts_per_turn / 2U) % ts::counts_per_turn, 0);
      const std::int64_t kept = t.counts();
      CHECK(update_position(t, transact(glitch, data_id::read_abs, now, fault::none)) ==
            position_status::implausible_step);
      CHECK(t.counts() == kept);
      continue;  // the axis went on meanwhile: the next reading covers two periods
    }
    REQUIRE(update_position(t, transact(enc, data_id::read_abs, now, fault::none)) ==
            position_status::accepted);
    REQUIRE(t.counts() - first == truth);
  }
  CHECK(rollovers > 20);
  CHECK(t.implausible_steps() == 6);
}

TEST_CASE("link health against the emulator: CRC errors, silence, cut frames, ca0 counted") {
  ts::emulator enc;
  enc.set_position(1000, 7);
  position_tracker t(position_config_for(ts::resolution, data_id::read_all, 2000));
  link_health h({3, 2});
  std::uint32_t now = 0;
  const auto step = [&](fault f) {
    enc.rotate(1500);  // the axis turns whatever the line does
    now += 50;
    const auto r = transact(enc, data_id::read_all, now, f);
    (void)update_position(t, r);
    return record(h, r);
  };
  CHECK(step(fault::none) == link_event::none);
  CHECK(step(fault::none) == link_event::restored);  // proven by two good frames
  const std::int64_t start = t.counts();
  CHECK(step(fault::crc) == link_event::none);
  CHECK(step(fault::silent) == link_event::none);
  CHECK(step(fault::none) == link_event::none);  // the run of failures broken
  CHECK(step(fault::cut) == link_event::none);
  CHECK(step(fault::parity) == link_event::none);
  CHECK(step(fault::crc) == link_event::lost);
  for (int i = 0; i < 5; ++i) {
    CHECK(step(fault::silent) == link_event::none);
  }
  CHECK(step(fault::none) == link_event::none);
  CHECK(step(fault::none) == link_event::restored);
  const link_counters& c = h.counters();
  CHECK(c.frames == 15);
  CHECK(c.good == 5);
  CHECK(c.crc_errors == 2);
  CHECK(c.timeouts == 7);  // 6 silent, 1 cut
  CHECK(c.invalid == 1);   // the communication alarm (ca0)
  CHECK(c.losses == 1);
  // 13 read periods of 1500 counts after `start`, 10 of them without a reading: the position
  // came through the outage (the plausible step widened by 2000 a missed period).
  CHECK(t.counts() - start == 13 * 1500);
}

TEST_CASE("alarms: a good frame with ea1 / ALMC set is counted, the link stays up") {
  ts::emulator enc;
  link_health h({2, 1});
  (void)record(h, transact(enc, data_id::read_all, 0, fault::none));
  CHECK(h.state() == link_state::up);
  enc.set_condition(almc_bit::ba, true);  // battery alarm: ea1 and ALMC bit 7
  CHECK(outcome_of(transact(enc, data_id::read_all, 100, fault::none)) == link_outcome::alarm);
  CHECK(outcome_of(transact(enc, data_id::read_abs, 200, fault::none)) == link_outcome::alarm);
  enc.set_condition(almc_bit::ba, false);
  enc.set_condition(almc_bit::fs, true);  // in ALMC only (not in SF)
  CHECK(outcome_of(transact(enc, data_id::read_all, 300, fault::none)) == link_outcome::alarm);
  CHECK(outcome_of(transact(enc, data_id::read_abs, 400, fault::none)) == link_outcome::ok);
  for (int i = 0; i < 5; ++i) {
    CHECK(record(h, transact(enc, data_id::read_all, 500U + 100U * static_cast<unsigned>(i),
                             fault::none)) == link_event::none);
  }
  CHECK(h.counters().alarms == 5);
  CHECK(h.state() == link_state::up);
}

TEST_CASE("responses without a position, and ca0 seen by decode_response alone") {
  ts::emulator enc;
  position_tracker t(position_config_for(ts::resolution, data_id::read_all));
  CHECK(update_position(t, transact(enc, data_id::read_enid, 0, fault::none)) ==
        position_status::no_reading);
  CHECK_FALSE(t.has_position());
  CHECK(t.periods() == 2);
  // ca0 set in a decoded ID3 frame (no check against the request): its data is invalid.
  const std::uint8_t bad_parity =
      static_cast<std::uint8_t>(control_field(data_id::read_all) ^ 0x80U);
  const ts::reply rep = enc.respond(byte_view(&bad_parity, 1), 100);
  const auto r = decode_response(rep.view());
  REQUIRE(r.is_complete());
  REQUIRE(r->ca0());
  CHECK(update_position(t, r) == position_status::no_reading);
  CHECK(outcome_of(r) == link_outcome::invalid);
  // ID1: the turn count alone
  enc.set_position(5, 65535);
  position_tracker turns(position_config_for(ts::resolution, data_id::read_abm, 2));
  CHECK(update_position(turns, transact(enc, data_id::read_abm, 200, fault::none)) ==
        position_status::seeded);
  enc.rotate(std::int64_t{2} << 17U);
  CHECK(update_position(turns, transact(enc, data_id::read_abm, 300, fault::none)) ==
        position_status::accepted);
  CHECK(turns.counts() == 65537);
  CHECK_FALSE(position_config_for({25, 16}, data_id::read_all).valid());
  CHECK(position_config_for({23, 16}, data_id::read_abs).range() == (std::uint64_t{1} << 23U));
}

TEST_CASE("response deadlines at 2.5 and 5 Mbps from the frame lengths") {
  CHECK(fields_ns(1, 2500000) == 4000);
  CHECK(fields_ns(1, 3000000) == 3334);  // rounded up
  CHECK(fields_ns(3, 0) == 0);
  CHECK(response_timeout_ns(data_id::read_abs, ts::standard_bit_rate) == 30000);
  CHECK(response_timeout_ns(data_id::read_all, ts::standard_bit_rate) == 50000);
  CHECK(response_timeout_ns(data_id::read_abs, ts::fast_bit_rate) == 18000);
  CHECK(response_timeout_ns(data_id::read_all, ts::fast_bit_rate) == 28000);
  CHECK(response_timeout_ns(data_id::eeprom_read, ts::standard_bit_rate, 0) == 16000);
  // from the request's start: the fields of both frames (the profile's transaction time) plus
  // the start allowance
  for (const data_id id :
       {data_id::read_abs, data_id::read_all, data_id::eeprom_read, data_id::eeprom_write}) {
    for (const std::uint32_t rate : {ts::standard_bit_rate, ts::fast_bit_rate}) {
      CHECK(transaction_timeout_ns(id, rate) == ts::transaction_ns(id, rate) + 6000U);
    }
  }
  CHECK(transaction_timeout_ns(data_id::read_all, ts::standard_bit_rate) == 54000);
}

TEST_CASE("ID1 polled: the turns alone, one count a turn; a run-time resolution") {
  volatile unsigned mt_bits = 16;  // not a constant: the configuration is made at run time
  const resolution res{17, static_cast<std::uint8_t>(mt_bits)};
  const auto c = position_config_for(res, data_id::read_abm, 3);
  CHECK(c.counts_per_turn == 1U);
  CHECK(c.turns == 65536U);
  CHECK(c.max_step == 3U);
  CHECK(position_config_for(res, data_id::read_all).range() == (std::uint64_t{1} << 33U));
}

TEST_CASE("position_config_for: more than 24 bits in either field is an invalid configuration") {
  CHECK(position_config_for(resolution{17, 16}, data_id::read_all).valid());
  CHECK_FALSE(position_config_for(resolution{25, 16}, data_id::read_all).valid());
  CHECK_FALSE(position_config_for(resolution{17, 25}, data_id::read_all).valid());
  CHECK_FALSE(position_config_for(resolution{17, 25}, data_id::read_abm).valid());
  CHECK(position_config_for(resolution{17, 25}, data_id::read_abs).valid());  // ABS alone
}

TEST_CASE("outcome_of: an EEPROM response carries no SF: no alarm is read from its fields") {
  response e;
  e.id = data_id::eeprom_read;
  e.sf = sf::ca0 | sf::ea1;  // not on the wire for this layout: ignored
  CHECK(outcome_of(decode_result<response>::complete(e, 4)) == link_outcome::ok);
  response a;
  a.id = data_id::read_abs;
  a.sf = sf::ca0;
  CHECK(outcome_of(decode_result<response>::complete(a, 6)) == link_outcome::invalid);
  a.sf = sf::ea1;
  CHECK(outcome_of(decode_result<response>::complete(a, 6)) == link_outcome::alarm);
}

TEST_CASE("position_config_for: 24 bits in either field is valid; max_step 0 by default") {
  const auto c = position_config_for(resolution{24, 24}, data_id::read_all);
  CHECK(c.valid());
  CHECK(c.counts_per_turn == (std::uint64_t{1} << 24U));
  CHECK(c.turns == (std::uint64_t{1} << 24U));
  CHECK(c.max_step == 0U);  // 0: the largest step unwrapping can tell (core/position.hpp)
  CHECK(position_config_for(resolution{24, 16}, data_id::read_abs).counts_per_turn ==
        (std::uint64_t{1} << 24U));
  CHECK(position_config_for(resolution{17, 24}, data_id::read_abm).turns ==
        (std::uint64_t{1} << 24U));
  CHECK(position_config_for(resolution{}, data_id::read_abm).max_step == 0U);
}

TEST_CASE("update_position: a response's fields outside its layout are not read") {
  // ID0 carries ABS alone, ID1 ABM alone: an ABM (or ABS) in the struct is no reading
  position_tracker abs_only(position_config_for(resolution{}, data_id::read_abs));
  response a;
  a.id = data_id::read_abs;
  a.abs = 100;
  a.abm = 7;
  CHECK(update_position(abs_only, decode_result<response>::complete(a, 6)) ==
        position_status::seeded);
  CHECK(abs_only.counts() == 100);
  position_tracker turns(position_config_for(resolution{}, data_id::read_abm));
  response m;
  m.id = data_id::read_abm;
  m.abs = 100;
  m.abm = 7;
  CHECK(update_position(turns, decode_result<response>::complete(m, 6)) == position_status::seeded);
  CHECK(turns.counts() == 7);
}
