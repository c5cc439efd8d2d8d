// Modbus RTU timing (Modbus over Serial Line V1.02 §2.5.1.1): bits per character, t1.5 and
// t3.5 from the baud rate, the parity and the stop bits.
#include "motionbus/modbus/timing.hpp"

#include <doctest/doctest.h>

using namespace motionbus::modbus;

TEST_CASE("RTU timing: t1.5 and t3.5 from baud, parity and stop bits") {
  CHECK(bits_per_character(parity::even, 1) == 11);
  CHECK(bits_per_character(parity::none, 2) == 11);
  CHECK(bits_per_character(parity::none, 1) == 10);
  // 9600 8E1: one character = 11 bits = 1145.8 us; t3.5 = 4010.4 us, t1.5 = 1718.75 us
  CHECK(t35_us(9600) == 4011);
  CHECK(t15_us(9600) == 1719);
  CHECK(t35_us(19200) == 2006);
  CHECK(t35_us(38400) == 1750);  // fixed above 19200
  CHECK(t15_us(115200) == 750);
  CHECK(character_time_us(9600, parity::none, 1) == 1042);
  CHECK(character_time_us(0, parity::none, 1) == 0);
}

TEST_CASE("parity: none, even and odd are three values") {
  // the library's timing counts a parity bit alike for both; a caller that configures a port
  // tells them apart
  CHECK(parity::even != parity::odd);
  CHECK(parity::none != parity::even);
  CHECK(parity::none != parity::odd);
}

TEST_CASE("RTU timing: at 19200 baud t1.5 and t3.5 are computed; the fixed values only above") {
  // 19200 8E1: t1.5 = 1.5 x 11 bits = 859.4 us, t3.5 = 2005.2 us (Serial Line §2.5.1.1 fixes
  // 750 and 1750 us for rates above 19200)
  CHECK(t15_us(19200) == 860);
  CHECK(t35_us(19200) == 2006);
  CHECK(t15_us(19201) == 750);
  CHECK(t35_us(19201) == 1750);
}

TEST_CASE("parity's numbers: those the Python package's t15_us and t35_us pass") {
  // python/src/modbus.cpp casts its `parity` argument (0 none, 1 even, 2 odd) to the enumeration
  CHECK(static_cast<unsigned>(parity::none) == 0);
  CHECK(static_cast<unsigned>(parity::even) == 1);
  CHECK(static_cast<unsigned>(parity::odd) == 2);
}
