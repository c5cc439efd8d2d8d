// The TS5700N8500 profile: reset and write-then-verify plans built at run time (the static
// suite builds them at compile time), and the alarm table's neutral row. The emulator is in
// ts5700n8500_emulator_test.cpp.
#include "motionbus/devices/ts5700n8500.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using namespace motionbus;
namespace ts = motionbus::devices::ts5700n8500;
namespace tf = motionbus::tformat;

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
}

TEST_CASE("alarm table: an undefined ALMC bit pattern has the table's first row") {
  // the caller passes single bits; anything else gets the first row, not a read past the end
  CHECK(&ts::info(static_cast<tf::almc_bit>(0x03)) == &ts::alarm_table[0]);
}

TEST_CASE("TS5700N8500: bit time of a bit rate (0 for none), page 6 and past 7 refused") {
  volatile std::uint32_t none = 0;  // run time, not a constant initialiser
  CHECK(ts::bit_ns(none) == 0U);
  volatile std::uint32_t rate = 2500000;
  CHECK(ts::bit_ns(rate) == 400U);
  volatile std::uint8_t page = 6;
  CHECK(ts::page_change_plan(page).error() == errc::out_of_range);
  page = 8;
  CHECK(ts::page_change_plan(page).error() == errc::out_of_range);
  page = 7;
  CHECK(ts::page_change_plan(page).ok());
}

TEST_CASE("TS5700N8500: timing and page 7 figures as the specification gives them") {
  // §8.1: the data frame starts "at 3 μs (typ.) after receiving the Delimiter signal"
  CHECK(ts::response_delay_ns == 3000U);
  // §5.4, Note 2: power-on standby 1 s with the external battery, 1.5 s without
  CHECK(ts::power_on_standby_us == 1500000U);
  // §7.2, §7.3: page 7 address 4 the over-heat threshold, address 5 the temperature; §7.2.2:
  // 00 turns over-heat detection off
  CHECK(ts::temperature_page == 7);
  CHECK(ts::overheat_address == 4);
  CHECK(ts::temperature_address == 5);
  CHECK(ts::overheat_off == 0x00);
  CHECK(!ts::decode_overheat_threshold(ts::overheat_off).enabled);
}

TEST_CASE("TS5700N8500: over-heat thresholds from 1 to 127 °C encode, 0 and 128 do not") {
  // §7.2.1: the byte is the temperature + 128; §7.2.4's table runs from +1 °C to +127 °C and
  // §7.4 ② asks for 1 °C or more
  CHECK(ts::encode_overheat_threshold(1).value() == 0x81);
  CHECK(ts::encode_overheat_threshold(127).value() == 0xFF);
  CHECK(ts::encode_overheat_threshold(0).error() == errc::out_of_range);
  CHECK(ts::encode_overheat_threshold(128).error() == errc::out_of_range);
  CHECK(ts::decode_overheat_threshold(0x81).celsius == 1);
  CHECK(ts::decode_overheat_threshold(0xFF).celsius == 127);
}

TEST_CASE("TS5700N8500: records default-constructed and the off threshold hold no figure") {
  // plan_step and overheat_setting as a caller declares them before filling them in
  const ts::plan_step step{};
  CHECK(step.size == 0);
  CHECK(step.view().empty());
  CHECK(step.wait_after_us == 0U);
  CHECK(!step.verify);
  CHECK(step.expected_edf == 0);
  const ts::overheat_setting setting{};
  CHECK(!setting.enabled);
  CHECK(setting.celsius == 0);
  // a threshold with bit 7 clear decodes as that same record: off, no temperature (§7.2.2: the
  // other bits are "X", so no figure can be read from them)
  for (const std::uint8_t off : {std::uint8_t{0x00}, std::uint8_t{0x5A}, std::uint8_t{0x7F}}) {
    CAPTURE(off);
    CHECK(!ts::decode_overheat_threshold(off).enabled);
    CHECK(ts::decode_overheat_threshold(off).celsius == 0);
  }
}

TEST_CASE("TS5700N8500: every user page 0 to 5 is writable; the read-back step waits nothing") {
  // §6.1.1: the effective pages are 0~5 (and page 7 for the temperature functions)
  for (std::uint8_t page = 0; page <= 5; ++page) {
    CAPTURE(page);
    CHECK(ts::writable(page, 0));
    CHECK(ts::writable(page, 126));
    CHECK(!ts::writable(page, 127));  // the page select
    const auto p = ts::write_verify_plan(page, 126, 0x5A);
    REQUIRE(p.ok());
    // the steps before the read wait for the EEPROM (18 ms max., §9.1 note); the read's
    // response arrives within its own transaction (§9.1: 3 μs after the request), so nothing
    // follows it to wait for, and only it verifies
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(p->steps[i].wait_after_us == ts::eeprom_write_us);
      CHECK(!p->steps[i].verify);
      CHECK(p->steps[i].expected_edf == 0);
    }
    CHECK(p->steps[3].wait_after_us == 0U);
  }
}

TEST_CASE("TS5700N8500: the latch rules' numbers (interface: the Python binding's LatchRule)") {
  // python/src/ts5700n8500.cpp binds LatchRule as none 0, latched 1, by_speed 2
  CHECK(static_cast<int>(ts::latch_rule::none) == 0);
  CHECK(static_cast<int>(ts::latch_rule::latched) == 1);
  CHECK(static_cast<int>(ts::latch_rule::by_speed) == 2);
}
