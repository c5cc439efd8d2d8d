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
