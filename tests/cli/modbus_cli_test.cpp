// Modbus through the CLI. Frames are the Modbus specification's examples with CRCs computed by
// an independent bitwise CRC-16/MODBUS (Modbus over Serial Line V1.02 §6.2.2).
#include <doctest/doctest.h>

#include <string>

#include "run_cli.hpp"

namespace {

std::string cli(const std::string& args, int* status = nullptr) {
  return testcli::run(args, status);
}

}  // namespace

TEST_CASE("decode modbus request: fields of an RTU ADU") {
  CHECK(cli("decode modbus request 1103006B00037687") ==
        "{\"ok\":true,\"slave\":17,\"function\":3,\"address\":107,\"quantity\":3,\"crc\":34678}\n");
  CHECK(cli("decode modbus request 110f0013000a02cd01bf0b") ==
        "{\"ok\":true,\"slave\":17,\"function\":15,\"address\":19,\"quantity\":10,\"byte_count\":2,"
        "\"values\":[1,0,1,1,0,0,1,1,1,0],\"crc\":3007}\n");
  CHECK(cli("decode modbus request 01100001000204000a01029230") ==
        "{\"ok\":true,\"slave\":1,\"function\":16,\"address\":1,\"quantity\":2,\"byte_count\":4,"
        "\"values\":[10,258],\"crc\":12434}\n");
  CHECK(cli("decode modbus request 0116000400f2002567ee") ==
        "{\"ok\":true,\"slave\":1,\"function\":22,\"address\":4,\"and_mask\":242,\"or_mask\":37,"
        "\"crc\":61031}\n");
  int status = 0;
  CHECK(cli("decode modbus request 110500ac1234020c", &status) ==
        "{\"ok\":false,\"error\":\"illegal_coil_value\"}\n");
  CHECK(status == 1);
  CHECK(cli("decode modbus request 1103006B00037688") ==
        "{\"ok\":false,\"error\":\"crc_mismatch\",\"expected\":34678,\"received\":34934}\n");
  CHECK(cli("decode modbus request 110300") == "{\"ok\":false,\"error\":\"pdu_length\"}\n");
}

TEST_CASE("decode modbus response: registers, bits, exceptions, FC11, checked against a request") {
  CHECK(cli("decode modbus response 110306022b00000064c8ba") ==
        "{\"ok\":true,\"slave\":17,\"function\":3,\"byte_count\":6,\"values\":[555,0,100],"
        "\"crc\":47816}\n");
  CHECK(cli("decode modbus response 110306022b00000064c8ba --request 1103006B00037687") ==
        "{\"ok\":true,\"slave\":17,\"function\":3,\"byte_count\":6,\"values\":[555,0,100],"
        "\"crc\":47816}\n");
  // 19 coils asked: the bits beyond 19 are not listed
  CHECK(cli("decode modbus response 110103cd6b054012 --request 1101001300138e92") ==
        "{\"ok\":true,\"slave\":17,\"function\":1,\"byte_count\":3,"
        "\"values\":[1,0,1,1,0,0,1,1,1,1,0,1,0,1,1,0,1,0,1],\"crc\":4672}\n");
  CHECK(cli("decode modbus response 118302c134") ==
        "{\"ok\":true,\"slave\":17,\"function\":3,\"exception\":2,\"exception_name\":\"illegal_"
        "data_address\",\"crc\":13505}\n");
  CHECK(cli("decode modbus response 01110100504d") ==
        "{\"ok\":true,\"slave\":1,\"function\":17,\"data\":\"0100\",\"crc\":19792}\n");
  // FC11 without its request: the standard layout's byte count is checked (250, two present)
  int fc11_status = 0;
  CHECK(cli("decode modbus response 1111FAB4FFCA4E", &fc11_status) ==
        "{\"ok\":false,\"error\":\"byte_count_mismatch\"}\n");
  CHECK(fc11_status == 1);
  // the SM unit's layout: two version bytes, no count (SM unit guideline §11)
  CHECK(cli("decode modbus response 0111020310BC --fc11 sm") ==
        "{\"ok\":true,\"slave\":1,\"function\":17,\"version_upper\":2,\"version_lower\":3,"
        "\"version\":\"2.0.3\",\"crc\":48144}\n");
  CHECK(cli("decode modbus response 0111020310BC") ==
        "{\"ok\":false,\"error\":\"byte_count_mismatch\"}\n");
  CHECK(cli("decode modbus response 0111020310BC --fc11 sm --request 0111C02C") ==
        "{\"ok\":true,\"slave\":1,\"function\":17,\"version_upper\":2,\"version_lower\":3,"
        "\"version\":\"2.0.3\",\"crc\":48144}\n");
  cli("decode modbus response 0111020310BC --fc11 nine", &fc11_status);
  CHECK(fc11_status == 2);
  // FC08 sub-function 00 echoes any even number of bytes; an odd number is refused
  CHECK(cli("decode modbus response 01080000A53712349672") ==
        "{\"ok\":true,\"slave\":1,\"function\":8,\"data\":\"0000a5371234\",\"crc\":29334}\n");
  // the response to another request
  CHECK(cli("decode modbus response 110103cd6b054012 --request 1103006B00037687") ==
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
  CHECK(cli("encode modbus request --function 3 --slave 17 --address 107 --quantity 3") ==
        "{\"ok\":true,\"hex\":\"1103006b00037687\"}\n");
  CHECK(cli("encode modbus request --function 0x10 --slave 1 --address 1 --values 10,258") ==
        "{\"ok\":true,\"hex\":\"01100001000204000a01029230\"}\n");
  CHECK(cli("encode modbus request --function 15 --slave 17 --address 19 --values "
            "1,0,1,1,0,0,1,1,1,0") == "{\"ok\":true,\"hex\":\"110f0013000a02cd01bf0b\"}\n");
  CHECK(cli("encode modbus request --function 0x11 --slave 1") ==
        "{\"ok\":true,\"hex\":\"0111c02c\"}\n");
  int status = 0;
  CHECK(cli("encode modbus request --function 3 --slave 17 --quantity 126", &status) ==
        "{\"ok\":false,\"error\":\"illegal_quantity\"}\n");
  CHECK(status == 1);
  CHECK(cli("encode modbus request --function 3 --slave 248") ==
        "{\"ok\":false,\"error\":\"slave_address\"}\n");
  cli("encode modbus request --function 3", &status);
  CHECK(status == 2);
  cli("encode modbus request --function 3 --slave 1 --values x", &status);
  CHECK(status == 2);
}
