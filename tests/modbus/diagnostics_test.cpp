// FC 07, 08, 0B, 0C, 18 and 2B/0E: the Modbus Application Protocol V1.1b3 examples (§6.7, 6.8,
// 6.9, 6.10, 6.18, 6.21), limits and mismatches.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/modbus.hpp"
#include "motionbus/modbus.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

TEST_CASE("FC07 read exception status, FC0B comm event counter, FC0C comm event log") {
  const bytes q07 = {0x07};
  const bytes r07 = {0x07, 0x6D};
  auto r = decode_response_for(view(q07), view(r07));
  REQUIRE(r.is_complete());
  CHECK(r->status == 0x6D);
  CHECK(decode_response_for(view(q07), view({0x07, 0x6D, 0x00})).error() ==
        errc::modbus_byte_count);

  const bytes q0b = {0x0B};
  const bytes r0b = {0x0B, 0xFF, 0xFF, 0x01, 0x08};
  r = decode_response_for(view(q0b), view(r0b));
  REQUIRE(r.is_complete());
  CHECK(r->status == 0xFFFF);
  CHECK(r->event_count == 0x0108);

  const bytes q0c = {0x0C};
  const bytes r0c = {0x0C, 0x08, 0x00, 0x00, 0x01, 0x08, 0x01, 0x21, 0x20, 0x00};
  r = decode_response_for(view(q0c), view(r0c));
  REQUIRE(r.is_complete());
  CHECK(r->event_count == 0x0108);
  CHECK(r->message_count == 0x0121);
  CHECK(r->data.size() == 2);
  CHECK(r->data[0] == 0x20);
  CHECK(decode_response_for(view(q0c),
                            view({0x0C, 0x09, 0x00, 0x00, 0x01, 0x08, 0x01, 0x21, 0x20, 0x00}))
            .error() == errc::modbus_byte_count);
}

TEST_CASE("FC08 diagnostics: sub-functions, echo of query data, data lengths") {
  std::uint8_t out[16] = {};
  const std::uint8_t data[] = {0xA5, 0x37};
  const auto n = encode_diagnostics(diagnostic::return_query_data, data, out);
  REQUIRE(n.ok());
  const bytes q(out, out + n.value());
  CHECK(q == bytes{0x08, 0x00, 0x00, 0xA5, 0x37});
  const auto dq = decode_request(view(q));
  REQUIRE(dq.is_complete());
  CHECK(dq->sub_function == 0);
  CHECK(decode_response_for(view(q), view(q)).is_complete());  // the echo
  CHECK(decode_response_for(view(q), view({0x08, 0x00, 0x00, 0xA5, 0x38})).error() ==
        errc::modbus_mismatch);
  CHECK(decode_response_for(view(q), view({0x08, 0x00, 0x01, 0xA5, 0x37})).error() ==
        errc::modbus_mismatch);
  const bytes counter = {0x08, 0x00, 0x0B, 0x00, 0x00};
  const bytes counter_reply = {0x08, 0x00, 0x0B, 0x01, 0x2C};  // the decoded view refers to it
  const auto rc = decode_response_for(view(counter), view(counter_reply));
  REQUIRE(rc.is_complete());
  CHECK(register_at(rc->data, 0) == 300);
  // server side: undefined sub-function (exception 01), data lengths, restart values
  CHECK(decode_request(view({0x08, 0x00, 0x05, 0x00, 0x00})).error() ==
        errc::modbus_illegal_function);
  CHECK(decode_request(view({0x08, 0x00, 0x0B, 0x00})).error() == errc::modbus_byte_count);
  CHECK(decode_request(view({0x08, 0x00, 0x00, 0x01})).error() == errc::modbus_byte_count);
  CHECK(decode_request(view({0x08, 0x00, 0x01, 0x12, 0x34})).error() == errc::modbus_coil_value);
  CHECK(decode_request(view({0x08, 0x00, 0x01, 0xFF, 0x00})).is_complete());
  CHECK(decode_request(view({0x08, 0x00})).error() == errc::truncated);
  CHECK(encode_diagnostics(0x05, data, out).error() == errc::modbus_illegal_function);
  CHECK(encode_diagnostics(diagnostic::clear_counters, byte_view(data, 1), out).error() ==
        errc::modbus_byte_count);
}

TEST_CASE("FC18 read FIFO queue") {
  std::uint8_t out[8] = {};
  const auto n = encode_read_fifo_queue(0x04DE, out);
  const bytes q(out, out + n.value());
  CHECK(q == bytes{0x18, 0x04, 0xDE});
  const bytes resp = {0x18, 0x00, 0x06, 0x00, 0x02, 0x01, 0xB8, 0x12, 0x84};
  const auto r = decode_response_for(view(q), view(resp));
  REQUIRE(r.is_complete());
  CHECK(r->fifo_count == 2);
  CHECK(register_at(r->data, 0) == 0x01B8);
  CHECK(register_at(r->data, 1) == 0x1284);
  CHECK(decode_response_for(view(q), view({0x18, 0x00, 0x08, 0x00, 0x02, 0x01, 0xB8, 0x12, 0x84}))
            .error() == errc::modbus_byte_count);
  CHECK(decode_response_for(view(q), view({0x18, 0x00, 0x42, 0x00, 0x20})).error() ==
        errc::modbus_quantity);
  CHECK(decode_request(view({0x18, 0x04})).error() == errc::truncated);
}

TEST_CASE("FC2B/0E read device identification: objects inside the PDU") {
  std::uint8_t out[8] = {};
  const auto n = encode_read_device_identification(1, 0, out);
  const bytes q(out, out + n.value());
  CHECK(q == bytes{0x2B, 0x0E, 0x01, 0x00});
  CHECK(encode_read_device_identification(5, 0, out).error() == errc::modbus_quantity);
  CHECK(decode_request(view({0x2B, 0x0E, 0x05, 0x00})).error() == errc::modbus_quantity);
  const bytes resp = {0x2B, 0x0E, 0x01, 0x01, 0x00, 0x00, 0x03, 0x00, 0x03, 'A', 'B',
                      'C',  0x01, 0x02, 'P',  '1',  0x02, 0x04, 'V',  '1',  '.', '0'};
  const auto r = decode_response_for(view(q), view(resp));
  REQUIRE(r.is_complete());
  CHECK(r->object_count == 3);
  CHECK(!r->more_follows);
  const auto o2 = object_at(r.value(), 2);
  REQUIRE(o2.ok());
  CHECK(o2->id == 0x02);
  CHECK(std::memcmp(o2->value.data(), "V1.0", 4) == 0);
  CHECK(object_at(r.value(), 3).error() == errc::out_of_range);
  // an object length running past the PDU, a count claiming more objects than present
  bytes bad = resp;
  bad[8] = 0x40;
  CHECK(decode_response_for(view(q), view(bad)).error() == errc::modbus_byte_count);
  bad = resp;
  bad[6] = 4;
  CHECK(decode_response_for(view(q), view(bad)).error() == errc::modbus_byte_count);
  // framed by length on a client, object by object
  std::uint8_t adu[256] = {};
  const std::size_t k = encode_rtu(1, view(resp), adu).value();
  rtu_framer f(framer_role::client, {1});
  testutil::sent_to(f, 1, 0x2B);
  std::size_t frames = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const auto e = f.feed(byte_view(adu + i, 1));
    frames += e.is_complete() ? 1U : 0U;
  }
  CHECK(frames == 1);
}

TEST_CASE("server responses for FC 07, 08, 0B, 0C, 18, 2B/0E encode to the spec's examples") {
  std::uint8_t out[64] = {};
  auto n = encode_exception_status_response(0x6D, out);
  CHECK(bytes(out, out + n.value()) == bytes{0x07, 0x6D});
  n = encode_comm_event_counter_response(0xFFFF, 0x0108, out);
  CHECK(bytes(out, out + n.value()) == bytes{0x0B, 0xFF, 0xFF, 0x01, 0x08});
  const std::uint8_t events[] = {0x20, 0x00};
  n = encode_comm_event_log_response(0x0000, 0x0108, 0x0121, events, out);
  CHECK(bytes(out, out + n.value()) ==
        bytes{0x0C, 0x08, 0x00, 0x00, 0x01, 0x08, 0x01, 0x21, 0x20, 0x00});
  const std::uint16_t fifo[] = {0x01B8, 0x1284};
  n = encode_fifo_response(fifo, out);
  CHECK(bytes(out, out + n.value()) == bytes{0x18, 0x00, 0x06, 0x00, 0x02, 0x01, 0xB8, 0x12, 0x84});
  std::uint16_t too_many[32] = {};
  CHECK(encode_fifo_response(too_many, out).error() == errc::modbus_quantity);
  const std::uint8_t data[] = {0xA5, 0x37};
  n = encode_diagnostics(diagnostic::return_query_data, data, out);  // the echo is the same PDU
  CHECK(bytes(out, out + n.value()) == bytes{0x08, 0x00, 0x00, 0xA5, 0x37});
  const std::uint8_t objects[] = {0x00, 0x03, 'A', 'B', 'C', 0x01, 0x02, 'P', '1'};
  n = encode_device_identification_response(1, 0x01, false, 0, 2, objects, out);
  REQUIRE(n.ok());
  const bytes resp(out, out + n.value());
  const bytes q = {0x2B, 0x0E, 0x01, 0x00};
  const auto r = decode_response_for(view(q), view(resp));
  REQUIRE(r.is_complete());
  CHECK(r->object_count == 2);
  CHECK(object_at(r.value(), 1)->id == 0x01);
  CHECK(encode_device_identification_response(1, 0x01, false, 0, 3, objects, out).error() ==
        errc::modbus_byte_count);
  CHECK(encode_comm_event_log_response(0, 0, 0, byte_view(objects, 9), mutable_byte_view(out, 10))
            .error() == errc::buffer_too_small);
}
