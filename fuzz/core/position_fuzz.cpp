// Position tracker oracle: readings from a hostile encoder (any value, any order) against an
// independent model of the documented rules in 128-bit arithmetic: the step modulo M of smallest
// magnitude, accepted within max_step x the periods since the last accepted reading (capped at
// (M - 1) / 2), the count unchanged otherwise, modulo 2^64. Input: counts_per_turn, turns and
// max_step (8 bytes each, reduced), then operations of 9 bytes: a kind and a value.
#include <motionbus/core/position.hpp>

#include <cstring>

#include "../fuzz_check.hpp"

namespace mb = motionbus;

namespace {

__extension__ typedef __int128 i128;           // NOLINT(modernize-use-using): __extension__
__extension__ typedef unsigned __int128 u128;  // NOLINT(modernize-use-using)

std::uint64_t take(const std::uint8_t* data, std::size_t size, std::size_t at) {
  std::uint64_t v = 0;
  if (at < size) {
    std::memcpy(&v, data + at, size - at < 8U ? size - at : 8U);
  }
  return v;
}

struct model {
  u128 m;
  u128 max_step;
  u128 limit;
  bool seeded = false;
  u128 last = 0;
  i128 counts = 0;
  u128 periods = 1;

  mb::position_status update(u128 v) {
    if (v >= m) {
      ++periods;
      return mb::position_status::out_of_range;
    }
    if (!seeded) {
      seeded = true;
      last = v;
      counts = static_cast<i128>(v);
      periods = 1;
      return mb::position_status::seeded;
    }
    i128 d = static_cast<i128>(v) - static_cast<i128>(last);
    if (d < 0) {
      d += static_cast<i128>(m);
    }
    if (d > static_cast<i128>(m / 2U)) {
      d -= static_cast<i128>(m);
    }
    const u128 mag = static_cast<u128>(d < 0 ? -d : d);
    u128 bound = max_step * periods;
    bound = bound > limit ? limit : bound;
    if (mag > bound) {
      ++periods;
      return mb::position_status::implausible_step;
    }
    counts += d;
    last = v;
    periods = 1;
    return mb::position_status::accepted;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Small ranges most of the time (wraps happen), any range up to 2^62 sometimes.
  const std::uint64_t a = take(data, size, 0);
  const std::uint64_t b = take(data, size, 8);
  const bool small = (a & 1U) == 0U;
  const std::uint64_t cpt = small ? (a >> 1U) % 5000U : a >> (1U + (a & 0x3FU) % 63U);
  const std::uint64_t turns = small ? b % 70U : b >> (b & 0x3FU);
  const std::uint64_t max_step = take(data, size, 16) % (small ? 4000U : ~std::uint64_t{0});
  const mb::position_config cfg{cpt, turns, max_step};
  mb::position_tracker t(cfg);
  if (!cfg.valid()) {
    MOTIONBUS_FUZZ_CHECK(t.update(take(data, size, 24)) == mb::position_status::invalid_config);
    return 0;
  }
  const std::uint64_t m = cfg.range();
  MOTIONBUS_FUZZ_CHECK(m == static_cast<u128>(cpt) * turns);
  model ref{m, max_step == 0U ? (m - 1U) / 2U : max_step, (m - 1U) / 2U};
  for (std::size_t i = 24; i + 9U <= size; i += 9U) {
    const std::uint8_t kind = data[i] % 4U;
    std::uint64_t v = take(data, size, i + 1U);
    v = (data[i] & 0x80U) != 0U ? v : v % (m + 2U);  // mostly in range, sometimes anything
    mb::position_status want{};
    mb::position_status got{};
    if (kind == 0U) {
      want = ref.update(v);
      got = t.update(v);
    } else if (kind == 1U) {
      const std::uint64_t single = v % (cpt + 1U);
      const std::uint64_t multi = (v >> 32U) % (turns + 1U);
      want = single >= cpt || multi >= turns ? ref.update(m)  // out of range: a missed period
                                             : ref.update(static_cast<u128>(multi) * cpt + single);
      got = t.update(single, multi);
    } else if (kind == 2U) {
      ++ref.periods;
      t.missed();
      continue;
    } else {
      ref.seeded = false;
      ref.periods = 1;
      t.reset();
      continue;
    }
    MOTIONBUS_FUZZ_CHECK(got == want);
    MOTIONBUS_FUZZ_CHECK(t.has_position() == ref.seeded);
    if (ref.seeded) {
      MOTIONBUS_FUZZ_CHECK(static_cast<std::uint64_t>(t.counts()) ==
                           static_cast<std::uint64_t>(ref.counts));
      MOTIONBUS_FUZZ_CHECK(t.reading() == ref.last);
      // the helpers agree with each other: counts = turns x cpt + within_turn, modulo 2^64
      MOTIONBUS_FUZZ_CHECK(t.within_turn() < cpt);
      MOTIONBUS_FUZZ_CHECK(static_cast<std::uint64_t>(t.turns()) * cpt + t.within_turn() ==
                           static_cast<std::uint64_t>(t.counts()));
      (void)t.millidegrees();
    }
  }
  return 0;
}
