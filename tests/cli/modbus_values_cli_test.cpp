// `read modbus --type ... --word-order ...`: 32- and 64-bit values over registers in the CLI
// (modbus/values.hpp, docs/modbus.md section 9), against a canned device on a pseudo-terminal.
#include <doctest/doctest.h>

#include <motionbus/modbus/rtu.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "run_cli.hpp"

namespace {

std::vector<std::uint8_t> adu(std::uint8_t slave, const std::vector<std::uint8_t>& pdu) {
  std::uint8_t out[256] = {};
  const auto n =
      motionbus::modbus::encode_rtu(slave, motionbus::byte_view(pdu.data(), pdu.size()), out);
  REQUIRE(n.ok());
  return std::vector<std::uint8_t>(out, out + n.value());
}

}  // namespace

TEST_CASE("read modbus --type: a read asks for the values' registers and prints the values") {
  // 123456.0f as libmodbus's modbus_set_float_abcd writes it: BADC
  testcli::canned_device device(
      adu(1, {0x03, 0x08, 0xF1, 0x47, 0x00, 0x20, 0x80, 0xFF, 0x00, 0x00}));
  int status = 0;
  CHECK_FIELDS(
      testcli::run("read modbus --slave 1 --function 3 --address 0 --quantity 2 --type f32 "
                   "--word-order badc --timeout-ms 500 --device '" +
                       device.path() + "'",
                   &status),
      "{\"ok\":true,\"typed_values\":[123456.0,\"-inf\"]}");
  CHECK(status == 0);
  CHECK(device.received() == adu(1, {0x03, 0x00, 0x00, 0x00, 0x04}));
}

TEST_CASE("read modbus --type: 64-bit integers, default order abcd") {
  testcli::canned_device device(
      adu(1, {0x04, 0x08, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}));
  int status = 0;
  CHECK_FIELDS(testcli::run("read modbus --slave 1 --function 4 --type i64 --timeout-ms 500 "
                            "--device '" +
                                device.path() + "'",
                            &status),
               "{\"ok\":true,\"typed_values\":[-9223372036854775808]}");
  CHECK(device.received() == adu(1, {0x04, 0x00, 0x00, 0x00, 0x04}));
}

TEST_CASE("read modbus --type: a write sends the values' registers in the word order") {
  testcli::canned_device device(adu(1, {0x10, 0x00, 0x0A, 0x00, 0x04}));
  int status = 0;
  CHECK_FIELDS(testcli::run("read modbus --slave 1 --function 16 --address 10 --type u32 "
                            "--word-order cdab --values 305419896,4294967295 --timeout-ms 500 "
                            "--device '" +
                                device.path() + "'",
                            &status),
               "{\"ok\":true,\"function\":16,\"quantity\":4}");
  CHECK(device.received() == adu(1, {0x10, 0x00, 0x0A, 0x00, 0x04, 0x08, 0x56, 0x78, 0x12, 0x34,
                                     0xFF, 0xFF, 0xFF, 0xFF}));
}

TEST_CASE("read modbus --type: refused arguments send nothing, each with its reason") {
  testcli::canned_device device({0x01, 0x06, 0x00, 0x00, 0x00, 0x00, 0x89, 0xCA});
  const std::string dev = " --timeout-ms 300 --device '" + device.path() + "'";
  const std::pair<const char*, const char*> cases[] = {
      {"--function 3 --slave 1 --type f16", "--type takes u32"},
      {"--function 3 --slave 1 --word-order cdab", "--word-order is for --type"},
      {"--function 3 --slave 1 --type f32 --word-order abdc", "--word-order takes abcd"},
      {"--function 6 --slave 1 --type u32 --values 1", "--type is for FC 03, 04"},
      {"--function 16 --slave 1 --type u32", "needs --values"},
      {"--function 16 --slave 1 --type u32 --values 4294967296", "is no u32"},
      {"--function 16 --slave 1 --type u32 --values -1", "is no u32"},
      {"--function 16 --slave 1 --type i32 --values 2147483648", "is no i32"},
      {"--function 16 --slave 1 --type f32 --values 1e39", "is no f32"},
      {"--function 16 --slave 1 --type f64 --values 1.5x", "is no f64"},
      {"--function 16 --slave 1 --type i64 --values 1,,2", "is no i64"},
      {"--function 3 --slave 1 --type f64 --quantity 32", "the library refuses it"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.first);
    int status = 0;
    const std::string out = testcli::output_of(
        testcli::cli_command() + "read modbus " + c.first + dev + " 2>&1", &status);
    CHECK_MESSAGE(out.find(c.second) != std::string::npos, out);
    CHECK(status == 2);
  }
  CHECK(device.received().empty());
}
