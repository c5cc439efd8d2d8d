// Modbus through the CLI. Frames are the Modbus specification's examples with CRCs computed by
// an independent bitwise CRC-16/MODBUS (Modbus over Serial Line V1.02 §6.2.2).
#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "run_cli.hpp"

namespace {

std::string cli(const std::string& args, int* status = nullptr) {
  return testcli::run(args, status);
}

}  // namespace

TEST_CASE("decode modbus request: fields of an RTU ADU") {
  CHECK_JSON(
      cli("decode modbus request 1103006B00037687"),
      "{\"ok\":true,\"slave\":17,\"function\":3,\"address\":107,\"quantity\":3,\"crc\":34678}\n");
  CHECK_JSON(
      cli("decode modbus request 110f0013000a02cd01bf0b"),
      "{\"ok\":true,\"slave\":17,\"function\":15,\"address\":19,\"quantity\":10,\"byte_count\":2,"
      "\"values\":[1,0,1,1,0,0,1,1,1,0],\"crc\":3007}\n");
  CHECK_JSON(
      cli("decode modbus request 01100001000204000a01029230"),
      "{\"ok\":true,\"slave\":1,\"function\":16,\"address\":1,\"quantity\":2,\"byte_count\":4,"
      "\"values\":[10,258],\"crc\":12434}\n");
  CHECK_JSON(
      cli("decode modbus request 0116000400f2002567ee"),
      "{\"ok\":true,\"slave\":1,\"function\":22,\"address\":4,\"and_mask\":242,\"or_mask\":37,"
      "\"crc\":61031}\n");
  int status = 0;
  CHECK_JSON(cli("decode modbus request 110500ac1234020c", &status),
             "{\"ok\":false,\"error\":\"illegal_coil_value\"}\n");
  CHECK(status == 1);
  CHECK_JSON(cli("decode modbus request 1103006B00037688"),
             "{\"ok\":false,\"error\":\"crc_mismatch\",\"expected\":34678,\"received\":34934}\n");
  // shorter than its function's length: truncated (FC03 requests are 8 bytes), not a CRC error
  CHECK_JSON(cli("decode modbus request 110300"),
             "{\"ok\":false,\"error\":\"truncated\",\"expected_bytes\":8,\"received_bytes\":3}\n");
  CHECK_JSON(cli("decode modbus request 1103006B00"),
             "{\"ok\":false,\"error\":\"truncated\",\"expected_bytes\":8,\"received_bytes\":5}\n");
}

TEST_CASE("decode modbus response: registers, bits, exceptions, FC11, checked against a request") {
  CHECK_JSON(cli("decode modbus response 110306022b00000064c8ba"),
             "{\"ok\":true,\"slave\":17,\"function\":3,\"byte_count\":6,\"values\":[555,0,100],"
             "\"crc\":47816}\n");
  CHECK_JSON(cli("decode modbus response 110306022b00000064c8ba --request 1103006B00037687"),
             "{\"ok\":true,\"slave\":17,\"function\":3,\"byte_count\":6,\"values\":[555,0,100],"
             "\"crc\":47816}\n");
  // 19 coils asked: the bits beyond 19 are not listed
  CHECK_JSON(cli("decode modbus response 110103cd6b054012 --request 1101001300138e92"),
             "{\"ok\":true,\"slave\":17,\"function\":1,\"byte_count\":3,"
             "\"values\":[1,0,1,1,0,0,1,1,1,1,0,1,0,1,1,0,1,0,1],\"crc\":4672}\n");
  CHECK_JSON(
      cli("decode modbus response 118302c134"),
      "{\"ok\":true,\"slave\":17,\"function\":3,\"exception\":2,\"exception_name\":\"illegal_"
      "data_address\",\"crc\":13505}\n");
  CHECK_JSON(cli("decode modbus response 01110100504d"),
             "{\"ok\":true,\"slave\":1,\"function\":17,\"data\":\"0100\",\"crc\":19792}\n");
  // FC11 without its request: the standard layout's byte count is checked (250, two present)
  int fc11_status = 0;
  CHECK_JSON(cli("decode modbus response 1111FAB4FFCA4E", &fc11_status),
             "{\"ok\":false,\"error\":\"byte_count_mismatch\"}\n");
  CHECK(fc11_status == 1);
  // the SM unit's layout: two version bytes, no count (SM unit guideline §11)
  CHECK_JSON(cli("decode modbus response 0111020310BC --fc11 sm"),
             "{\"ok\":true,\"slave\":1,\"function\":17,\"version_upper\":2,\"version_lower\":3,"
             "\"version\":\"2.0.3\",\"crc\":48144}\n");
  CHECK_JSON(cli("decode modbus response 0111020310BC"),
             "{\"ok\":false,\"error\":\"byte_count_mismatch\"}\n");
  CHECK_JSON(cli("decode modbus response 0111020310BC --fc11 sm --request 0111C02C"),
             "{\"ok\":true,\"slave\":1,\"function\":17,\"version_upper\":2,\"version_lower\":3,"
             "\"version\":\"2.0.3\",\"crc\":48144}\n");
  cli("decode modbus response 0111020310BC --fc11 nine", &fc11_status);
  CHECK(fc11_status == 2);
  // FC08 sub-function 00 echoes any even number of bytes; an odd number is refused
  CHECK_JSON(cli("decode modbus response 01080000A53712349672"),
             "{\"ok\":true,\"slave\":1,\"function\":8,\"data\":\"0000a5371234\",\"crc\":29334}\n");
  // the response to another request
  CHECK_JSON(cli("decode modbus response 110103cd6b054012 --request 1103006B00037687"),
             "{\"ok\":false,\"error\":\"response_mismatch\",\"expected\":3,\"received\":1}\n");
  int status = 0;
  cli("decode modbus response 110306022b00000064c8ba --request zz", &status);
  CHECK(status == 2);
}

TEST_CASE("decode modbus response in text: exceptions by name, registers, CRC in hex") {
  CHECK(testcli::run_as_is("decode modbus response 118302c134") ==
        "ok  slave=17 function=0x03 exception=0x02 exception_name=illegal_data_address "
        "crc=0x34C1\n");
  CHECK(testcli::run_as_is("decode modbus response 110306022b00000064c8ba --request "
                           "1103006b00037687") ==
        "ok  slave=17 function=0x03 byte_count=6 values=555,0,100 crc=0xBAC8\n");
}

TEST_CASE("encode modbus request: RTU ADU as hex") {
  CHECK_JSON(cli("encode modbus request --function 3 --slave 17 --address 107 --quantity 3"),
             "{\"ok\":true,\"hex\":\"1103006b00037687\"}\n");
  CHECK_JSON(cli("encode modbus request --function 0x10 --slave 1 --address 1 --values 10,258"),
             "{\"ok\":true,\"hex\":\"01100001000204000a01029230\"}\n");
  CHECK_JSON(cli("encode modbus request --function 15 --slave 17 --address 19 --values "
                 "1,0,1,1,0,0,1,1,1,0"),
             "{\"ok\":true,\"hex\":\"110f0013000a02cd01bf0b\"}\n");
  CHECK_JSON(cli("encode modbus request --function 0x11 --slave 1"),
             "{\"ok\":true,\"hex\":\"0111c02c\"}\n");
  int status = 0;
  // what the library's builders refuse is a usage error that names the library's code
  CHECK(cli("encode modbus request --function 3 --slave 17 --quantity 126", &status).empty());
  CHECK(status == 2);
  CHECK(testcli::run_stderr("encode modbus request --function 3 --slave 17 --quantity 126")
            .find("illegal_quantity") != std::string::npos);
  CHECK(cli("encode modbus request --function 3 --slave 248", &status).empty());
  CHECK(status == 2);
  CHECK(
      testcli::run_stderr("encode modbus request --function 3 --slave 248").find("slave_address") !=
      std::string::npos);
  cli("encode modbus request --function 3", &status);
  CHECK(status == 2);
  cli("encode modbus request --function 3 --slave 1 --values x", &status);
  CHECK(status == 2);
  // --function and --slave are numbers in their ranges, checked as the options are parsed
  for (const char* args :
       {"encode modbus request --function 0 --slave 1",
        "encode modbus request --function 0x80 --slave 1",
        "encode modbus request --function three --slave 1", "encode modbus request --slave 1",
        "encode modbus request --function 3 --slave 256"}) {
    CAPTURE(args);
    CHECK(cli(args, &status).empty());
    CHECK(status == 2);
    const std::string err = testcli::run_stderr(args);
    CHECK(err.find(std::string(args).find("--slave 256") != std::string::npos
                       ? "--slave"
                       : "--function") != std::string::npos);
  }
}

TEST_CASE("encode modbus request: a write needs its values, a coil is on or off") {
  int status = 0;
  // FC06 without --values would write 0 to register 0
  CHECK(cli("encode modbus request --function 6 --slave 1", &status).empty());
  CHECK(status == 2);
  CHECK(
      testcli::run_stderr("encode modbus request --function 6 --slave 1").find("needs --values") !=
      std::string::npos);
  for (const char* args :
       {"--function 5 --slave 1", "--function 5 --slave 1 --values 2",
        "--function 5 --slave 1 --values yes", "--function 5 --slave 1 --values on,off",
        "--function 6 --slave 1 --values 1,2", "--function 15 --slave 1",
        "--function 15 --slave 1 --values on,2", "--function 16 --slave 1",
        "--function 0x16 --slave 1 --values 1", "--function 23 --slave 1 --quantity 2",
        "--function 3 --slave 1 --values 5", "--function 3 --slave 1 --data 00"}) {
    CAPTURE(args);
    CHECK(cli(std::string("encode modbus request ") + args, &status).empty());
    CHECK(status == 2);
  }
  // a coil is on (FF00) or off (0000): on/off or 1/0 (Modbus Application Protocol §6.5)
  CHECK_JSON(cli("encode modbus request --function 5 --slave 1 --address 172 --values on"),
             "{\"ok\":true,\"hex\":\"010500acff004c1b\"}\n");
  CHECK_JSON(cli("encode modbus request --function 5 --slave 1 --address 172 --values 1"),
             "{\"ok\":true,\"hex\":\"010500acff004c1b\"}\n");
  CHECK_JSON(cli("encode modbus request --function 5 --slave 1 --address 172 --values OFF"),
             "{\"ok\":true,\"hex\":\"010500ac00000deb\"}\n");
  CHECK_JSON(cli("encode modbus request --function 15 --slave 17 --address 19 --values "
                 "on,off,on,on,off,off,1,1,1,0"),
             "{\"ok\":true,\"hex\":\"110f0013000a02cd01bf0b\"}\n");
  CHECK_JSON(cli("encode modbus request --function 6 --slave 17 --address 1 --values 3"),
             "{\"ok\":true,\"hex\":\"1106000100039a9b\"}\n");
}

TEST_CASE("read modbus: refused arguments send nothing; a write needs its values") {
  testcli::canned_device device({0x01, 0x06, 0x00, 0x00, 0x00, 0x00, 0x89, 0xCA});
  const std::string dev = " --timeout-ms 300 --device '" + device.path() + "'";
  for (const char* args : {"--function 6 --slave 1", "--function 5 --slave 1 --values 2",
                           "--function 3 --slave 248", "--function 3 --slave 1 --quantity 126"}) {
    CAPTURE(args);
    int status = 0;
    CHECK(cli(std::string("read modbus ") + args + dev, &status).empty());
    CHECK(status == 2);
  }
  CHECK(device.received().empty());
}

TEST_CASE("read modbus: an exception response fails the transaction (exit status 1)") {
  testcli::canned_device device({0x11, 0x83, 0x02, 0xC1, 0x34});
  int status = 0;
  CHECK_JSON(cli("read modbus --slave 17 --function 3 --address 107 --quantity 3 --timeout-ms 500 "
                 "--device '" +
                     device.path() + "'",
                 &status),
             "{\"ok\":false,\"error\":\"exception\",\"slave\":17,\"function\":3,\"exception\":2,"
             "\"exception_name\":\"illegal_data_address\",\"crc\":13505}\n");
  CHECK(status == 1);
  const std::vector<std::uint8_t> request = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87};
  CHECK(device.received() == request);
}

TEST_CASE("a truncated response is reported as truncated, not as a CRC mismatch") {
  // FC03, byte count 6: 11 bytes; 7 present
  CHECK_JSON(cli("decode modbus response 110306022b0000"),
             "{\"ok\":false,\"error\":\"truncated\",\"expected_bytes\":11,\"received_bytes\":7}\n");
  CHECK_JSON(cli("decode modbus response 110306022b0000 --request 1103006B00037687"),
             "{\"ok\":false,\"error\":\"truncated\",\"expected_bytes\":11,\"received_bytes\":7}\n");
  CHECK_JSON(cli("decode modbus response 1183"),
             "{\"ok\":false,\"error\":\"truncated\","
             "\"expected_bytes\":5,\"received_bytes\":2}\n");
  // a whole frame with a bad CRC is still a CRC mismatch
  CHECK_JSON(cli("decode modbus response 110306022b00000064c8bb"),
             "{\"ok\":false,\"error\":\"crc_mismatch\",\"expected\":47816,\"received\":48072}\n");
  // on the line: the device stops after 7 of 11 bytes
  testcli::canned_device device({0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00});
  int status = 0;
  CHECK_JSON(cli("read modbus --slave 17 --function 3 --address 107 --quantity 3 --timeout-ms 500 "
                 "--device '" +
                     device.path() + "'",
                 &status),
             "{\"ok\":false,\"error\":\"truncated\"}\n");
  CHECK(status == 1);
}
