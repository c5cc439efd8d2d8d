// FC14 Read File Record and FC15 Write File Record (Modbus Application Protocol V1.1b3 §6.14,
// §6.15): the spec's worked examples both ways, every kind of bad sub-request its own error and
// exception, the responses checked against their requests, and the server dispatch.
#include "motionbus/modbus/file_record.hpp"

#include "motionbus/modbus/framer.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/modbus.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/pdu_server.hpp"
#include "motionbus/modbus/server.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using testutil::bytes;
using testutil::output;
using testutil::view;

namespace {

// §6.14's example: file 4 records 1-2, file 3 records 9-10.
const bytes read_request = {0x14, 0x0E, 0x06, 0x00, 0x04, 0x00, 0x01, 0x00,
                            0x02, 0x06, 0x00, 0x03, 0x00, 0x09, 0x00, 0x02};
const bytes read_response = {0x14, 0x0C, 0x05, 0x06, 0x0D, 0xFE, 0x00,
                             0x20, 0x05, 0x06, 0x33, 0xCD, 0x00, 0x40};
// §6.15's example: file 4 records 7-9 := 06AF 04BE 100D.
const bytes write_request = {0x15, 0x0D, 0x06, 0x00, 0x04, 0x00, 0x07, 0x00,
                             0x03, 0x06, 0xAF, 0x04, 0xBE, 0x10, 0x0D};

errc request_error(const bytes& pdu) {
  const auto d = decode_file_record_request(view(pdu));
  return d.is_complete() ? errc::ok : d.error();
}

}  // namespace

TEST_CASE("file records: the spec's examples encode and decode") {
  std::uint8_t out[253] = {};
  const file_record reads[] = {{{}, 4, 1, 2}, {{}, 3, 9, 2}};
  CHECK(output(encode_read_file_record(reads, out), out) == read_request);
  const std::uint8_t values[] = {0x06, 0xAF, 0x04, 0xBE, 0x10, 0x0D};
  const file_record writes[] = {{byte_view(values), 4, 7, 3}};
  CHECK(output(encode_write_file_record(writes, out), out) == write_request);

  const auto q = decode_file_record_request(view(read_request));
  REQUIRE(q.is_complete());
  CHECK(q.consumed() == read_request.size());
  CHECK(q->count == 2);
  CHECK(file_record_at(q.value(), 1)->file == 3);
  CHECK(file_record_at(q.value(), 1)->record == 9);
  CHECK(file_record_at(q.value(), 1)->length == 2);
  CHECK(file_record_at(q.value(), 2).error() == errc::out_of_range);

  const auto r = decode_read_file_record_response(view(read_request), view(read_response));
  REQUIRE(r.is_complete());
  CHECK_FALSE(r->exception);
  REQUIRE(r->count == 2);
  const file_record second = file_record_at(r.value(), 1).value();
  CHECK(second.file == 3);
  CHECK(second.record == 9);
  CHECK(bytes(second.data.begin(), second.data.end()) == bytes{0x33, 0xCD, 0x00, 0x40});
  const file_record first = file_record_at(r.value(), 0).value();
  CHECK(bytes(first.data.begin(), first.data.end()) == bytes{0x0D, 0xFE, 0x00, 0x20});

  const auto w = decode_file_record_request(view(write_request));
  REQUIRE(w.is_complete());
  CHECK(w->count == 1);
  const file_record rec = file_record_at(w.value(), 0).value();
  CHECK(rec.record == 7);
  CHECK(bytes(rec.data.begin(), rec.data.end()) == bytes(values, values + 6));
  CHECK(output(encode_write_file_record_response(w.value(), out), out) == write_request);
  const auto echo = decode_write_file_record_response(view(write_request), view(write_request));
  REQUIRE(echo.is_complete());
  CHECK(echo->response);
  CHECK(file_record_at(echo.value(), 0)->length == 3);

  const file_record answers[] = {{first.data, 0, 0, 0}, {second.data, 0, 0, 0}};
  CHECK(output(encode_read_file_record_response(answers, out), out) == read_response);
}

TEST_CASE("file records: each kind of bad request is its own error, answered 03 then 02") {
  struct bad {
    bytes pdu;
    errc error;
  };
  const std::vector<bad> cases = {
      {{}, errc::modbus_pdu_length},
      {{0x03, 0x07}, errc::modbus_illegal_function},
      {{0x14}, errc::truncated},
      {{0x14, 0x06, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00}, errc::modbus_byte_count},  // < 7
      {{0x14, 0x08, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00}, errc::modbus_byte_count},
      {{0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00}, errc::truncated},  // 5 of 7 bytes
      {{0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0xAA}, errc::modbus_byte_count},
      {{0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00}, errc::modbus_quantity},  // N = 0
      {{0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x7D}, errc::modbus_quantity},  // > 253
      {{0x14, 0x07, 0x05, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01}, errc::modbus_reference_type},
      {{0x14, 0x07, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01}, errc::modbus_file_number},
      {{0x14, 0x07, 0x06, 0x00, 0x01, 0x27, 0x10, 0x00, 0x01}, errc::modbus_record_number},
      {{0x14, 0x07, 0x06, 0x00, 0x01, 0x27, 0x0F, 0x00, 0x02}, errc::modbus_record_number},
      // FC15
      {{0x15, 0x08, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00}, errc::modbus_byte_count},
      {{0x15, 0xFC, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00}, errc::modbus_byte_count},
      {{0x15, 0x09, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x12, 0x34}, errc::modbus_byte_count},
      {{0x15, 0x0A, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x12, 0x34, 0x06},
       errc::modbus_byte_count},  // a second sub-request's header cut by the data length
      {{0x15, 0x09, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x12, 0x34}, errc::modbus_quantity},
      {{0x15, 0x09, 0x07, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x12, 0x34},
       errc::modbus_reference_type},
      {{0x15, 0x09, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x12, 0x34},
       errc::modbus_file_number},
      {{0x15, 0x09, 0x06, 0x00, 0x01, 0x27, 0x0F, 0x00, 0x02, 0x12, 0x34},
       errc::modbus_byte_count},  // N = 2 but one register: layout first (03)
      {{0x15, 0x09, 0x06, 0xFF, 0xFF, 0x27, 0x10, 0x00, 0x01, 0x12, 0x34},
       errc::modbus_record_number},
  };
  for (const bad& c : cases) {
    CAPTURE(c.pdu);
    CHECK(request_error(c.pdu) == c.error);
  }
  // 03 (lengths) is answered before 02 (fields): a bad reference type in sub-request 1 and a
  // record length 0 in sub-request 2
  CHECK(request_error({0x14, 0x0E, 0x05, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x06, 0x00, 0x01, 0x00,
                       0x00, 0x00, 0x00}) == errc::modbus_quantity);
  CHECK(exception_for(errc::modbus_reference_type) == exception_code::illegal_data_address);
  CHECK(exception_for(errc::modbus_file_number) == exception_code::illegal_data_address);
  CHECK(exception_for(errc::modbus_record_number) == exception_code::illegal_data_address);
  CHECK(exception_for(errc::modbus_quantity) == exception_code::illegal_data_value);
  // the extremes that are legal: file 0xFFFF, the last record, 35 sub-requests
  CHECK(request_error({0x14, 0x07, 0x06, 0xFF, 0xFF, 0x27, 0x0F, 0x00, 0x01}) == errc::ok);
  bytes many = {0x14, 0xF5};
  for (int k = 0; k < 35; ++k) {
    many.insert(many.end(), {0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01});
  }
  CHECK(request_error(many) == errc::ok);
  many[1] = 0xFC;  // 36 would be 0xFC: past 0xF5
  CHECK(request_error(many) == errc::modbus_byte_count);
  // the largest FC14 answer: one sub-request of 124 records (2 + 2 + 248 = 252 bytes)
  CHECK(request_error({0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x7C}) == errc::ok);
}

TEST_CASE("file records: the encoders refuse what the decoder refuses") {
  std::uint8_t out[253] = {};
  const file_record none[1] = {};
  CHECK(encode_read_file_record(span<const file_record>(none, 0), out).error() ==
        errc::modbus_pdu_length);
  const file_record zero[] = {{{}, 1, 0, 0}};
  CHECK(encode_read_file_record(zero, out).error() == errc::modbus_quantity);
  const file_record big[] = {{{}, 1, 0, 125}};
  CHECK(encode_read_file_record(big, out).error() == errc::modbus_quantity);
  const file_record no_file[] = {{{}, 0, 0, 1}};
  CHECK(encode_read_file_record(no_file, out).error() == errc::modbus_file_number);
  const file_record past[] = {{{}, 1, 0x270F, 2}};
  CHECK(encode_read_file_record(past, out).error() == errc::modbus_record_number);
  std::vector<file_record> thirty_six(36, file_record{{}, 1, 0, 1});
  CHECK(encode_read_file_record(span<const file_record>(thirty_six.data(), 36), out).error() ==
        errc::modbus_pdu_length);
  const file_record ok[] = {{{}, 1, 0, 1}};
  CHECK(encode_read_file_record(ok, mutable_byte_view(out, 8)).error() == errc::buffer_too_small);
  CHECK(encode_read_file_record(ok, mutable_byte_view(out, 9)).value_or(0) == 9U);
  const std::uint8_t three[3] = {1, 2, 3};
  const file_record odd[] = {{byte_view(three), 1, 0, 1}};
  CHECK(encode_write_file_record(odd, out).error() == errc::modbus_byte_count);
  static const std::uint8_t lots[250] = {};
  const file_record too_long[] = {{byte_view(lots, 246), 1, 0, 123}};
  CHECK(encode_write_file_record(too_long, out).error() == errc::modbus_pdu_length);
  const file_record longest[] = {{byte_view(lots, 244), 1, 0, 122}};
  CHECK(encode_write_file_record(longest, out).value_or(0) == 253U);
  CHECK(request_error(bytes(out, out + 253)) == errc::ok);
  // the server's FC14 answer
  CHECK(encode_read_file_record_response(span<const file_record>(none, 0), out).error() ==
        errc::modbus_pdu_length);
  const file_record odd_answer[] = {{byte_view(three), 0, 0, 0}};
  CHECK(encode_read_file_record_response(odd_answer, out).error() == errc::modbus_byte_count);
  const file_record empty_answer[] = {{byte_view(three, 0), 0, 0, 0}};
  CHECK(encode_read_file_record_response(empty_answer, out).error() == errc::modbus_byte_count);
  const file_record huge_answer[] = {{byte_view(lots, 250), 0, 0, 0}};
  CHECK(encode_read_file_record_response(huge_answer, out).error() == errc::modbus_pdu_length);
  const file_record one_answer[] = {{byte_view(three, 2), 0, 0, 0}};
  CHECK(encode_read_file_record_response(one_answer, mutable_byte_view(out, 5)).error() ==
        errc::buffer_too_small);
  const auto w = decode_file_record_request(view(write_request));
  CHECK(encode_write_file_record_response(w.value(), mutable_byte_view(out, 14)).error() ==
        errc::buffer_too_small);
  const auto r = decode_file_record_request(view(read_request));
  CHECK(encode_write_file_record_response(r.value(), out).error() == errc::invalid_argument);
  const auto echoed = decode_write_file_record_response(view(write_request), view(write_request));
  CHECK(encode_write_file_record_response(echoed.value(), out).error() == errc::invalid_argument);
}

TEST_CASE("file records: responses are checked against their request") {
  auto read_error = [](bytes pdu) {
    const auto r = decode_read_file_record_response(view(read_request), view(pdu));
    return r.is_complete() ? errc::ok : r.error();
  };
  CHECK(read_error(read_response) == errc::ok);
  bytes b = read_response;
  b[3] = 0x07;
  CHECK(read_error(b) == errc::modbus_reference_type);
  b = read_response;
  b[1] = 0x0D;
  CHECK(read_error(b) == errc::truncated);
  b = read_response;
  b[1] = 0x0B;
  CHECK(read_error(b) == errc::modbus_byte_count);
  b = read_response;
  b[2] = 0x04;  // even sub-response length
  CHECK(read_error(b) == errc::modbus_byte_count);
  b = read_response;
  b[2] = 0x01;  // shorter than a length and a reference type
  CHECK(read_error(b) == errc::modbus_byte_count);
  b = read_response;
  b[8] = 0x07;  // the second runs past the data
  CHECK(read_error(b) == errc::modbus_byte_count);
  CHECK(read_error({0x14, 0x06, 0x05, 0x06, 0x0D, 0xFE, 0x00, 0x20}) == errc::modbus_mismatch);
  CHECK(read_error({0x14, 0x07, 0x05, 0x06, 0x0D, 0xFE, 0x00, 0x20, 0x03}) ==
        errc::modbus_byte_count);  // a second sub-response cut after its length
  CHECK(read_error({0x14, 0x0C, 0x07, 0x06, 0x0D, 0xFE, 0x00, 0x20, 0x11, 0x22, 0x03, 0x06, 0x33,
                    0x44}) == errc::modbus_mismatch);  // 3 records asked 2
  bytes three = read_response;
  three[1] = 0x10;
  three.insert(three.end(), {0x03, 0x06, 0x12, 0x34});
  CHECK(read_error(three) == errc::modbus_mismatch);  // a third sub-response
  CHECK(read_error({0x14}) == errc::truncated);
  CHECK(read_error({0x03, 0x02, 0x00, 0x00}) == errc::modbus_mismatch);
  CHECK(read_error({}) == errc::modbus_pdu_length);
  const auto ex = decode_read_file_record_response(view(read_request), view(bytes{0x94, 0x02}));
  REQUIRE(ex.is_complete());
  CHECK(ex->exception);
  CHECK(ex->exception_code == 0x02);
  CHECK(ex->count == 0);
  CHECK(read_error({0x94, 0x02, 0x00}) == errc::modbus_byte_count);
  // the request itself must be a valid FC14 one
  CHECK(decode_read_file_record_response(view(write_request), view(read_response)).error() ==
        errc::invalid_argument);
  CHECK(decode_read_file_record_response(view(bytes{0x14, 0x07}), view(read_response)).error() ==
        errc::invalid_argument);
  CHECK(decode_write_file_record_response(view(read_request), view(write_request)).error() ==
        errc::invalid_argument);

  auto write_error = [](bytes pdu) {
    const auto r = decode_write_file_record_response(view(write_request), view(pdu));
    return r.is_complete() ? errc::ok : r.error();
  };
  b = write_request;
  b.back() = 0x0E;  // another value echoed
  CHECK(write_error(b) == errc::modbus_mismatch);
  b = write_request;
  b[1] = 0x0F;
  CHECK(write_error(b) == errc::truncated);
  CHECK(write_error({0x95, 0x04}) == errc::ok);
  CHECK(write_error({0x15, 0x09, 0x06, 0x00, 0x04, 0x00, 0x07, 0x00, 0x01, 0x06, 0xAF}) ==
        errc::modbus_mismatch);  // a valid FC15 PDU, not the request's
}

namespace {

// Two files of 16 records each (files 1 and 2); file 3 exists for reads only.
struct file_device {
  std::uint16_t files[3][16] = {};
  int writes = 0;

  std::uint8_t read_file_record(std::uint16_t file, std::uint16_t record, mutable_byte_view out) {
    const std::size_t n = out.size() / 2U;
    if (file < 1U || file > 3U || record + n > 16U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < n; ++i) {
      store_be16(out, 2U * i, files[file - 1U][record + i]);
    }
    return 0;
  }
  std::uint8_t write_file_record(std::uint16_t file, std::uint16_t record, byte_view data) {
    const std::size_t n = data.size() / 2U;
    if (file < 1U || file > 2U || record + n > 16U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < n; ++i) {
      files[file - 1U][record + i] = register_at(data, i);
    }
    ++writes;
    return 0;
  }
};
struct checked_file_device : file_device {
  std::uint8_t check_file_record(std::uint16_t file, std::uint16_t record,
                                 std::uint16_t length) const {
    return file >= 1U && file <= 2U && record + length <= 16U ? 0 : 0x02;
  }
};
// Record 0 of file 1 is write-protected: the check refuses it, though write_file_record (the
// plain device's) would take it.
struct protected_file_device : file_device {
  std::uint8_t check_file_record(std::uint16_t file, std::uint16_t record,
                                 std::uint16_t length) const {
    return file == 1U && record == 0U ? 0x02 : (record + length <= 16U ? 0 : 0x02);
  }
};
// Files written only (FC15 served, not FC14): one file of 16 records.
struct write_only_files {
  std::uint16_t records[16] = {};
  std::uint8_t write_file_record(std::uint16_t file, std::uint16_t record, byte_view data) {
    if (file != 1U || record + data.size() / 2U > 16U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < data.size() / 2U; ++i) {
      records[record + i] = register_at(data, i);
    }
    return 0;
  }
};
struct read_only_files {
  std::uint8_t read_file_record(std::uint16_t, std::uint16_t, mutable_byte_view out) {
    for (auto& b : out) {
      b = 0xAB;
    }
    return 0;
  }
};

}  // namespace

TEST_CASE("file records: the server reads and writes them through the device") {
  static_assert(
      (served_functions<file_device>() & functions_of(0x14, 0x15)) == functions_of(0x14, 0x15), "");
  static_assert(served_functions<read_only_files>() == functions_of(0x14), "");
  file_device dev;
  dev.files[2][9] = 0x33CD;
  dev.files[2][10] = 0x0040;
  // file 4 is unknown: 02 from the device
  CHECK(testutil::serve_pdu(dev, 1, read_request) == bytes{0x94, 0x02});
  const bytes read3 = {0x14, 0x07, 0x06, 0x00, 0x03, 0x00, 0x09, 0x00, 0x02};
  CHECK(testutil::serve_pdu(dev, 1, read3) ==
        bytes{0x14, 0x06, 0x05, 0x06, 0x33, 0xCD, 0x00, 0x40});
  // written, then read back
  const bytes write = {0x15, 0x0D, 0x06, 0x00, 0x01, 0x00, 0x07, 0x00,
                       0x03, 0x06, 0xAF, 0x04, 0xBE, 0x10, 0x0D};
  CHECK(testutil::serve_pdu(dev, 1, write) == write);
  CHECK(dev.files[0][8] == 0x04BE);
  const bytes read1 = {0x14, 0x0E, 0x06, 0x00, 0x01, 0x00, 0x07, 0x00,
                       0x01, 0x06, 0x00, 0x01, 0x00, 0x08, 0x00, 0x02};
  CHECK(testutil::serve_pdu(dev, 1, read1) ==
        bytes{0x14, 0x0A, 0x03, 0x06, 0x06, 0xAF, 0x05, 0x06, 0x04, 0xBE, 0x10, 0x0D});
  // the codec's exceptions: 03 for the lengths, 02 for the fields
  CHECK(testutil::serve_pdu(dev, 1, {0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00}) ==
        bytes{0x94, 0x03});
  CHECK(testutil::serve_pdu(dev, 1, {0x14, 0x07, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01}) ==
        bytes{0x94, 0x02});
  CHECK(testutil::serve_pdu(dev, 1,
                            {0x15, 0x09, 0x05, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01}) ==
        bytes{0x95, 0x02});
  CHECK(testutil::serve_pdu(dev, 1, {0x15, 0x09, 0x06}) == bytes{0x95, 0x03});
  // a broadcast write is executed, not answered
  const bytes broadcast = {0x15, 0x09, 0x06, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0xBE, 0xEF};
  CHECK(testutil::serve_adu(dev, 1, view(testutil::rtu(0, broadcast))).empty());
  CHECK(dev.files[1][0] == 0xBEEF);
  read_only_files ro;
  CHECK(testutil::serve_pdu(ro, 1, broadcast) == bytes{0x95, 0x01});
  CHECK(testutil::serve_pdu(ro, 1, {0x14, 0x07, 0x06, 0x00, 0x09, 0x00, 0x00, 0x00, 0x01}) ==
        bytes{0x14, 0x04, 0x03, 0x06, 0xAB, 0xAB});
}

TEST_CASE("file records: check_file_record keeps a failing FC15 from writing anything") {
  // sub-request 1 fits file 1, sub-request 2 does not fit file 2 (records 15-16 of 16)
  const bytes write = {0x15, 0x14, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x12, 0x34,
                       0x06, 0x00, 0x02, 0x00, 0x0F, 0x00, 0x02, 0x56, 0x78, 0x9A, 0xBC};
  checked_file_device checked;
  CHECK(testutil::serve_pdu(checked, 1, write) == bytes{0x95, 0x02});
  CHECK(checked.writes == 0);
  CHECK(checked.files[0][0] == 0);
  CHECK(testutil::serve_pdu(checked, 1, {0x15, 0x09, 0x06}) == bytes{0x95, 0x03});
  const bytes fits = {0x15, 0x09, 0x06, 0x00, 0x02, 0x00, 0x0F, 0x00, 0x01, 0x56, 0x78};
  CHECK(testutil::serve_pdu(checked, 1, fits) == fits);
  CHECK(checked.files[1][15] == 0x5678);
  // reads are not checked first (they change nothing): the device's own answer
  checked.files[1][3] = 0xCAFE;
  CHECK(testutil::serve_pdu(checked, 1, {0x14, 0x07, 0x06, 0x00, 0x02, 0x00, 0x03, 0x00, 0x01}) ==
        bytes{0x14, 0x04, 0x03, 0x06, 0xCA, 0xFE});
  // without it (documented): the sub-requests before the failing one are written
  file_device unchecked;
  CHECK(testutil::serve_pdu(unchecked, 1, write) == bytes{0x95, 0x02});
  CHECK(unchecked.writes == 1);
  CHECK(unchecked.files[0][0] == 0x1234);
}

TEST_CASE("file records: the RTU framer sizes FC14/15 requests and responses by their counts") {
  // two requests back to back, no silence between them: each ends at its byte count
  const bytes stream = [] {
    bytes s = testutil::rtu(1, read_request);
    const bytes w = testutil::rtu(1, write_request);
    s.insert(s.end(), w.begin(), w.end());
    return s;
  }();
  rtu_server_framer server(framer_options{1, frame_end::length});
  std::vector<bytes> frames;
  feed_all(server, view(stream), [&](const auto& r) {
    CHECK(r.is_complete());
    frames.push_back(bytes(r->pdu.begin(), r->pdu.end()));
    return true;
  });
  CHECK(frames == std::vector<bytes>{read_request, write_request});
  CHECK(predict_request_size(view({0x01, 0x14})) == 0U);  // the count not yet there
  CHECK(predict_response_size(view({0x01, 0x14, 0x0C}), 0x14) == 17U);
  CHECK(predict_response_size(view({0x01, 0x15, 0x0D}), 0x15) == 18U);

  rtu_client_framer client(framer_options{1, frame_end::length});
  const bytes adu = testutil::rtu(1, read_request);
  client.sent(view(adu));
  frames.clear();
  feed_all(client, view(testutil::rtu(1, read_response)), [&](const auto& r) {
    CHECK(r.is_complete());
    frames.push_back(bytes(r->pdu.begin(), r->pdu.end()));
    return true;
  });
  CHECK(frames == std::vector<bytes>{read_response});
}

TEST_CASE("file records: default-constructed ones, and value() of a failure, hold nothing") {
  const auto none = [](const file_record& rec) {
    return rec.data.empty() && rec.file == 0U && rec.record == 0U && rec.length == 0U;
  };
  const auto nothing = [](const file_records& r) {
    return r.body.empty() && r.requests.empty() && r.function == 0U && r.count == 0U &&
           !r.response && !r.exception && r.exception_code == 0U;
  };
  CHECK(none(file_record{}));
  CHECK(nothing(file_records{}));
  const auto failed = decode_file_record_request(view(bytes{0x14, 0x0E}));
  REQUIRE(failed.is_failed());
  CHECK(nothing(failed.value()));
  const auto request = decode_file_record_request(view(read_request));
  REQUIRE(request.is_complete());
  const auto past = file_record_at(request.value(), 2);
  CHECK(past.error() == errc::out_of_range);
  CHECK(none(past.value()));
}

TEST_CASE("file records: check_file_record is asked for every FC15 sub-request, the first too") {
  // sub-request 1: file 1, record 0 (refused by the check); sub-request 2: file 2, record 15
  const bytes write = {0x15, 0x12, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x12,
                       0x34, 0x06, 0x00, 0x02, 0x00, 0x0F, 0x00, 0x01, 0x56, 0x78};
  protected_file_device dev;
  CHECK(testutil::serve_pdu(dev, 1, write) == bytes{0x95, 0x02});
  CHECK(dev.writes == 0);
  CHECK(dev.files[0][0] == 0);
  CHECK(dev.files[1][15] == 0);
  // the same sub-requests the other way round: refused all the same, nothing written
  const bytes swapped = {0x15, 0x12, 0x06, 0x00, 0x02, 0x00, 0x0F, 0x00, 0x01, 0x56,
                         0x78, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x12, 0x34};
  CHECK(testutil::serve_pdu(dev, 1, swapped) == bytes{0x95, 0x02});
  CHECK(dev.writes == 0);
  CHECK(dev.files[1][15] == 0);
}

TEST_CASE("file records: a device that only writes them serves FC15, answers FC14 with 01") {
  static_assert(served_functions<write_only_files>() == functions_of(0x15), "");
  write_only_files dev;
  const bytes write = {0x15, 0x09, 0x06, 0x00, 0x01, 0x00, 0x02, 0x00, 0x01, 0xBE, 0xEF};
  CHECK(testutil::serve_pdu(dev, 1, write) == write);
  CHECK(dev.records[2] == 0xBEEF);
  CHECK(testutil::serve_pdu(dev, 1, {0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x02, 0x00, 0x01}) ==
        bytes{0x94, 0x01});
  CHECK(testutil::serve_pdu(dev, 1,
                            {0x15, 0x09, 0x06, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01}) ==
        bytes{0x95, 0x02});
}
