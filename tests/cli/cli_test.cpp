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
  // 0x8776, and its wire bytes, low byte first: 76 87
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":34678,\"wire\":\"7687\"}\n");
  CHECK(r.status == 0);
  r = run("crc modbus 313233343536373839");
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":19255,\"wire\":\"374b\"}\n");  // 0x4B37
  r = run("crc modbus '0x31 0x32 0x33 0x34 0x35 0x36 0x37 0x38 0x39'");
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":19255,\"wire\":\"374b\"}\n");
  r = run("crc tformat '02 20 b4'");
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":150}\n");  // 0x02 ^ 0x20 ^ 0xB4
  // x^6 mod (x^6 + x + 1) = x + 1 = 000011, inverted 111100
  r = run("crc biss6 1");
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":60}\n");
  // x^4 mod (x^4 + x + 1) = x + 1 = 0011, inverted 1100
  r = run("crc biss4 1");
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":12}\n");
  // "123456789" as bits, first bit first: BiSS CRC6 0x2E, CRC4 0x1 (independent reference)
  const std::string bits =
      "001100010011001000110011001101000011010100110110001101110011100000111001";
  r = run("crc biss6 " + bits);
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":46}\n");
  r = run("crc biss4 " + bits);
  CHECK_JSON(r.out, "{\"ok\":true,\"crc\":1}\n");
  CHECK(r.status == 0);
}

TEST_CASE("crc: invalid inputs are reported with a code and exit status 1") {
  auto r = run("crc modbus 0g");
  CHECK_JSON(r.out, "{\"ok\":false,\"error\":\"invalid_hex\"}\n");
  CHECK(r.status == 1);
  r = run("crc modbus 123");
  CHECK_JSON(r.out, "{\"ok\":false,\"error\":\"invalid_hex\"}\n");
  CHECK(r.status == 1);
  r = run("crc biss6 0120");
  CHECK_JSON(r.out, "{\"ok\":false,\"error\":\"invalid_bits\"}\n");
  CHECK(r.status == 1);
  r = run("crc tformat ''");
  CHECK_JSON(r.out, "{\"ok\":false,\"error\":\"empty_input\"}\n");
  CHECK(r.status == 1);
}

TEST_CASE("stdin: one input per line, blank lines skipped, status 1 if any is invalid") {
  auto r = run("crc modbus -", "313233343536373839\\n\\n11 03 00 6B 00 03\\r\\n");
  CHECK_JSON(r.out,
             "{\"ok\":true,\"crc\":19255,\"wire\":\"374b\"}\n{\"ok\":true,\"crc\":34678,\"wire\":"
             "\"7687\"}\n");
  CHECK(r.status == 0);
  r = run("crc biss4 -", "1\\nxyz\\n1\\n");
  CHECK_JSON(r.out,
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
  CHECK_FIELDS(v.out, "{\"ok\":true}");
  int status = -1;
  CHECK(testcli::run_as_is("version", &status).find("motionbus ") == 0);
  CHECK(status == 0);
}

TEST_CASE("monitor and capture check their options before they open a port or a recording") {
  // An option out of its range is a usage error (status 2, nothing on stdout) that names the
  // option, even where the port or the file could not be opened: nothing is opened first.
  for (const char* args : {"monitor tformat --device /nonexistent/port --gap-us 0",
                           "monitor modbus --device /nonexistent/port --gap-us 60000001",
                           "decode tformat capture /nonexistent.vcd --line line --gap-us 0",
                           "decode modbus capture /nonexistent.vcd --line line --baud 4000001"}) {
    CAPTURE(args);
    int status = -1;
    const std::string err = testcli::run_stderr(args, &status);
    CHECK(status == 2);
    CHECK(err.find(std::string(args).find("gap-us") != std::string::npos ? "--gap-us" : "--baud") !=
          std::string::npos);
    CHECK(run(args).out.empty());
  }
  // the listing names each capture's recording
  const std::string top = testcli::run_as_is("--help");
  for (const char* line : {"decode modbus capture <file>", "decode tformat capture <file>",
                           "decode biss capture <file>", "monitor tformat"}) {
    CAPTURE(line);
    CHECK(top.find(line) != std::string::npos);
  }
}

TEST_CASE("text output: hex where engineers think in hex, failures with their evidence") {
  int status = -1;
  CHECK(testcli::run_as_is("decode tformat response 1a2045230111341200c0aa", &status) ==
        "ok  data_id=3 cf=0x1A sf=0x20 ea0=0 ea1=1 ca0=0 ca1=0 abs=74565 abm=4660 enid=0x11 "
        "almc=0xC0 alarms=\"BE battery error, BA battery alarm\" crc=0xAA\n");
  CHECK(status == 0);
  CHECK(testcli::run_as_is("decode modbus request 1103006B00037688", &status) ==
        "FAIL crc_mismatch  expected=0x8776 received=0x8876\n");
  CHECK(status == 1);
  CHECK(testcli::run_as_is("encode modbus request --function 3 --slave 17 --address 107 "
                           "--quantity 3") == "ok  hex=[11 03 00 6B 00 03 76 87]\n");
  CHECK(testcli::run_as_is("crc modbus '11 03 00 6B 00 03'") == "ok  crc=0x8776 wire=[76 87]\n");
}

TEST_CASE("--help at every level prints the options, defaults and allowed values") {
  int status = -1;
  const std::string top = testcli::run_as_is("--help", &status);
  CHECK(status == 0);
  for (const char* line :
       {"decode tformat response <input|->", "decode modbus request <input|->", "decode biss csd",
        "encode tformat request", "read sm-unit", "serve tformat-encoder", "crc biss6 <input|->"}) {
    CAPTURE(line);
    CHECK(top.find(line) != std::string::npos);
  }
  const std::string decode = testcli::run_as_is("decode --help", &status);
  CHECK(status == 0);
  CHECK(decode.find("T-format (Tamagawa") != std::string::npos);
  CHECK(decode.find("Modbus RTU") != std::string::npos);
  const std::string read = testcli::run_as_is("read tformat --help", &status);
  CHECK(status == 0);
  CHECK(read.find("--id HEX") != std::string::npos);
  CHECK(read.find("--baud BAUD=2500000") != std::string::npos);
  CHECK(read.find("--echo") != std::string::npos);
  const std::string modbus = testcli::run_as_is("read modbus --help", &status);
  CHECK(modbus.find("--parity P:{E,O,N}=E") != std::string::npos);
  CHECK(modbus.find("--function FC") != std::string::npos);
  const std::string monitor = testcli::run_as_is("monitor modbus --help", &status);
  CHECK(status == 0);
  for (const char* option : {"--device PORT", "--count N=0", "--duration S=0", "--baud BAUD=9600",
                             "--fc11 LAYOUT:{standard,sm}=standard", "--json"}) {
    CAPTURE(option);
    CHECK(monitor.find(option) != std::string::npos);
  }
  testcli::run_as_is("read modbus --parity X --slave 1 --function 3 --device /dev/null", &status);
  CHECK(status == 2);  // not an allowed value
}

TEST_CASE("--help says what each input is: hex bytes, or bits for BiSS-C") {
  int status = -1;
  for (const char* args : {"decode biss csd --help", "crc biss6 --help", "crc biss4 --help"}) {
    CAPTURE(args);
    const std::string help = testcli::run_as_is(args, &status);
    CHECK(status == 0);
    CHECK(help.find("0/1 bits") != std::string::npos);
    CHECK(help.find("hex bytes") == std::string::npos);
  }
  for (const char* args :
       {"decode modbus request --help", "decode tformat response --help", "crc modbus --help"}) {
    CAPTURE(args);
    const std::string help = testcli::run_as_is(args, &status);
    CHECK(help.find("hex bytes") != std::string::npos);
    CHECK(help.find("0/1 bits") == std::string::npos);
  }
  // and takes what it says
  CHECK(run("decode biss csd 000110000000000000001111000100100000011111110").status == 0);
}

TEST_CASE("--help shows each number's range, written once where the option is bound") {
  const std::string help = testcli::run_as_is("encode modbus request --help");
  CHECK(help.find("Modbus function code (decimal or 0x..) (1..127)") != std::string::npos);
  CHECK(help.find("(0..65535)") != std::string::npos);  // --address, --quantity
  const std::string gateway = testcli::run_as_is("gateway --help");
  CHECK(gateway.find("client connections at once; one more is closed at once (1..8)") !=
        std::string::npos);
}
