// The motionbus CLI contract: JSON per input, error codes, exit statuses 0/1/2, stdin mode.
// Expected CRCs come from published values (CRC-16/MODBUS check 0x4B37; the Modbus over Serial
// Line example 11 03 00 6B 00 03 -> 76 87) or from hand division (single-bit BiSS inputs).
#include <doctest/doctest.h>

#include <string>

#include "run_cli.hpp"

namespace {

struct run_result {
  std::string out;
  int status = -1;
};

run_result run(const std::string& args, const std::string& stdin_text = "") {
  run_result r;
  r.out = testcli::run(args, &r.status, stdin_text);
  return r;
}

}  // namespace

TEST_CASE("crc: published and hand-computed values") {
  auto r = run("crc modbus '11 03 00 6B 00 03'");
  CHECK(r.out == "{\"ok\":true,\"crc\":34678}\n");  // 0x8776: wire bytes 76 87
  CHECK(r.status == 0);
  r = run("crc modbus 313233343536373839");
  CHECK(r.out == "{\"ok\":true,\"crc\":19255}\n");  // 0x4B37
  r = run("crc modbus '0x31 0x32 0x33 0x34 0x35 0x36 0x37 0x38 0x39'");
  CHECK(r.out == "{\"ok\":true,\"crc\":19255}\n");
  r = run("crc tformat '02 20 b4'");
  CHECK(r.out == "{\"ok\":true,\"crc\":150}\n");  // 0x02 ^ 0x20 ^ 0xB4
  // x^6 mod (x^6 + x + 1) = x + 1 = 000011, inverted 111100
  r = run("crc biss6 1");
  CHECK(r.out == "{\"ok\":true,\"crc\":60}\n");
  // x^4 mod (x^4 + x + 1) = x + 1 = 0011, inverted 1100
  r = run("crc biss4 1");
  CHECK(r.out == "{\"ok\":true,\"crc\":12}\n");
  // "123456789" as bits, first bit first: BiSS CRC6 0x2E, CRC4 0x1 (independent reference)
  const std::string bits =
      "001100010011001000110011001101000011010100110110001101110011100000111001";
  r = run("crc biss6 " + bits);
  CHECK(r.out == "{\"ok\":true,\"crc\":46}\n");
  r = run("crc biss4 " + bits);
  CHECK(r.out == "{\"ok\":true,\"crc\":1}\n");
  CHECK(r.status == 0);
}

TEST_CASE("crc: invalid inputs are reported with a code and exit status 1") {
  auto r = run("crc modbus 0g");
  CHECK(r.out == "{\"ok\":false,\"error\":\"invalid_hex\"}\n");
  CHECK(r.status == 1);
  r = run("crc modbus 123");
  CHECK(r.out == "{\"ok\":false,\"error\":\"invalid_hex\"}\n");
  CHECK(r.status == 1);
  r = run("crc biss6 0120");
  CHECK(r.out == "{\"ok\":false,\"error\":\"invalid_bits\"}\n");
  CHECK(r.status == 1);
  r = run("crc tformat ''");
  CHECK(r.out == "{\"ok\":false,\"error\":\"empty_input\"}\n");
  CHECK(r.status == 1);
}

TEST_CASE("stdin: one input per line, blank lines skipped, status 1 if any is invalid") {
  auto r = run("crc modbus -", "313233343536373839\\n\\n11 03 00 6B 00 03\\r\\n");
  CHECK(r.out == "{\"ok\":true,\"crc\":19255}\n{\"ok\":true,\"crc\":34678}\n");
  CHECK(r.status == 0);
  r = run("crc biss4 -", "1\\nxyz\\n1\\n");
  CHECK(r.out ==
        "{\"ok\":true,\"crc\":12}\n{\"ok\":false,\"error\":\"invalid_bits\"}\n"
        "{\"ok\":true,\"crc\":12}\n");
  CHECK(r.status == 1);
}

TEST_CASE("usage errors exit with status 2 and print nothing on stdout") {
  for (const char* args :
       {"", "frobnicate", "crc", "crc crc32 00", "crc modbus", "crc modbus 00 11",
        "decode nosuch kind 00", "encode nosuch kind", "decode"}) {
    CAPTURE(args);
    const auto r = run(args);
    CHECK(r.status == 2);
    CHECK(r.out.empty());
  }
  const auto v = run("version");
  CHECK(v.status == 0);
  CHECK(v.out.find("\"ok\":true") != std::string::npos);
}
