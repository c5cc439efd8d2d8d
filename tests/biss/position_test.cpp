// BiSS-C position and link health: the ABSYS emulator (a single-turn rotary slave whose turn is
// SIP_CNT x 2^SIP_RES counts) across its rollover on random trajectories, a multi-turn slave
// across its counter's wrap, injected CRC errors, missing slaves and nE; the frame timing.
#include "motionbus/biss/position.hpp"

#include <doctest/doctest.h>

#include <cstdint>

#include "../support/prng.hpp"
#include "motionbus/biss/codec.hpp"
#include "motionbus/devices/absys.hpp"
#include "motionbus/devices/absys_emulator.hpp"

using namespace motionbus;
namespace bs = motionbus::biss;
namespace ab = motionbus::devices::absys;

namespace {

enum class fault { none, crc, silent };

// One frame of the emulator as a master captures it (line delay 2, Ack 1), damaged as `f`
// says, decoded, and the CDM handed back.
bs::frame_result<1> read(ab::emulator& enc, fault f) {
  std::uint32_t words[2] = {0xFFFFFFFFU, 0xFFFFFFFFU};  // an idle line: SL high
  if (f != fault::silent) {
    REQUIRE(enc.frame(words, 2, 1).ok());
  }
  if (f == fault::crc) {
    words[1] ^= 1U << 20U;  // one CRC bit (the CRC is bits 39..44 of the 45-bit frame)
  }
  // (a line delay of at most 16: a silent line is biss_no_ack within the 64 samples)
  const auto r = bs::decode_frame(words, 64, ab::layout, bs::decode_options{16, 256});
  enc.control(false);
  return r;
}

}  // namespace

TEST_CASE("ABSYS rotary on random trajectories: the rollover at 512 x 2^10 counts unwrapped") {
  const ab::emulator_config cfg{};  // 512 periods x 2^10: 524288 counts a turn
  const position_config pc =
      bs::position_config_for(ab::default_bp3(cfg.type, cfg.sip_count, cfg.sip_resolution), 20000);
  REQUIRE(pc.valid());
  CHECK(pc.counts_per_turn == 524288U);
  int rollovers = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    testutil::splitmix64 rng(seed);
    ab::emulator enc(cfg);
    const std::uint64_t turn = enc.pulses_per_revolution();
    std::int64_t truth = static_cast<std::int64_t>(rng.below(turn));
    enc.set_position(static_cast<std::uint32_t>(truth));
    position_tracker t(pc);
    link_health h;
    REQUIRE(bs::update_position(t, read(enc, fault::none)) == position_status::seeded);
    const std::int64_t first = t.counts() - truth;
    std::int64_t speed = 0;
    for (int i = 0; i < 3000; ++i) {
      speed += static_cast<std::int64_t>(rng.below(2001)) - 1000;
      speed = speed > 19000 ? 19000 : (speed < -19000 ? -19000 : speed);
      const std::int64_t before = truth;
      truth += speed;
      const auto wrap = [turn](std::int64_t p) {
        const auto m = static_cast<std::int64_t>(turn);
        return p >= 0 ? p / m : -((-p - 1) / m) - 1;
      };
      rollovers += wrap(truth) != wrap(before) ? 1 : 0;
      const auto sm = static_cast<std::int64_t>(turn);
      enc.set_position(static_cast<std::uint32_t>(((truth % sm) + sm) % sm));
      const auto r = read(enc, fault::none);
      REQUIRE(bs::update_position(t, r) == position_status::accepted);
      (void)bs::record(h, r);
      REQUIRE(t.counts() - first == truth);
    }
    CHECK(h.counters().good == 3000);
    CHECK(h.state() == link_state::up);
  }
  CHECK(rollovers > 20);
}

TEST_CASE("a multi-turn slave: the counter's wrap unwrapped, a jump reported") {
  // 12 multi-turn + 13 single-turn bits, nE only, CRC5 0x25 (docs/biss.md's example)
  constexpr bs::slave_layout layout{12, 13, 2, true, false, bs::crc_from_biss_notation(0x25)};
  position_tracker t(bs::position_config_for(layout, 3000));
  const std::uint64_t m = std::uint64_t{1} << 25U;
  testutil::splitmix64 rng(9);
  std::int64_t truth = static_cast<std::int64_t>(m) - 40000;  // close to the wrap
  std::int64_t first = 0;
  const std::int64_t start = truth;
  for (int i = 0; i < 2000; ++i) {
    const auto reading = static_cast<std::uint64_t>(truth) % m;
    bs::slave_values v;
    v.multi_turn = reading >> 13U;
    v.single_turn = reading & 0x1FFFU;
    std::uint32_t words[2] = {};
    REQUIRE(bs::encode_frame(layout, v, span<std::uint32_t>(words, 2), {1, 1, false, 4}).ok());
    const auto r = bs::decode_frame(words, 64, layout);
    REQUIRE(r.is_complete());
    const position_status st = bs::update_position(t, r);
    if (i == 0) {
      REQUIRE(st == position_status::seeded);
      first = t.counts() - truth;
    } else {
      REQUIRE(st == position_status::accepted);
    }
    REQUIRE(t.counts() - first == truth);
    truth += static_cast<std::int64_t>(rng.below(2901)) - 400;
  }
  CHECK(start < static_cast<std::int64_t>(m));  // the trajectory crossed the counter's wrap
  CHECK(truth > static_cast<std::int64_t>(m));
  // an impossible jump: a quarter of the range
  bs::slave_values v;
  v.multi_turn = ((static_cast<std::uint64_t>(truth) + m / 4U) % m) >> 13U;
  std::uint32_t words[2] = {};
  REQUIRE(bs::encode_frame(layout, v, span<std::uint32_t>(words, 2), {1, 1, false, 4}).ok());
  const std::int64_t kept = t.counts();
  CHECK(bs::update_position(t, bs::decode_frame(words, 64, layout)) ==
        position_status::implausible_step);
  CHECK(t.counts() == kept);
}

TEST_CASE("link health against the ABSYS emulator: CRC errors, silence, nE") {
  ab::emulator enc;
  link_health h({2, 2});
  position_tracker t(bs::position_config_for(ab::default_bp3(bs::encoder_type::rotary, 512, 10)));
  enc.set_position(1000);
  CHECK(bs::record(h, read(enc, fault::none)) == link_event::none);
  CHECK(bs::record(h, read(enc, fault::none)) == link_event::restored);
  const auto crc = read(enc, fault::crc);
  CHECK(crc.error() == errc::crc_mismatch);
  CHECK(bs::update_position(t, crc) == position_status::no_reading);
  CHECK(bs::record(h, crc) == link_event::none);
  const auto silent = read(enc, fault::silent);
  CHECK(silent.error() == errc::biss_no_ack);
  CHECK(bs::record(h, silent) == link_event::lost);
  CHECK(bs::record(h, read(enc, fault::none)) == link_event::none);
  enc.set_error(ab::sensor_error::in_operation);  // nE active: an alarm, and no reading
  const auto ne = read(enc, fault::none);
  CHECK(bs::outcome_of(ne) == link_outcome::alarm);
  CHECK(bs::update_position(t, ne) == position_status::no_reading);
  CHECK_FALSE(t.has_position());
  CHECK(bs::record(h, ne) == link_event::restored);
  enc.set_error(ab::sensor_error::none);
  CHECK(bs::update_position(t, read(enc, fault::none)) == position_status::seeded);
  CHECK(t.counts() == 1000);
  const link_counters& c = h.counters();
  CHECK(c.frames == 6);
  CHECK(c.crc_errors == 1);
  CHECK(c.timeouts == 1);
  CHECK(c.alarms == 1);
  CHECK(c.losses == 1);
  // an incomplete capture is a timeout; a slave index past the chain is invalid
  std::uint32_t words[2] = {};
  REQUIRE(enc.frame(words, 2, 1).ok());
  const auto cut = bs::decode_frame(words, 20, ab::layout);
  CHECK(cut.is_incomplete());
  CHECK(bs::outcome_of(cut) == link_outcome::timeout);
  const auto good = bs::decode_frame(words, 64, ab::layout);
  CHECK(bs::outcome_of(good, 1) == link_outcome::invalid);
  CHECK(bs::update_position(t, good, 1) == position_status::no_reading);
}

TEST_CASE("configurations from the layout, a given turn, and the EDS") {
  CHECK(bs::position_config_for(ab::layout).range() == (std::uint64_t{1} << 32U));
  const auto given = bs::position_config_for(ab::layout, 360000, 100);
  CHECK(given.counts_per_turn == 360000U);
  CHECK(given.turns == 1U);
  CHECK(given.max_step == 100U);
  constexpr bs::slave_layout wide{63, 1, 0, true, true, bs::crc6_43};
  CHECK_FALSE(bs::position_config_for(wide, 1000, 0).valid());
  CHECK_FALSE(bs::position_config_for(wide).valid());
  bs::bp3_profile linear = ab::default_bp3(bs::encoder_type::linear, 1000, 0);
  CHECK_FALSE(bs::position_config_for(linear).valid());
  bs::bp3_profile multi = ab::default_bp3(bs::encoder_type::rotary, 1, 17);
  multi.mt_length = 12;
  const auto mc = bs::position_config_for(multi);
  CHECK(mc.counts_per_turn == (std::uint64_t{1} << 17U));
  CHECK(mc.turns == 4096U);
  multi.mt_length = 63;
  CHECK_FALSE(bs::position_config_for(multi).valid());
}

TEST_CASE("frame timing: from the clock, the measured line delay, the Ack and the timeout") {
  // ABSYS at its highest clock (2.5 MHz, Table 1): 40 bits of slave data.
  const auto t = bs::frame_timing_for(ab::layout, 2500000, 3, 1, 50);
  REQUIRE(t.ok());
  CHECK(t->capture_bits == 3U + 1U + 1U + 2U + 40U);
  CHECK(t->response_timeout_ns == 47U * 400U);
  CHECK(t->cycle_ns == 97U * 400U);
  CHECK(t->options.max_line_delay == 4U);
  CHECK(t->options.max_ack_bits == 1U);
  // the bounds decode a frame whose line delay drifted by one clock, and call a silent line
  // biss_no_ack within the capture
  ab::emulator enc;
  enc.set_position(0x12345);
  std::uint32_t words[2] = {};
  REQUIRE(enc.frame(words, 4, 1).ok());
  const auto r = bs::decode_frame(words, t->capture_bits, ab::layout, t->options);
  REQUIRE(r.is_complete());
  CHECK(r->slaves[0].single_turn == 0x12345U);
  const std::uint32_t idle[2] = {0xFFFFFFFFU, 0xFFFFFFFFU};
  CHECK(bs::decode_frame(idle, t->capture_bits, ab::layout, t->options).error() ==
        errc::biss_no_ack);
  // rounding up: 1 MHz + 1 Hz makes each clock just under 1 µs
  const auto odd = bs::frame_timing_for(ab::layout, 1000001, 0, 1, 0);
  REQUIRE(odd.ok());
  CHECK(odd->response_timeout_ns == 44000U);      // 44 clocks of 999.999 ns, rounded up
  CHECK(bs::clocks_for_ns(1000, 2500000) == 3U);  // 2.5 clocks: 3
  CHECK(bs::clocks_for_ns(800, 2500000) == 2U);
  CHECK(bs::clocks_for_ns(800, 0) == 0U);
  // a chain: both slaves' bits
  const bs::slave_layout chain[2] = {ab::layout, ab::layout};
  const auto c = bs::frame_timing_for(span<const bs::slave_layout>(chain, 2), 2500000, 0, 1, 0);
  REQUIRE(c.ok());
  CHECK(c->capture_bits == 1U + 1U + 2U + 80U);
  // errors
  CHECK(bs::frame_timing_for(ab::layout, 0, 0, 1, 0).error() == errc::invalid_argument);
  CHECK(bs::frame_timing_for(ab::layout, 2500000, 0, 0, 0).error() == errc::invalid_argument);
  CHECK(bs::frame_timing_for(span<const bs::slave_layout>(), 2500000, 0, 1, 0).error() ==
        errc::invalid_argument);
  constexpr bs::slave_layout broken{0, 0, 0, true, true, bs::crc6_43};
  CHECK(bs::frame_timing_for(broken, 2500000, 0, 1, 0).error() == errc::biss_layout);
  CHECK(bs::frame_timing_for(ab::layout, 1, 0, 1, 10).error() == errc::out_of_range);
  CHECK(bs::frame_timing_for(ab::layout, 2500000, 0, 1, std::size_t{1} << 31U).error() ==
        errc::out_of_range);
  if (sizeof(std::size_t) > 4U) {  // counts that cannot even be multiplied safely
    const auto huge = static_cast<std::size_t>(std::uint64_t{1} << 32U);
    CHECK(bs::frame_timing_for(ab::layout, 2500000, huge, 1, 0).error() == errc::out_of_range);
    CHECK(bs::frame_timing_for(ab::layout, 2500000, 0, huge, 0).error() == errc::out_of_range);
    CHECK(bs::frame_timing_for(ab::layout, 2500000, 0, 1, huge).error() == errc::out_of_range);
  }
}

TEST_CASE("a given turn with multi-turn bits from a layout made at run time") {
  volatile unsigned mt = 12;  // not a constant: the configuration is made at run time
  bs::slave_layout l = ab::layout;
  l.multi_turn_bits = mt;
  const auto c = bs::position_config_for(l, 360000, 7);
  CHECK(c.counts_per_turn == 360000U);
  CHECK(c.turns == 4096U);
  CHECK(c.max_step == 7U);
}

TEST_CASE("outcome_of: nW alone is an alarm; frame_timing_for refuses an empty chain") {
  bs::slave_values v;
  v.single_turn = 1234;
  v.nw = false;  // a warning, no error
  std::uint32_t words[4] = {};
  const auto n = bs::encode_frame(ab::layout, v, span<std::uint32_t>(words, 4));
  REQUIRE(n.ok());
  const auto r = bs::decode_frame(span<const std::uint32_t>(words, 4), *n, ab::layout);
  REQUIRE(r.is_complete());
  CHECK(bs::outcome_of(r) == link_outcome::alarm);
  v.nw = true;
  REQUIRE(bs::encode_frame(ab::layout, v, span<std::uint32_t>(words, 4)).ok());
  CHECK(bs::outcome_of(bs::decode_frame(span<const std::uint32_t>(words, 4), *n, ab::layout)) ==
        link_outcome::ok);
  CHECK(bs::frame_timing_for(span<const bs::slave_layout>(), 2500000, 0, 1, 0).error() ==
        errc::invalid_argument);
  bs::slave_layout many[bs::max_chain + 1] = {};
  CHECK(
      bs::frame_timing_for(span<const bs::slave_layout>(many, bs::max_chain + 1), 2500000, 0, 1, 0)
          .error() == errc::invalid_argument);
}

TEST_CASE("position_config_for(layout) without max_step: any step unwrapping can tell") {
  bs::slave_layout l;
  l.single_turn_bits = 12;
  l.multi_turn_bits = 4;  // M = 2^16
  const position_config pc = bs::position_config_for(l);
  REQUIRE(pc.valid());
  position_tracker t(pc);
  CHECK(t.max_step() == 32767U);  // (M - 1) / 2
  REQUIRE(t.update(100) == position_status::seeded);
  CHECK(t.update(100 + 32767) == position_status::accepted);
  CHECK(t.counts() == 100 + 32767);
}

TEST_CASE("a given turn with 62 multi-turn bits, the most; the invalid configurations alike") {
  // position.hpp: more than 62 multi-turn bits is invalid; 62 with one count a turn is the
  // largest range a tracker takes (2^62). Every invalid configuration the three forms give is
  // the same value: 0 counts, 0 turns, the max_step given (as position_config::from_bits's).
  constexpr bs::slave_layout most{62, 0, 0, true, true, bs::crc6_43};
  const auto c = bs::position_config_for(most, 1, 0);
  CHECK(c.counts_per_turn == 1U);
  CHECK(c.turns == (std::uint64_t{1} << 62U));
  CHECK(c.valid());
  CHECK(c.range() == (std::uint64_t{1} << 62U));
  constexpr bs::slave_layout too_many{63, 0, 0, true, true, bs::crc6_43};
  bs::bp3_profile linear = ab::default_bp3(bs::encoder_type::linear, 1000, 0);
  const position_config invalid[] = {
      bs::position_config_for(too_many, 1000, 7), bs::position_config_for(too_many, 7),
      bs::position_config_for(linear, 7), position_config::from_bits(0, 63, 7)};
  for (const position_config& i : invalid) {
    CHECK(i.counts_per_turn == 0U);
    CHECK(i.turns == 0U);
    CHECK(i.max_step == 7U);
    CHECK_FALSE(i.valid());
  }
}

TEST_CASE("position_config_for(bp3_profile): without max_step any step; 62 MT_LEN bits the most") {
  // A rotary profile of 2^10 pulses a turn (SIP_CNT 1, SIP_RES 10) and 4 multi-turn bits:
  // M = 2^14, and without max_step the tracker takes any step unwrapping can tell,
  // (M - 1) / 2. One pulse a turn and MT_LEN 62 is the largest range, 2^62; 63 is invalid.
  bs::bp3_profile p = ab::default_bp3(bs::encoder_type::rotary, 1, 10);
  p.mt_length = 4;
  const position_config pc = bs::position_config_for(p);
  REQUIRE(pc.valid());
  CHECK(pc.max_step == 0U);
  position_tracker t(pc);
  CHECK(t.max_step() == 8191U);
  REQUIRE(t.update(100) == position_status::seeded);
  CHECK(t.update(100 + 8191) == position_status::accepted);
  bs::bp3_profile one = ab::default_bp3(bs::encoder_type::rotary, 1, 0);
  one.mt_length = 62;
  const position_config most = bs::position_config_for(one);
  CHECK(most.valid());
  CHECK(most.range() == (std::uint64_t{1} << 62U));
  one.mt_length = 63;
  CHECK_FALSE(bs::position_config_for(one).valid());
}

TEST_CASE(
    "update_position: a slave past the chain is no reading; every no reading is a missed period") {
  // position.hpp: a slave index past the chain, like a failed frame, is a read period without
  // a reading: position_status::no_reading and missed() (periods() counts it).
  const bs::slave_layout chain[2] = {bs::absys_layout, bs::absys_layout};
  const bs::slave_values values[2] = {{0, 1000, true, true}, {0, 2000, true, true}};
  std::uint32_t words[4] = {};
  const auto n = bs::encode_frame(span<const bs::slave_layout>(chain, 2),
                                  span<const bs::slave_values>(values, 2), words);
  REQUIRE(n.ok());
  const auto r = bs::decode_frame(words, *n, span<const bs::slave_layout>(chain, 2));
  REQUIRE(r.is_complete());
  position_tracker t(bs::position_config_for(bs::absys_layout));
  CHECK(bs::update_position(t, r, 1) == position_status::seeded);
  CHECK(t.counts() == 2000);
  CHECK(t.periods() == 1U);
  CHECK(bs::update_position(t, r, 2) == position_status::no_reading);  // past the chain
  CHECK(t.periods() == 2U);
  CHECK(bs::update_position(t, r, 5) == position_status::no_reading);
  CHECK(t.periods() == 3U);
  const auto cut = bs::decode_frame(words, 20, span<const bs::slave_layout>(chain, 2));
  REQUIRE(cut.is_incomplete());
  CHECK(bs::update_position(t, cut, 0) == position_status::no_reading);
  CHECK(t.periods() == 4U);
  CHECK(t.counts() == 2000);
  CHECK(bs::update_position(t, r, 1) == position_status::accepted);
  CHECK(t.periods() == 1U);
}

TEST_CASE("frame_timing_for: the longest cycle, eight slaves, 2^32 clocks refused at any clock") {
  // At 1 GHz a clock lasts 1 ns: ABSYS with no line delay and an Ack of 1 captures 44 clocks;
  // a timeout of 2^32 - 1 - 44 clocks makes a cycle of 2^32 - 1 ns, the longest accepted, one
  // clock more is out_of_range.
  const auto longest = bs::frame_timing_for(ab::layout, 1000000000U, 0, 1, 4294967295U - 44U);
  REQUIRE(longest.ok());
  CHECK(longest->capture_bits == 44U);
  CHECK(longest->response_timeout_ns == 44U);
  CHECK(longest->cycle_ns == 4294967295U);
  CHECK(bs::frame_timing_for(ab::layout, 1000000000U, 0, 1, 4294967296U - 44U).error() ==
        errc::out_of_range);
  // a chain of max_chain slaves: 1 + 1 + 2 + 8 x 40 clocks
  const bs::slave_layout eight[bs::max_chain] = {ab::layout, ab::layout, ab::layout, ab::layout,
                                                 ab::layout, ab::layout, ab::layout, ab::layout};
  const auto c =
      bs::frame_timing_for(span<const bs::slave_layout>(eight, bs::max_chain), 2500000, 0, 1, 0);
  REQUIRE(c.ok());
  CHECK(c->capture_bits == 4U + 320U);
  // position.hpp: a count of 2^32 clocks or more is out_of_range whatever the clock, also at
  // 4 GHz where 2^32 clocks last about 2^30 ns
  if (sizeof(std::size_t) > 4U) {
    const auto count = static_cast<std::size_t>(std::uint64_t{1} << 32U);
    CHECK(bs::frame_timing_for(ab::layout, 4000000000U, count, 1, 0).error() == errc::out_of_range);
    CHECK(bs::frame_timing_for(ab::layout, 4000000000U, 0, count, 0).error() == errc::out_of_range);
    CHECK(bs::frame_timing_for(ab::layout, 4000000000U, 0, 1, count).error() == errc::out_of_range);
    CHECK(bs::frame_timing_for(ab::layout, 4000000000U, count - 1U, 1, 0).ok());
  }
  // a refused timing's value is an empty one: nothing computed, the decoder's default bounds
  const auto refused = bs::frame_timing_for(ab::layout, 0, 0, 1, 0);
  REQUIRE(!refused.ok());
  CHECK(refused.value().capture_bits == 0U);
  CHECK(refused.value().response_timeout_ns == 0U);
  CHECK(refused.value().cycle_ns == 0U);
  CHECK(refused.value().options.max_line_delay == bs::decode_options{}.max_line_delay);
}
