// BiSS-C through the CLI: the decode/encode contract, with frames built here from
// docs/biss.md §5 (the CRC by long division) rather than by the library.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "../support/bit_strings.hpp"
#include "../support/reference_crc.hpp"
#include "run_cli.hpp"

namespace {

using testutil::as_ints;
using testutil::bits_of;

// idle, Ack, Start, CDS, 32-bit position, nE, nW, inverted CRC6 0x43 over position + nE + nW.
std::string absys_frame(std::size_t idle, std::size_t ack, bool cds, std::uint32_t pos, bool ne,
                        bool nw) {
  const std::string covered = bits_of(pos, 32) + (ne ? "1" : "0") + (nw ? "1" : "0");
  const std::uint32_t crc = ref::crc_of_bits({6, 0x03, 0, false, false, 0x3F}, as_ints(covered));
  return std::string(idle, '1') + std::string(ack, '0') + "1" + (cds ? "1" : "0") + covered +
         bits_of(crc, 6);
}

std::string crc_field(const std::string& frame) {
  return std::to_string(std::stoul(frame.substr(frame.size() - 6), nullptr, 2));
}

std::string hex_of(const std::string& bits) {
  std::string padded = bits + std::string((4U - bits.size() % 4U) % 4U, '0');
  std::string out;
  for (std::size_t i = 0; i < padded.size(); i += 4) {
    out.push_back("0123456789ABCDEF"[std::stoul(padded.substr(i, 4), nullptr, 2)]);
    if (i % 32U == 28U) {
      out.push_back(' ');
    }
  }
  return out;
}

}  // namespace

TEST_CASE("decode biss csd: bit strings and hex words, every field") {
  const std::string f = absys_frame(2, 3, true, 0x0001E240, true, false);
  int status = -1;
  CHECK_JSON(testcli::run("decode biss csd " + f, &status),
             "{\"ok\":true,\"position\":123456,\"ne\":1,\"nw\":0,\"cds\":1,\"crc\":" +
                 crc_field(f) + ",\"line_delay\":2,\"start\":5,\"ack_bits\":3}\n");
  CHECK(status == 0);
  CHECK_JSON(
      testcli::run("decode biss csd --hex '" + hex_of(f) + "' --bits " + std::to_string(f.size())),
      "{\"ok\":true,\"position\":123456,\"ne\":1,\"nw\":0,\"cds\":1,\"crc\":" + crc_field(f) +
          ",\"line_delay\":2,\"start\":5,\"ack_bits\":3}\n");
  // trailing samples after the CRC (hex padding, timeout) do not matter
  CHECK_FIELDS(testcli::run("decode biss csd --hex '" + hex_of(f + "0000000") + "'"),
               "{\"position\":123456}");
  const std::string g = absys_frame(0, 1, false, 0xFFFFFFFFU, false, true);
  CHECK_JSON(testcli::run("decode biss csd " + g),
             "{\"ok\":true,\"position\":4294967295,\"ne\":0,\"nw\":1,\"cds\":0,\"crc\":" +
                 crc_field(g) + ",\"line_delay\":0,\"start\":1,\"ack_bits\":1}\n");
}

TEST_CASE("decode biss csd: errors") {
  const std::string f = absys_frame(1, 2, false, 77, true, true);
  std::string bad = f;
  bad[10] = bad[10] == '1' ? '0' : '1';
  int status = 0;
  CHECK_JSON(testcli::run("decode biss csd " + bad, &status),
             "{\"ok\":false,\"error\":\"crc_mismatch\",\"expected\":21,\"received\":49}\n");
  CHECK(status == 1);
  CHECK_JSON(testcli::run("decode biss csd " + f.substr(0, f.size() - 1)),
             "{\"ok\":false,\"error\":\"truncated\"}\n");
  CHECK_JSON(testcli::run("decode biss csd 11111111111"), "{\"ok\":false,\"error\":\"no_ack\"}\n");
  CHECK_JSON(testcli::run("decode biss csd 1110000000000"),
             "{\"ok\":false,\"error\":\"no_start\"}\n");
  CHECK_JSON(testcli::run("decode biss csd 10x1"), "{\"ok\":false,\"error\":\"invalid_bits\"}\n");
  // the same frame read with the wrong data length fails its CRC
  CHECK_JSON(testcli::run("decode biss csd " + f + " --data-bits 30"),
             "{\"ok\":false,\"error\":\"crc_mismatch\",\"expected\":45,\"received\":60}\n");
}

TEST_CASE("decode biss csd: other layouts through --data-bits and the CRC options") {
  // 18-bit position, nE, nW, CRC5 0x25 start 3 not inverted (long division here)
  const std::string covered = bits_of(0x2ABCD, 18) + "10";
  const std::uint32_t crc = ref::crc_of_bits({5, 0x05, 3, false, false, 0}, as_ints(covered));
  const std::string f = "1100" + std::string("1") + "0" + covered + bits_of(crc, 5);
  CHECK_JSON(
      testcli::run("decode biss csd " + f +
                   " --data-bits 18 --crc-bits 5 --crc-poly 25 --crc-start 3 --no-crc-invert"),
      "{\"ok\":true,\"position\":175053,\"ne\":1,\"nw\":0,\"cds\":0,\"crc\":" +
          std::to_string(crc) + ",\"line_delay\":2,\"start\":4,\"ack_bits\":2}\n");
  // the polynomial without its x^5 term is the same polynomial
  CHECK_FIELDS(
      testcli::run("decode biss csd " + f +
                   " --data-bits 18 --crc-bits 5 --crc-poly 0x05 --crc-start 3 --no-crc-invert"),
      "{\"ok\":true,\"position\":175053}");
  int status = 0;
  testcli::run("decode biss csd " + f + " --crc-bits 5", &status);
  CHECK(status == 2);  // a width other than 6 needs its polynomial
}

TEST_CASE("decode and encode biss csd in text") {
  CHECK(testcli::run_as_is("encode biss csd --position 123456 --ack 3 --cds 1") ==
        "ok  bits=000110000000000000001111000100100000011111110\n");
  CHECK(testcli::run_as_is("decode biss csd 000110000000000000001111000100100000011111110") ==
        "ok  position=123456 ne=1 nw=1 cds=1 crc=0x3E line_delay=0 start=3 ack_bits=3\n");
  CHECK(testcli::run_as_is("decode biss csd 000110000000000000001111000100100000011111111") ==
        "FAIL crc_mismatch  expected=0x3E received=0x3F\n");
}

TEST_CASE("encode biss csd: the frame of the notes, and a round trip") {
  int status = -1;
  CHECK_JSON(testcli::run("encode biss csd --position 123456 --ack 3 --cds 1 --nw 0", &status),
             "{\"ok\":true,\"bits\":\"" + absys_frame(0, 3, true, 123456, true, false) + "\"}\n");
  CHECK(status == 0);
  CHECK_JSON(testcli::run("encode biss csd --position 7"),
             "{\"ok\":true,\"bits\":\"" + absys_frame(0, 1, false, 7, true, true) + "\"}\n");
  // the library's refusal is a usage error naming its code
  CHECK(testcli::run("encode biss csd --position 4294967296", &status).empty());
  CHECK(status == 2);
  CHECK(testcli::run_stderr("encode biss csd --position 4294967296").find("out_of_range") !=
        std::string::npos);
  const std::string out =
      testcli::run("encode biss csd --position 99 --ne 0 --ack 5 --line-delay 2");
  const auto lines = testcli::json_lines(out);
  REQUIRE(lines.size() == 1);
  REQUIRE(lines[0].contains("bits"));
  const std::string bits = lines[0]["bits"].get<std::string>().substr(0, 2 + 5 + 2 + 40);
  CHECK_FIELDS(testcli::run("decode biss csd " + bits),
               "{\"position\":99,\"ne\":0,\"nw\":1,\"cds\":0,\"line_delay\":2}");
}
