// The position tracker: a simulated axis turning at varying speed, read at a fixed rate, across
// every wrap (single-turn rollover, multi-turn counter wrap, a turn that is not a power of two),
// with missed reads and injected impossible jumps; configuration limits and the helpers.
#include "motionbus/core/position.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "../support/prng.hpp"

using namespace motionbus;

namespace {

// The reading of a true position p (any sign): p modulo M in 0..M-1.
std::uint64_t reading_of(std::int64_t p, std::uint64_t m) {
  const auto sm = static_cast<std::int64_t>(m);
  const std::int64_t r = p % sm;
  return static_cast<std::uint64_t>(r < 0 ? r + sm : r);
}

// floor(p / m) for the wrap count.
std::int64_t wraps_of(std::int64_t p, std::uint64_t m) {
  const auto sm = static_cast<std::int64_t>(m);
  return p >= 0 ? p / sm : -((-p - 1) / sm) - 1;
}

struct trajectory_stats {
  int wraps_up = 0;
  int wraps_down = 0;
  int jumps = 0;
  int missed = 0;
};

// An axis starting at `start` whose speed (counts per read) changes by a random acceleration
// each read, kept within max_step; read `reads` times at the fixed rate. One read in
// `jump_every` is replaced by an impossible one, one in `miss_every` is missed.
trajectory_stats run_axis(const position_config& cfg, std::int64_t start, std::uint64_t seed,
                          int reads, int jump_every, int miss_every) {
  testutil::splitmix64 rng(seed);
  position_tracker t(cfg);
  const std::uint64_t m = cfg.range();
  const auto max_speed = static_cast<std::int64_t>(cfg.max_step);
  std::int64_t p = start;
  std::int64_t v = 0;
  trajectory_stats s;
  REQUIRE(t.update(reading_of(p, m)) == position_status::seeded);
  const std::int64_t origin = p - static_cast<std::int64_t>(reading_of(p, m));
  std::int64_t last_wrap = wraps_of(p, m);
  bool skipped = false;  // the previous read was missed or rejected
  for (int i = 0; i < reads; ++i) {
    const std::int64_t accel = static_cast<std::int64_t>(rng.below(2U * 64U + 1U)) - 64;
    v += accel * (max_speed / 256 + 1);
    v = v > max_speed ? max_speed : (v < -max_speed ? -max_speed : v);
    p += v;
    const std::int64_t w = wraps_of(p, m);
    s.wraps_up += w > last_wrap ? 1 : 0;
    s.wraps_down += w < last_wrap ? 1 : 0;
    last_wrap = w;
    if (miss_every != 0 && rng.below(static_cast<std::uint64_t>(miss_every)) == 0U) {
      t.missed();
      ++s.missed;
      skipped = true;
      continue;
    }
    if (jump_every != 0 && !skipped && rng.below(static_cast<std::uint64_t>(jump_every)) == 0U) {
      // A reading the axis cannot reach from the last accepted one in one period.
      const std::uint64_t span = cfg.unambiguous_step() - t.plausible_step();
      const std::uint64_t jump = t.plausible_step() + 1U + rng.below(span == 0U ? 1U : span);
      const std::int64_t before = t.counts();
      const std::uint64_t bad = (t.reading() + (rng.below(2) == 0U ? jump : m - jump)) % m;
      CHECK(t.update(bad) == position_status::implausible_step);
      CHECK(t.counts() == before);
      ++s.jumps;
      skipped = true;
      continue;
    }
    const position_status st = t.update(reading_of(p, m));
    REQUIRE(st == position_status::accepted);
    REQUIRE(t.counts() == p - origin);  // the unwrapped position is the simulated one
    skipped = false;
  }
  CHECK(t.implausible_steps() == static_cast<std::uint32_t>(s.jumps));
  return s;
}

}  // namespace

TEST_CASE("single-turn reading: the rollover unwrapped over random trajectories") {
  // T-format ID0 of a 17-bit encoder, a single-turn BiSS slave: M = 2^17; up to 3000 counts a
  // read (6000 min^-1 read at 4.4 kHz), so many turns each way.
  const position_config cfg = position_config::from_bits(17, 0, 3000);
  REQUIRE(cfg.valid());
  int up = 0;
  int down = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const auto s = run_axis(cfg, static_cast<std::int64_t>(seed * 6007U), seed, 3000, 0, 0);
    up += s.wraps_up;
    down += s.wraps_down;
  }
  CHECK(up > 20);  // the trajectories did cross the rollover, both ways
  CHECK(down > 20);
}

TEST_CASE("multi-turn reading: the counter's wrap (65535 -> 0 and back) unwrapped") {
  // TS5700N8500 ID3: 2^17 counts x 2^16 turns; the axis starts within a few turns of the
  // counter's end, at up to 100 000 counts a read.
  const position_config cfg = position_config::from_bits(17, 16, 100000);
  const std::int64_t m = static_cast<std::int64_t>(cfg.range());
  int up = 0;
  int down = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const std::int64_t start = m - static_cast<std::int64_t>((seed % 5U) << 17U) - 1;
    const auto s = run_axis(cfg, start, seed * 31U, 2000, 0, 0);
    up += s.wraps_up;
    down += s.wraps_down;
  }
  CHECK(up > 0);  // the counter's wrap crossed, both ways
  CHECK(down > 0);
}

TEST_CASE("a turn that is not a power of two (BP3 rotary: SIP_CNT x 2^SIP_RES)") {
  const position_config cfg{360000, 1, 170000};  // a fast axis: almost half a turn a read
  REQUIRE(cfg.valid());
  int wraps = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto s = run_axis(cfg, 359999, seed + 100U, 2000, 0, 0);
    wraps += s.wraps_up + s.wraps_down;
  }
  CHECK(wraps > 100);
}

TEST_CASE("injected impossible jumps are reported, the position kept, tracking resumes") {
  int wraps = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto a = run_axis(position_config::from_bits(17, 0, 3000), 5, seed, 3000, 20, 0);
    CHECK(a.jumps > 50);
    const auto b = run_axis(position_config::from_bits(17, 16, 100000), (std::int64_t{1} << 33) - 7,
                            seed, 2000, 20, 0);
    CHECK(b.jumps > 30);
    wraps += b.wraps_up + b.wraps_down;
  }
  CHECK(wraps > 0);  // jumps were injected across the counter's wrap too
}

TEST_CASE("missed reads widen the plausible step: the position survives an outage") {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto s = run_axis(position_config::from_bits(17, 0, 3000), 77, seed, 3000, 25, 4);
    CHECK(s.missed > 300);
    CHECK(s.jumps > 10);
  }
}

TEST_CASE("the bound: max_step accepted, max_step + 1 not; it grows per missed period") {
  position_tracker t(position_config::from_bits(10, 0, 100));  // M = 1024
  CHECK(t.update(1000) == position_status::seeded);
  CHECK(t.counts() == 1000);
  CHECK(t.update((1000 + 100) % 1024) == position_status::accepted);  // +100 across the rollover
  CHECK(t.counts() == 1100);
  CHECK(t.step() == 100);
  CHECK(t.update(76 + 101) == position_status::implausible_step);
  CHECK(t.counts() == 1100);
  CHECK(t.periods() == 2);
  CHECK(t.plausible_step() == 200);
  CHECK(t.update(76 + 200) == position_status::accepted);  // two periods' worth
  CHECK(t.counts() == 1300);
  CHECK(t.plausible_step() == 100);
  for (int i = 0; i < 10; ++i) {
    t.missed();
  }
  CHECK(t.plausible_step() == 511);  // capped at (M - 1) / 2
  CHECK(t.periods() == 11);
  CHECK(t.update((276 + 1024 - 511) % 1024) == position_status::accepted);
  CHECK(t.counts() == 1300 - 511);
  CHECK(t.step() == -511);
  CHECK(t.implausible_steps() == 1);
}

TEST_CASE("max_step 0: the largest unambiguous step, (M - 1) / 2") {
  position_tracker even(position_config::from_bits(3, 0));  // M = 8: steps up to 3
  CHECK(even.max_step() == 3);
  CHECK(even.update(0) == position_status::seeded);
  CHECK(even.update(3) == position_status::accepted);
  CHECK(even.update(7) == position_status::implausible_step);  // 4 either way: ambiguous
  CHECK(even.update(6) == position_status::accepted);          // +3 from the last accepted
  CHECK(even.counts() == 6);
  position_tracker odd(position_config{7, 1, 0});  // M = 7: steps up to 3
  CHECK(odd.update(6) == position_status::seeded);
  CHECK(odd.update(2) == position_status::accepted);  // +3 across the rollover
  CHECK(odd.counts() == 9);
  CHECK(odd.update(6) == position_status::accepted);  // +4 modulo 7 is -3
  CHECK(odd.counts() == 6);
  CHECK(odd.step() == -3);
}

TEST_CASE("two-field readings: each field checked against its own range") {
  position_tracker t(position_config::from_bits(17, 16, 1000));
  CHECK(t.update(131070, 65535) == position_status::seeded);
  CHECK(t.counts() == (std::int64_t{1} << 33) - 2);
  CHECK(t.update(131070, 65534) == position_status::implausible_step);  // a whole turn back
  CHECK(t.update(3, 0) == position_status::accepted);  // +5: the counter wrapped to 0
  CHECK(t.counts() == (std::int64_t{1} << 33) + 3);
  CHECK(t.turns() == 65536);
  CHECK(t.update(131072, 0) == position_status::out_of_range);
  CHECK(t.update(0, 65536) == position_status::out_of_range);
  CHECK(t.update(std::uint64_t{1} << 33) == position_status::out_of_range);
  CHECK(t.counts() == (std::int64_t{1} << 33) + 3);
}

TEST_CASE("reset() forgets the position: the next reading seeds it") {
  position_tracker t(position_config::from_bits(8, 0, 10));
  CHECK(t.update(250) == position_status::seeded);
  CHECK(t.update(4) == position_status::accepted);
  CHECK(t.counts() == 260);
  CHECK(t.update(100) == position_status::implausible_step);  // e.g. an encoder zero reset
  t.reset();
  CHECK_FALSE(t.has_position());
  CHECK(t.update(100) == position_status::seeded);
  CHECK(t.counts() == 100);
  CHECK(t.reading() == 100);
  CHECK(t.step() == 0);
}

TEST_CASE("configurations: ranges 4 .. 2^62, max_step within (M - 1) / 2") {
  CHECK_FALSE(position_config{1, 1, 0}.valid());
  CHECK_FALSE(position_config{3, 1, 0}.valid());
  CHECK(position_config{4, 1, 0}.valid());
  CHECK(position_config{2, 2, 1}.valid());
  CHECK_FALSE(position_config{0, 5, 0}.valid());
  CHECK_FALSE(position_config{5, 0, 0}.valid());
  CHECK(position_config::from_bits(31, 31).valid());
  CHECK_FALSE(position_config::from_bits(32, 31).valid());
  CHECK_FALSE(position_config::from_bits(63, 0).valid());
  CHECK_FALSE(position_config::from_bits(0, 63).valid());
  CHECK_FALSE((position_config{std::uint64_t{1} << 40, std::uint64_t{1} << 40, 0}.valid()));
  CHECK(position_config::from_bits(10, 0, 511).valid());
  CHECK_FALSE(position_config::from_bits(10, 0, 512).valid());
  position_tracker bad(position_config::from_bits(10, 0, 512));
  CHECK(bad.update(1) == position_status::invalid_config);
  CHECK(bad.update(1, 0) == position_status::invalid_config);
  CHECK_FALSE(bad.has_position());
  CHECK(to_string(position_status::accepted) == std::string("accepted"));
  CHECK(to_string(position_status::seeded) == std::string("seeded"));
  CHECK(to_string(position_status::implausible_step) == std::string("implausible_step"));
  CHECK(to_string(position_status::out_of_range) == std::string("out_of_range"));
  CHECK(to_string(position_status::invalid_config) == std::string("invalid_config"));
  CHECK(to_string(position_status::no_reading) == std::string("no_reading"));
  CHECK(to_string(static_cast<position_status>(99)) == std::string("unknown"));
}

TEST_CASE("turns, within_turn, millidegrees, revolutions and degrees, negative positions too") {
  position_tracker t(position_config::from_bits(17, 0, 60000));
  CHECK(t.update(100) == position_status::seeded);
  CHECK(t.turns() == 0);
  CHECK(t.within_turn() == 100);
  CHECK(t.update(131072 - 49900) == position_status::accepted);  // 100 -> -49900
  CHECK(t.counts() == -49900);
  CHECK(t.turns() == -1);
  CHECK(t.within_turn() == 131072 - 49900);
  // -49900 / 131072 turns = -137.054443... degrees: floor in millidegrees
  CHECK(t.millidegrees() == -137055);
  CHECK(t.revolutions() == doctest::Approx(-49900.0 / 131072.0));
  CHECK(t.degrees() == doctest::Approx(-49900.0 * 360.0 / 131072.0));
  position_tracker exact(position_config{360000, 4, 0});
  CHECK(exact.update(3 * 360000 + 123456) == position_status::seeded);
  CHECK(exact.millidegrees() == 3 * 360000 + 123456);
  // A huge turn (2^61 counts) where within_turn x 360000 does not fit 64 bits: exact still.
  position_tracker huge(position_config{std::uint64_t{1} << 61U, 2, 0});
  CHECK(huge.update((std::uint64_t{1} << 61U) - 1U) == position_status::seeded);
  CHECK(huge.millidegrees() == 359999);
  CHECK(huge.update(std::uint64_t{1} << 60U) == position_status::accepted);
  CHECK(huge.millidegrees() == 180000);
}

TEST_CASE("the defaults: a single-turn reading of 2^17 counts, max_step (M - 1) / 2") {
  // position_config{} (a default-constructed tracker's) is the TS5700N8500's ID0 reading
  const position_config c;
  CHECK(c.counts_per_turn == 131072);
  CHECK(c.turns == 1);
  CHECK(c.max_step == 0);
  position_tracker t;
  CHECK(t.counts_per_turn() == 131072);
  CHECK(t.max_step() == 65535);
  CHECK(t.update(0) == position_status::seeded);
  CHECK(t.update(65535) == position_status::accepted);       // the largest step, half a turn less 1
  CHECK(t.update(131072) == position_status::out_of_range);  // M is one turn
  CHECK(t.update(0) == position_status::accepted);           // -65535 (+65537 is the longer way)
  CHECK(t.counts() == 0);
}

TEST_CASE("the range's limits: M up to 2^62, from_bits up to 62 bits in all") {
  CHECK(max_position_range == std::uint64_t{1} << 62U);
  CHECK(position_config{std::uint64_t{1} << 62U, 1, 0}.valid());
  CHECK(position_config{std::uint64_t{1} << 61U, 2, 0}.valid());
  CHECK_FALSE(position_config{std::uint64_t{1} << 62U, 2, 0}.valid());
  CHECK_FALSE(position_config{std::uint64_t{1} << 63U, 1, 0}.valid());
  CHECK(position_config::from_bits(62, 0).valid());
  CHECK(position_config::from_bits(62, 0).range() == std::uint64_t{1} << 62U);
  CHECK(position_config::from_bits(0, 62).valid());
  CHECK(position_config::from_bits(0, 62).range() == std::uint64_t{1} << 62U);
  CHECK_FALSE(position_config::from_bits(62, 1).valid());
  CHECK_FALSE(position_config::from_bits(1, 62).valid());
  position_tracker t(position_config::from_bits(62, 0));
  CHECK(t.update((std::uint64_t{1} << 62U) - 1U) == position_status::seeded);
  CHECK(t.update(0) == position_status::accepted);  // +1 across the rollover
  CHECK(t.counts() == std::int64_t{1} << 62U);
}

TEST_CASE("a reading out of range is a period missed, as a rejected one is") {
  position_tracker t(position_config::from_bits(10, 0, 100));  // M = 1024
  CHECK(t.update(500) == position_status::seeded);
  CHECK(t.update(1024) == position_status::out_of_range);
  CHECK(t.periods() == 2);
  CHECK(t.plausible_step() == 200);
  CHECK(t.update(1024, 0) == position_status::out_of_range);  // the single-turn field
  CHECK(t.update(0, 1) == position_status::out_of_range);     // the multi-turn field
  CHECK(t.periods() == 4);
  CHECK(t.plausible_step() == 400);
  CHECK(t.update(900) == position_status::accepted);  // four periods' worth
  CHECK(t.counts() == 900);
  CHECK(t.implausible_steps() == 0);
}

TEST_CASE("before the first reading: counts, step and reading 0, one period, max_step") {
  const position_tracker t(position_config::from_bits(10, 0, 100));
  CHECK_FALSE(t.has_position());
  CHECK(t.counts() == 0);
  CHECK(t.step() == 0);
  CHECK(t.reading() == 0);
  CHECK(t.periods() == 1);
  CHECK(t.plausible_step() == 100);
  CHECK(t.implausible_steps() == 0);
}

TEST_CASE("the first reading is the last accepted one: periods missed before it are forgotten") {
  position_tracker t(position_config::from_bits(10, 0, 100));  // M = 1024
  t.missed();
  t.missed();  // the encoder does not answer yet
  CHECK(t.periods() == 3);
  CHECK(t.plausible_step() == 300);
  CHECK(t.update(500) == position_status::seeded);
  CHECK(t.periods() == 1);
  CHECK(t.plausible_step() == 100);
  CHECK(t.step() == 0);
  CHECK(t.update(601) == position_status::implausible_step);  // one period's bound, not three
  // the same after reset(), periods missed between it and the reading
  CHECK(t.update(600) == position_status::accepted);
  t.reset();
  t.missed();
  t.missed();
  CHECK(t.update(10) == position_status::seeded);
  CHECK(t.periods() == 1);
  CHECK(t.plausible_step() == 100);
  CHECK(t.step() == 0);
  CHECK(t.update(111) == position_status::implausible_step);
}

TEST_CASE("reset() after use: step 0, one period, max_step, as a new tracker's") {
  position_tracker t(position_config::from_bits(10, 0, 100));  // M = 1024
  CHECK(t.update(500) == position_status::seeded);
  CHECK(t.update(550) == position_status::accepted);
  CHECK(t.update(900) == position_status::implausible_step);
  t.missed();
  CHECK(t.step() == 50);
  CHECK(t.periods() == 3);
  CHECK(t.plausible_step() == 300);
  t.reset();
  CHECK_FALSE(t.has_position());
  CHECK(t.step() == 0);
  CHECK(t.periods() == 1);
  CHECK(t.plausible_step() == 100);
  CHECK(t.implausible_steps() == 1);  // counted since construction
}

TEST_CASE("whole turns: a turn's first count is in that turn, at 0 and below 0 too") {
  position_tracker t(position_config::from_bits(4, 4));  // 16 counts x 16 turns, steps to 127
  CHECK(t.update(0) == position_status::seeded);
  CHECK(t.turns() == 0);
  CHECK(t.within_turn() == 0);
  CHECK(t.millidegrees() == 0);
  CHECK(t.update(256 - 16) == position_status::accepted);  // one turn back: -16
  CHECK(t.counts() == -16);
  CHECK(t.turns() == -1);
  CHECK(t.within_turn() == 0);
  CHECK(t.millidegrees() == -360000);
  CHECK(t.update(32) == position_status::accepted);  // +48
  CHECK(t.counts() == 32);
  CHECK(t.turns() == 2);
  CHECK(t.within_turn() == 0);
  CHECK(t.millidegrees() == 720000);
}

TEST_CASE("the enumerators' numbers are part of the interface") {
  // firmware logs the status as an integer (the meter's position expectations are such numbers),
  // so the numbers are fixed here as the header states them
  CHECK(static_cast<int>(position_status::accepted) == 0);
  CHECK(static_cast<int>(position_status::seeded) == 1);
  CHECK(static_cast<int>(position_status::implausible_step) == 2);
  CHECK(static_cast<int>(position_status::out_of_range) == 3);
  CHECK(static_cast<int>(position_status::invalid_config) == 4);
  CHECK(static_cast<int>(position_status::no_reading) == 5);
}
