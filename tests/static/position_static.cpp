// Compile-time suite for the position tracker, the link health and the deadlines: every
// assertion is evaluated by the compiler, where constant evaluation also rejects undefined
// behaviour (signed overflow in the unwrapping, shifts out of range). Compiling this file is the
// test.
#include <cstdint>

#include "motionbus/biss/position.hpp"
#include "motionbus/core/link_health.hpp"
#include "motionbus/core/position.hpp"
#include "motionbus/devices/absys.hpp"
#include "motionbus/tformat/position.hpp"

namespace mb = motionbus;

namespace {

// The TS5700N8500's counter wrap (65535 -> 0) and back, unwrapped.
constexpr std::int64_t across_the_wrap() {
  mb::position_tracker t(mb::position_config::from_bits(17, 16, 1000));
  (void)t.update(131000, 65535);
  (void)t.update(200, 0);         // +272 across the wrap
  (void)t.update(131071, 65535);  // -201 back
  return t.counts();
}
static_assert(across_the_wrap() == (std::int64_t{1} << 33) - 1, "");

constexpr mb::position_status a_jump() {
  mb::position_tracker t(mb::position_config::from_bits(17, 0, 1000));
  (void)t.update(5);
  return t.update(5 + 65536);
}
static_assert(a_jump() == mb::position_status::implausible_step, "");

constexpr std::int64_t largest_range() {
  mb::position_tracker t(mb::position_config{std::uint64_t{1} << 31U, std::uint64_t{1} << 31U, 0});
  (void)t.update((std::uint64_t{1} << 62U) - 1U);
  (void)t.update(std::uint64_t{1} << 61U);  // the largest step back: (M - 1) / 2
  return t.step();
}
static_assert(largest_range() == -(std::int64_t{1} << 61U) + 1, "");

// millidegrees() (a bit-by-bit multiply-divide) in constant evaluation: exact where
// within_turn() x 360000 does not fit 64 bits, and below zero.
constexpr std::int64_t millidegrees_at(std::uint64_t counts_per_turn, std::uint64_t first,
                                       std::uint64_t second) {
  mb::position_tracker t(mb::position_config{counts_per_turn, 2, 0});
  (void)t.update(first);
  (void)t.update(second);
  return t.millidegrees();
}
static_assert(millidegrees_at(std::uint64_t{1} << 61U, (std::uint64_t{1} << 61U) - 1U,
                              (std::uint64_t{1} << 61U) - 1U) == 359999,
              "");
static_assert(millidegrees_at(131072, 100, 2 * 131072 - 49900) == -137055, "");

constexpr mb::link_event lost_after_three() {
  mb::link_health h({3, 1});
  (void)h.record(mb::link_outcome::ok);
  (void)h.record(mb::errc::crc_mismatch);
  (void)h.record(mb::errc::biss_no_ack);
  return h.record_timeout();
}
static_assert(lost_after_three() == mb::link_event::lost, "");

static_assert(mb::tformat::response_timeout_ns(mb::tformat::data_id::read_all, 2500000) == 50000,
              "");
static_assert(mb::tformat::response_timeout_ns(mb::tformat::data_id::read_abs, 5000000) == 18000,
              "");
static_assert(mb::biss::frame_timing_for(mb::devices::absys::layout, 2500000, 3, 1, 50)
                      .value()
                      .response_timeout_ns == 18800,
              "");
static_assert(mb::biss::position_config_for(
                  mb::devices::absys::default_bp3(mb::biss::encoder_type::rotary, 512, 10))
                      .counts_per_turn == 524288U,
              "");

}  // namespace

int main() {
  return 0;
}
