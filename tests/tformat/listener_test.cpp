// T-format line listener (both directions of a tapped line): requests and responses framed
// and paired; the abnormal requests of spec Tables 5 and 6 paired with their ID3 replies.
// Frames built here by hand from the spec's field structure (CRC = XOR of the fields).
#include "motionbus/tformat/listener.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/prng.hpp"
#include "../support/stream.hpp"

using namespace motionbus;
using namespace motionbus::tformat;

using namespace testutil;

namespace {

struct event {
  bool ok = false;
  errc error = errc::ok;
  bool response = false;
  bytes frame;
  errc request_error = errc::ok;
  bool id3_reply = false;
  std::uint8_t sf = 0;
};
bool operator==(const event& a, const event& b) {
  return a.ok == b.ok && a.error == b.error && a.response == b.response && a.frame == b.frame &&
         a.request_error == b.request_error && a.id3_reply == b.id3_reply && a.sf == b.sf;
}

event note(const decode_result<heard>& r) {
  event e;
  if (!r) {
    e.error = r.error();
    return e;
  }
  e.ok = true;
  e.response = r->is_response;
  e.frame.assign(r->bytes.begin(), r->bytes.end());
  e.request_error = r->request_error;
  e.id3_reply = r->id3_reply;
  e.sf = r->resp.sf;
  return e;
}

// The line in chunks, then the silence.
std::vector<event> chunks(line_listener& l, const bytes& line, std::size_t chunk) {
  return fed_notes(l, view(line), chunk, note, then::idle);
}

// The line one byte at a time through put(), then the silence.
std::vector<event> one_by_one(line_listener& l, const bytes& line) {
  return put_notes(l, view(line), note, then::idle);
}

// The ID3 data an encoder answers an abnormal request with, `sf` its status field.
bytes id3_reply(std::uint8_t sf) {
  return with_crc({0x1A, sf, 0x00, 0x00, 0x00, 0x11, 0x00, 0x00, 0x00, 0x00});
}

}  // namespace

TEST_CASE("listener: a read of a closed EEPROM address, answered with ID3 data, is paired") {
  // issue 23: EA 06 EC (IDD, page 7 address 6), and the emulator's reply
  const bytes line = {0xEA, 0x06, 0xEC, 0x1A, 0x00, 0x00, 0x00,
                      0x00, 0x11, 0x00, 0x00, 0x00, 0x00, 0x0B};
  for (std::size_t chunk = 1; chunk <= line.size(); ++chunk) {
    line_listener l;
    const auto out = chunks(l, line, chunk);
    CAPTURE(chunk);
    REQUIRE(out.size() == 2U);  // no missing response, no phantom request, no garbage
    CHECK(out[0].ok);
    CHECK(!out[0].response);
    CHECK(out[0].frame == bytes{0xEA, 0x06, 0xEC});
    CHECK(out[0].request_error == errc::ok);
    CHECK(out[1].ok);
    CHECK(out[1].response);
    CHECK(out[1].id3_reply);
    CHECK(out[1].frame.size() == 11U);
    CHECK(l.dropped() == 0U);
    line_listener b;
    CHECK(one_by_one(b, line) == out);
  }
}

TEST_CASE("listener: the abnormal requests of Tables 5 and 6, paired with their ID3 replies") {
  struct exchange {
    bytes request;
    errc error;       // request_error
    std::uint8_t sf;  // the ID3 reply's status field (ca0: parity, ca1: delimiter)
  };
  const std::vector<exchange> table = {
      {{0x82}, errc::tformat_parity, sf::ca0},               // ID0 CF, parity bit wrong
      {{0xA2}, errc::tformat_unknown_data_id, 0x00},         // ID4
      {{0x02}, errc::ok, sf::ca1},                           // delimiter error (UART's)
      {{0xEA, 0x06, 0xEC}, errc::ok, 0x00},                  // closed address (Table 6)
      {{0xEA, 0x06, 0x00}, errc::crc_mismatch, 0x00},        // IDD, bad CRC
      {{0x32, 0x04, 0x99, 0x00}, errc::crc_mismatch, 0x00},  // ID6, bad CRC
      {with_crc({0xEA, 0x86}), errc::reserved_bits, 0x00},   // busy bit in a request
      // Table 6 No. 4: a parity error in an EEPROM request's CF, sized by its Data ID
      {{0xB2, 0x00, 0x32, 0x12}, errc::tformat_parity, sf::ca0},  // ID6
      {{0x6A, 0x06, 0xEC}, errc::tformat_parity, sf::ca0},        // IDD
  };
  bytes line;
  for (const exchange& x : table) {
    line = cat({line, x.request, id3_reply(x.sf)});
  }
  line_listener l;
  const auto out = chunks(l, line, 5);
  REQUIRE(out.size() == 2U * table.size());
  for (std::size_t i = 0; i < table.size(); ++i) {
    CAPTURE(i);
    const event& q = out[2U * i];
    const event& a = out[2U * i + 1U];
    CHECK(q.ok);
    CHECK(!q.response);
    CHECK(q.frame == table[i].request);
    CHECK(q.request_error == table[i].error);
    CHECK(a.ok);
    CHECK(a.response);
    CHECK(a.id3_reply);
    CHECK(a.sf == table[i].sf);  // the alarm bits, for the monitor to flag
  }
  line_listener b;
  CHECK(one_by_one(b, line) == out);
}

TEST_CASE("listener: requests and responses of every layout; a missing response; garbage") {
  const bytes id0 = {0x02};
  const bytes id0_reply = with_crc({0x02, 0x00, 0x10, 0x00, 0x00});
  const bytes id3 = {0x1A};
  const bytes id3_data = id3_reply(0x00);
  const bytes write = with_crc({0x32, 0x04, 0x99});
  const bytes id1 = {0x8A};
  const bytes line = cat({id0,
                          id0_reply,
                          id3,
                          id3_data,
                          write,
                          write,
                          id0,
                          {0x00, 0x55},
                          id1,
                          with_crc({0x8A, 0x00, 0x05, 0x00, 0x00})});
  line_listener l;
  const auto out = chunks(l, line, 3);
  // id0 request, response; id3 request, response (not an "ID3 reply": it was asked for); the
  // ID6 request and its echoing response; a request without response (the next is a request,
  // garbage dropped between); a request and its response
  REQUIRE(out.size() == 9U);
  const bool response[] = {false, true, false, true, false, true, false, false, true};
  for (std::size_t i = 0; i < out.size(); ++i) {
    CAPTURE(i);
    CHECK(out[i].ok);
    CHECK(out[i].response == response[i]);
    CHECK(!out[i].id3_reply);
  }
  CHECK(l.dropped() == 2U);
  line_listener b;
  CHECK(one_by_one(b, line) == out);
}

TEST_CASE("listener: a corrupted response is reported, a frame behind it is not lost") {
  bytes bad = with_crc({0x02, 0x00, 0x10, 0x00, 0x00});
  bad[2] ^= 0x01;
  const bytes good = with_crc({0x02, 0x00, 0x11, 0x00, 0x00});
  line_listener l;
  const auto out = chunks(l, cat({{0x02}, bad, good}), 64);
  REQUIRE(out.size() >= 3U);
  CHECK(!out[0].response);
  CHECK(!out[1].ok);
  CHECK(out[1].error == errc::crc_mismatch);
  CHECK(out.back().ok);
  CHECK(out.back().response);
  CHECK(out.back().frame == good);
}

TEST_CASE("listener put(): byte by byte, the results of feed() in chunks (random streams)") {
  testutil::splitmix64 rng(0x7f0a);
  const std::vector<bytes> frames = {{0x02},
                                     {0x1A},
                                     {0xEA, 0x06, 0xEC},
                                     with_crc({0x32, 0x04, 0x99}),
                                     with_crc({0x02, 0x00, 0x10, 0x00, 0x00}),
                                     id3_reply(0x40),
                                     with_crc({0xEA, 0x06, 0x42}),
                                     {0x82},
                                     {0x22}};
  std::size_t heard_frames = 0;
  for (int round = 0; round < 300; ++round) {
    bytes line;
    while (line.size() < 200U) {
      const std::uint64_t kind = rng.below(10);
      if (kind < 8U) {
        bytes f = frames[static_cast<std::size_t>(rng.below(frames.size()))];
        if (kind == 7U) {
          flip_a_byte(rng, f);
        }
        line = cat({line, f});
      } else {
        line.push_back(rng.byte());
      }
    }
    line_listener a;
    line_listener b;
    const auto expected = chunks(a, line, 1U + static_cast<std::size_t>(rng.below(20)));
    CAPTURE(round);
    CHECK(one_by_one(b, line) == expected);
    for (const auto& e : expected) {
      heard_frames += e.ok ? 1U : 0U;
    }
  }
  CHECK(heard_frames > 5000U);
}

TEST_CASE("listener: the silence drops the rest of a rejected response (no phantom requests)") {
  // issue 23 review §5: an ID0 request, a response whose CRC is wrong holding 1A and 02
  const bytes response = {0x02, 0x00, 0x1A, 0x02, 0x00, 0x55};  // CRC should be 0x18
  const bytes line = cat({{0x02}, response});
  for (std::size_t chunk = 1; chunk <= line.size(); ++chunk) {
    CAPTURE(chunk);
    line_listener l;
    const auto out = chunks(l, line, chunk);
    REQUIRE(out.size() == 2U);
    CHECK(out[0].ok);
    CHECK(!out[0].response);
    CHECK(out[1].error == errc::crc_mismatch);
    CHECK(l.pending() == 0U);
    CHECK(l.dropped() == response.size());
    CHECK(!l.expecting_response());
    line_listener b;
    CHECK(one_by_one(b, line) == out);
  }
}

TEST_CASE("listener: a response that does not answer its request (another EEPROM address) fails") {
  // IDD read of address 5, answered for address 6: CRC-valid, but not this request's answer
  const bytes line = cat({with_crc({0xEA, 0x05}), with_crc({0xEA, 0x06, 0x55})});
  line_listener l;
  const auto out = chunks(l, line, line.size());
  REQUIRE(out.size() >= 2U);
  CHECK(out[0].ok);
  CHECK(!out[0].response);
  CHECK(!out[1].ok);
  CHECK(out[1].error == errc::tformat_address_mismatch);
  line_listener b;
  CHECK(one_by_one(b, line) == out);
}

TEST_CASE("listener: a request heard whole reports its decoded fields") {
  struct fields {
    bool ok = false;
    data_id id = data_id::read_abs;
    std::uint8_t address = 0;
    std::uint8_t edf = 0;
    std::uint8_t crc = 0;
  };
  const auto first_request = [](const bytes& line) {
    line_listener l;
    const auto out = fed_notes(
        l, view(line), line.size(),
        [](const decode_result<heard>& r) {
          fields f;
          if (r && !r->is_response) {
            f = fields{true, r->req.id, r->req.address, r->req.edf, r->req.crc};
          }
          return f;
        },
        then::idle);
    return out.empty() ? fields{} : out[0];
  };
  const bytes write = with_crc({0x32, 0x05, 0x12});  // ID6: address 5, data 0x12
  const fields w = first_request(write);
  CHECK(w.ok);
  CHECK(w.id == data_id::eeprom_write);
  CHECK(w.address == 0x05);
  CHECK(w.edf == 0x12);
  CHECK(w.crc == write[3]);
  const bytes read = with_crc({0xEA, 0x7F});  // IDD: address 127
  const fields r = first_request(read);
  CHECK(r.ok);
  CHECK(r.id == data_id::eeprom_read);
  CHECK(r.address == 0x7F);
  CHECK(r.crc == read[2]);
}

TEST_CASE("listener: a CF-only request is heard at its byte, new, after garbage, after a silence") {
  line_listener l;
  REQUIRE(l.put(0x02));  // a new listener: ID0's request
  CHECK(l.result()->req.id == data_id::read_abs);
  CHECK(l.idle().is_incomplete());  // no response: the silence ends the expectation
  CHECK_FALSE(l.put(0x00));         // no sync code: dropped
  CHECK(l.dropped() == 1U);
  REQUIRE(l.put(0x1A));  // the next byte, ID3's request
  CHECK(l.result()->req.id == data_id::read_all);
  // a rejected response, the silence that drops its rest, then a request at its byte
  const bytes bad = {0x1A, 0x00, 0, 0, 0, 0x11, 0, 0, 0, 0, 0x55};  // CRC should be 0x0B
  const auto r = l.feed(view(bad));
  REQUIRE(r.is_failed());
  CHECK(r.error() == errc::crc_mismatch);
  CHECK(l.idle().is_incomplete());
  CHECK(l.pending() == 0U);
  REQUIRE(l.put(0x8A));  // ID1's request
  CHECK_FALSE(l.result()->is_response);
  CHECK(l.result()->req.id == data_id::read_abm);
}

TEST_CASE("listener: feed() of part of a response needs its remaining bytes") {
  line_listener l;
  REQUIRE(l.feed(view(bytes{0x1A})).is_complete());   // ID3's request
  const bytes head = {0x1A, 0x00, 0x01, 0x02, 0x03};  // 5 of the response's 11 bytes
  const auto r = l.feed(view(head));
  REQUIRE(r.is_incomplete());
  CHECK(r.needed() == 6U);
  const auto r2 = l.feed(view(bytes{0x04, 0x11}));
  REQUIRE(r2.is_incomplete());
  CHECK(r2.needed() == 4U);
}

TEST_CASE("listener: idle() with nothing (more) held is incomplete, needing a frame's first byte") {
  line_listener l;
  const auto none = l.idle();
  REQUIRE(none.is_incomplete());
  CHECK(none.needed() == 1U);
  // an IDD request cut short (CF and an ADF of 0x00): truncated, one byte dropped; the ADF
  // left has no sync code, starts no frame: dropped, and then nothing is held
  REQUIRE(l.feed(view(bytes{0xEA, 0x00})).is_incomplete());
  const auto cut = l.idle();
  CHECK(cut.error() == errc::truncated);
  CHECK(cut.consumed() == 0U);  // consumed(): bytes of the call's input taken; idle() has none
  CHECK(l.dropped() == 1U);     // the one byte dropped
  const auto rest = l.idle();
  REQUIRE(rest.is_incomplete());
  CHECK(rest.needed() == 1U);
  CHECK(l.pending() == 0U);
  CHECK(l.dropped() == 2U);
}

TEST_CASE("listener: ID3 data with ca0 or ca1 answering an ID3 request is its response") {
  // The encoder flags a request it received with a parity or delimiter error (spec §6.3.2);
  // the tap heard the request whole: the reply is paired, its SF tells
  for (const std::uint8_t sf : {std::uint8_t{0x40}, std::uint8_t{0x80}}) {
    CAPTURE(static_cast<int>(sf));
    line_listener l;
    REQUIRE(l.put(0x1A));
    const auto r = l.feed(view(id3_reply(sf)));
    REQUIRE(r.is_complete());
    CHECK(r->is_response);
    CHECK(r->resp.sf == sf);
    CHECK_FALSE(r->id3_reply);
    CHECK_FALSE(l.expecting_response());
  }
}

TEST_CASE(
    "listener: after a response, and after one cut short by the silence, a request at its "
    "byte") {
  line_listener l;
  REQUIRE(l.put(0x02));
  const auto r = l.feed(view(with_crc({0x02, 0x00, 0x40, 0xE2, 0x01})));
  REQUIRE(r.is_complete());
  CHECK(r->is_response);
  REQUIRE(l.put(0x8A));  // ID1's request, heard at its byte
  CHECK(l.result()->req.id == data_id::read_abm);
  CHECK_FALSE(l.put(0x8A));  // the first byte of its response
  const auto cut = l.idle();
  CHECK(cut.error() == errc::truncated);
  CHECK_FALSE(l.expecting_response());  // the silence ends the expectation
  CHECK(l.pending() == 0U);
  REQUIRE(l.put(0x8A));  // after the silence: a request, at its byte
  CHECK_FALSE(l.result()->is_response);
  CHECK(l.result()->req.id == data_id::read_abm);
}

TEST_CASE("listener: an abnormal request reports its Data ID and CF as read") {
  // heard::req: "its fields where request_error is ok; id and cf always"
  const std::uint8_t id4_cf = control_field(std::uint8_t{4});
  struct row {
    bytes frame;
    errc error;
    data_id id;
  };
  const row rows[] = {
      {{0x1A ^ 0x80}, errc::tformat_parity, data_id::read_all},
      {{id4_cf}, errc::tformat_unknown_data_id, static_cast<data_id>(4)},
      {{0xEA ^ 0x80, 0x05, 0x6F}, errc::tformat_parity, data_id::eeprom_read},
      {{0xEA, 0x05, 0x00}, errc::crc_mismatch, data_id::eeprom_read},
  };
  for (const row& x : rows) {
    CAPTURE(static_cast<int>(x.frame[0]));
    line_listener l;
    const auto r = l.feed(view(x.frame));
    REQUIRE(r.is_complete());
    CHECK_FALSE(r->is_response);
    CHECK(r->request_error == x.error);
    CHECK(r->req.id == x.id);
    CHECK(r->req.cf == x.frame[0]);
  }
}

TEST_CASE("listener: after a request cut short by the silence, the next request at its byte") {
  line_listener l;
  REQUIRE(l.feed(view(bytes{0xEA})).is_incomplete());  // an IDD request's CF alone
  CHECK(l.idle().error() == errc::truncated);          // its one byte dropped
  CHECK(l.pending() == 0U);
  CHECK(l.dropped() == 1U);
  REQUIRE(l.put(0x02));
  CHECK(l.result()->req.id == data_id::read_abs);
}

TEST_CASE("listener: an abnormal EEPROM request reports its fields as read") {
  // Sized by its Data ID as read (docs/tformat.md: `B2 00 32 12` is one request), its bytes
  // are its address, data and CRC, even where the request is refused
  struct row {
    bytes frame;
    errc error;
    std::uint8_t address;
    std::uint8_t edf;
  };
  const row rows[] = {
      {{0xB2, 0x00, 0x32, 0x12}, errc::tformat_parity, 0x00, 0x32},  // ID6, parity error
      {{0x32, 0x05, 0x12, 0x00}, errc::crc_mismatch, 0x05, 0x12},    // ID6, bad CRC
      {{0xEA, 0x05, 0x6C}, errc::crc_mismatch, 0x05, 0x00},          // IDD, bad CRC: no EDF
      {{0x6A, 0x07, 0x6D}, errc::tformat_parity, 0x07, 0x00},        // IDD, parity error
  };
  for (const row& x : rows) {
    CAPTURE(static_cast<int>(x.frame[0]));
    line_listener l;
    const auto r = l.feed(view(x.frame));
    REQUIRE(r.is_complete());
    CHECK(r->request_error == x.error);
    CHECK(r->req.address == x.address);
    CHECK(r->req.edf == x.edf);
    CHECK(r->req.crc == x.frame.back());
    CHECK(r->bytes.size() == x.frame.size());
  }
}

TEST_CASE("listener: a response with an abnormal request's CF is not checked against its fields") {
  // An IDD read whose CRC is wrong: its address is not what the master sent, so a response
  // with its CF is not compared with it (nothing to compare: only ID3 data is expected)
  line_listener l;
  REQUIRE(l.feed(view(with_crc({0xEA, 0x05}))).is_complete());  // a good read of address 5
  REQUIRE(l.feed(view(with_crc({0xEA, 0x05, 0x42}))).is_complete());
  const bytes bad = {0xEA, 0x06, 0x00};  // CRC should be 0xEC
  const auto q = l.feed(view(bad));
  REQUIRE(q.is_complete());
  CHECK(q->request_error == errc::crc_mismatch);
  const auto r = l.feed(view(with_crc({0xEA, 0x05, 0x42})));
  REQUIRE(r.is_complete());
  CHECK(r->is_response);
  CHECK(r->resp.address == 0x05);
}
