// Link health: the counters per outcome, the lost / restored hysteresis, the classification of
// the library's error codes and decode results, saturation.
#include "motionbus/core/link_health.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "../support/run_time.hpp"

using namespace motionbus;

TEST_CASE("the link starts lost and is up after restore_after successes") {
  link_health h({2, 3});
  CHECK(h.lost());
  CHECK(h.record(link_outcome::ok) == link_event::none);
  CHECK(h.record(link_outcome::alarm) == link_event::none);
  CHECK(h.lost());
  CHECK(h.record(link_outcome::ok) == link_event::restored);
  CHECK(h.state() == link_state::up);
  CHECK(h.counters().losses == 0);
  CHECK(h.counters().alarms == 1);
  CHECK(h.counters().good == 3);
}

TEST_CASE("a link that never answers is never up") {
  link_health h;
  for (int i = 0; i < 100; ++i) {
    CHECK(h.record_timeout() == link_event::none);
  }
  CHECK(h.lost());
  CHECK(h.counters().timeouts == 100);
  CHECK(h.counters().consecutive_failures == 100);
  CHECK(h.counters().losses == 0);
}

TEST_CASE("lost after lose_after consecutive failures, whatever their kind; restored after") {
  link_health h({3, 2});
  CHECK(h.record(link_outcome::ok) == link_event::none);
  CHECK(h.record(link_outcome::ok) == link_event::restored);
  // two failures, a success: the count starts again
  CHECK(h.record(link_outcome::crc_error) == link_event::none);
  CHECK(h.record(link_outcome::timeout) == link_event::none);
  CHECK(h.record(link_outcome::ok) == link_event::none);
  CHECK(h.counters().consecutive_failures == 0);
  CHECK(h.record(link_outcome::invalid) == link_event::none);
  CHECK(h.record(link_outcome::crc_error) == link_event::none);
  CHECK(h.record(link_outcome::timeout) == link_event::lost);
  CHECK(h.lost());
  CHECK(h.record(link_outcome::timeout) == link_event::none);  // reported once
  // one success, a failure: not restored yet
  CHECK(h.record(link_outcome::ok) == link_event::none);
  CHECK(h.record(link_outcome::crc_error) == link_event::none);
  CHECK(h.record(link_outcome::ok) == link_event::none);
  CHECK(h.record(link_outcome::alarm) == link_event::restored);  // an alarm frame is a success
  const link_counters& c = h.counters();
  CHECK(c.frames == 13);
  CHECK(c.good == 6);
  CHECK(c.alarms == 1);
  CHECK(c.crc_errors == 3);
  CHECK(c.timeouts == 3);
  CHECK(c.invalid == 1);
  CHECK(c.failures() == 7);
  CHECK(c.losses == 1);
  CHECK(c.consecutive_successes == 2);
}

TEST_CASE("thresholds of 0 act as 1") {
  // at run time: a constant configuration may be folded while compiling (the branch uncounted)
  const auto zero = testutil::at_run_time(std::uint16_t{0});
  link_health h({zero, zero});
  CHECK(h.record(link_outcome::ok) == link_event::restored);
  CHECK(h.record(link_outcome::crc_error) == link_event::lost);
  CHECK(h.record(link_outcome::alarm) == link_event::restored);
}

TEST_CASE("classify: the library's error codes and decode results") {
  CHECK(classify(errc::ok) == link_outcome::ok);
  CHECK(classify(errc::crc_mismatch) == link_outcome::crc_error);
  CHECK(classify(errc::truncated) == link_outcome::timeout);
  CHECK(classify(errc::no_frame) == link_outcome::timeout);
  CHECK(classify(errc::biss_no_ack) == link_outcome::timeout);
  CHECK(classify(errc::biss_no_start) == link_outcome::timeout);
  CHECK(classify(errc::tformat_parity) == link_outcome::invalid);
  CHECK(classify(errc::tformat_communication_alarm) == link_outcome::invalid);
  CHECK(classify(errc::reserved_bits) == link_outcome::invalid);
  CHECK(classify(decode_result<int>::complete(1, 1)) == link_outcome::ok);
  CHECK(classify(decode_result<int>(need_input{3})) == link_outcome::timeout);
  CHECK(classify(decode_result<int>(decode_failure{errc::crc_mismatch, 1})) ==
        link_outcome::crc_error);
  CHECK(classify(decode_result<int, input_unit::bits>(decode_failure{errc::biss_no_ack, 64})) ==
        link_outcome::timeout);
  link_health h({1, 1});
  CHECK(h.record(errc::ok) == link_event::restored);
  CHECK(h.record(errc::tformat_cf_mismatch) == link_event::lost);
  CHECK(h.counters().invalid == 1);
}

TEST_CASE("clear_counters keeps the state and the run in progress") {
  link_health h({2, 2});
  (void)h.record(link_outcome::ok);
  (void)h.record(link_outcome::ok);
  (void)h.record(link_outcome::timeout);
  h.clear_counters();
  CHECK(h.counters().frames == 0);
  CHECK(h.counters().timeouts == 0);
  CHECK(h.counters().consecutive_failures == 1);
  CHECK(h.record(link_outcome::timeout) == link_event::lost);
}

TEST_CASE("the consecutive counts saturate instead of wrapping") {
  link_health h;
  for (int i = 0; i < 70000; ++i) {
    (void)h.record(link_outcome::crc_error);
  }
  CHECK(h.counters().consecutive_failures == 0xFFFF);
  CHECK(h.counters().crc_errors == 70000);
  CHECK(h.lost());
}

TEST_CASE("names") {
  CHECK(to_string(link_outcome::ok) == std::string("ok"));
  CHECK(to_string(link_outcome::alarm) == std::string("alarm"));
  CHECK(to_string(link_outcome::crc_error) == std::string("crc_error"));
  CHECK(to_string(link_outcome::timeout) == std::string("timeout"));
  CHECK(to_string(link_outcome::invalid) == std::string("invalid"));
  CHECK(to_string(static_cast<link_outcome>(9)) == std::string("unknown"));
  CHECK(to_string(link_state::up) == std::string("up"));
  CHECK(to_string(link_state::lost) == std::string("lost"));
}

TEST_CASE("the defaults: restored after three successes, lost after three failures") {
  link_health h;
  CHECK(h.record(link_outcome::ok) == link_event::none);
  CHECK(h.record(link_outcome::ok) == link_event::none);
  CHECK(h.record(link_outcome::ok) == link_event::restored);
  CHECK(h.record(link_outcome::timeout) == link_event::none);
  CHECK(h.record(link_outcome::timeout) == link_event::none);
  CHECK(h.record(link_outcome::timeout) == link_event::lost);
  const link_config c;
  CHECK(c.lose_after == 3);
  CHECK(c.restore_after == 3);
}

TEST_CASE("the enumerators' numbers are part of the interface") {
  // firmware logs outcomes, states and events as integers (the meter's expectations are such
  // numbers), so they are fixed here as the header states them
  CHECK(static_cast<int>(link_outcome::ok) == 0);
  CHECK(static_cast<int>(link_outcome::alarm) == 1);
  CHECK(static_cast<int>(link_outcome::crc_error) == 2);
  CHECK(static_cast<int>(link_outcome::timeout) == 3);
  CHECK(static_cast<int>(link_outcome::invalid) == 4);
  CHECK(static_cast<int>(link_state::up) == 0);
  CHECK(static_cast<int>(link_state::lost) == 1);
  CHECK(static_cast<int>(link_event::none) == 0);
  CHECK(static_cast<int>(link_event::lost) == 1);
  CHECK(static_cast<int>(link_event::restored) == 2);
}
