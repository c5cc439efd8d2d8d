// The device profiles' internals (detail::), apart from the API tests: refusals their public
// callers never reach with the arguments they pass.
#include <doctest/doctest.h>

#include <cstdint>

#include "../support/bytes.hpp"
#include "motionbus/devices/sm_unit.hpp"
#include "motionbus/devices/ts5700n8500.hpp"

using namespace motionbus;
using namespace testutil;
namespace sm = motionbus::devices::sm_unit;
namespace ts = motionbus::devices::ts5700n8500;
namespace tf = motionbus::tformat;

TEST_CASE("detail: the SM unit's password block builder refuses slave 248") {
  std::uint8_t out[256] = {};
  const mutable_byte_view o(out, sizeof out);
  CHECK(sm::detail::write_password_block(248, sm::holding::login, text("password"), o).error() ==
        errc::modbus_slave_address);
}

TEST_CASE("detail: a TS5700N8500 plan step is refused when the plan is full or the ID unknown") {
  ts::plan<1> one;
  CHECK(ts::detail::add_step(one, tf::data_id::read_abs, 0) == errc::ok);
  CHECK(ts::detail::add_step(one, tf::data_id::read_abs, 0) == errc::buffer_too_small);
  ts::plan<1> bad;
  CHECK(ts::detail::add_step(bad, static_cast<tf::data_id>(0x5), 0) ==
        errc::tformat_unknown_data_id);
}
