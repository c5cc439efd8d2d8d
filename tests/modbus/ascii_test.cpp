// Modbus ASCII (Modbus over Serial Line V1.02 §2.5.2): the LRC, encode_ascii, decode_ascii and
// ascii_framer in its three roles.
#include "motionbus/modbus/ascii.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/frame_events.hpp"
#include "../support/prng.hpp"
#include "../support/stream.hpp"
#include "motionbus/core/stream.hpp"
#include "motionbus/modbus/server.hpp"

using namespace motionbus;
using namespace motionbus::modbus;
using namespace testutil;

namespace {

bytes chars(const std::string& s) {
  return bytes(s.begin(), s.end());
}

// The ASCII ADU of `pdu` for `slave`.
bytes ascii(std::uint8_t slave, const bytes& pdu) {
  std::uint8_t out[max_ascii_size] = {};
  return output(encode_ascii(slave, view(pdu), out), out);
}

}  // namespace

TEST_CASE("LRC: the two's complement of the 8-bit sum (Serial Line §2.5.2.2, §6.2.1)") {
  // Application Protocol's FC03 example: 11 03 00 6B 00 03, sum 0x82
  const bytes read = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03};
  CHECK(lrc::compute(view(read)) == 0x7E);
  CHECK(lrc::compute(view(bytes{0x01, 0x03, 0x00, 0x00, 0x00, 0x01})) == 0xFB);
  CHECK(lrc::compute(byte_view{}) == 0x00);
  CHECK(lrc::compute(view(bytes{0xFF, 0xFF})) == 0x02);  // the carries are discarded
  lrc c;
  for (const std::uint8_t b : read) {
    c.update(b);
  }
  CHECK(c.value() == 0x7E);
  c.update(0x7E);
  CHECK(c.sum() == 0x00);  // over the bytes and their LRC
  static_assert(lrc::compute(byte_view{}) == 0, "constexpr");
}

TEST_CASE("ASCII sizes and the inter-character timeout, as Serial Line §2.5.2.1 gives them") {
  CHECK(max_ascii_size == 513U);  // ':', 2 x 255 hex digits, CR LF
  CHECK(max_ascii_bytes == 255U);
  CHECK(ascii_char_timeout_ms == 1000U);  // "an interval greater than 1 second"
}

TEST_CASE("encode_ascii: ':', uppercase hex of address, PDU and LRC, CR LF") {
  CHECK(ascii(0x11, {0x03, 0x00, 0x6B, 0x00, 0x03}) == chars(":1103006B00037E\r\n"));
  CHECK(ascii(0x00, {0x06, 0x00, 0x01, 0xAB, 0xCD}) == chars(":00060001ABCD81\r\n"));
  // the longest: 253-byte PDU, 513 characters
  const bytes big(max_pdu_size, 0x5A);
  CHECK(ascii(0xF7, big).size() == max_ascii_size);
  std::uint8_t out[max_ascii_size] = {};
  const bytes pdu = {0x03, 0x00, 0x6B, 0x00, 0x03};
  CHECK(encode_ascii(248, view(pdu), out).error() == errc::modbus_slave_address);
  CHECK(encode_ascii(1, byte_view{}, out).error() == errc::modbus_pdu_length);
  const bytes too_big(max_pdu_size + 1U, 0);
  CHECK(encode_ascii(1, view(too_big), out).error() == errc::modbus_pdu_length);
  std::uint8_t small[17] = {};
  CHECK(encode_ascii(1, view(pdu), mutable_byte_view(small, 16)).error() == errc::buffer_too_small);
  CHECK(small[0] == 0);  // nothing written
  CHECK(encode_ascii(1, view(pdu), mutable_byte_view(small, 17)).value() == 17U);
}

TEST_CASE("decode_ascii: the bytes back, lowercase digits accepted, what follows not read") {
  std::uint8_t out[max_ascii_bytes] = {};
  const bytes frame = chars(":1103006B00037E\r\n");
  const auto r = decode_ascii(view(cat({frame, chars(":01")})), out);
  REQUIRE(r.is_complete());
  CHECK(r.consumed() == frame.size());
  CHECK(r->slave == 0x11);
  CHECK(bytes(r->pdu.begin(), r->pdu.end()) == bytes{0x03, 0x00, 0x6B, 0x00, 0x03});
  CHECK(r->lrc == 0x7E);
  CHECK(!r->broadcast());
  // lowercase (a choice: the specification names 0-9, A-F; see ascii.hpp)
  const auto lower = decode_ascii(view(chars(":00060001abcd81\r\n")), out);
  REQUIRE(lower.is_complete());
  CHECK(lower->broadcast());
  CHECK(bytes(lower->pdu.begin(), lower->pdu.end()) == bytes{0x06, 0x00, 0x01, 0xAB, 0xCD});
  // every PDU size round-trips
  splitmix64 rng(25);
  for (std::size_t n = 1; n <= max_pdu_size; ++n) {
    bytes pdu(n);
    for (auto& b : pdu) {
      b = rng.byte();
    }
    const auto slave = static_cast<std::uint8_t>(rng.below(248));
    const bytes adu = ascii(slave, pdu);
    const auto d = decode_ascii(view(adu), out);
    REQUIRE(d.is_complete());
    CHECK(d->slave == slave);
    CHECK(bytes(d->pdu.begin(), d->pdu.end()) == pdu);
  }
}

TEST_CASE("decode_ascii: each kind of bad input its own error") {
  std::uint8_t out[max_ascii_bytes] = {};
  const auto fails = [&](const std::string& s, errc e, std::size_t consumed) {
    const auto r = decode_ascii(view(chars(s)), out);
    CHECK(r.error() == e);
    CHECK(r.consumed() == consumed);
  };
  fails("", errc::no_frame, 0);
  fails("1103006B00037E\r\n", errc::no_frame, 1);                 // bad start
  fails(":1103006G00037E\r\n", errc::modbus_ascii_character, 9);  // non-hex character
  fails(":1103 006B00037E\r\n", errc::modbus_ascii_character, 6);
  fails(":1103006B00037\r\n", errc::modbus_ascii_odd_digits, 16);  // odd digit count
  fails(":1103006B00037F\r\n", errc::crc_mismatch, 17);            // bad LRC
  const auto bad = decode_ascii(view(chars(":1103006B00037F\r\n")), out);
  CHECK(bad.expected() == 0x7E);
  CHECK(bad.received() == 0x7F);
  fails(":1103006B00037E", errc::modbus_ascii_end, 15);     // no CR LF
  fails(":1103006B00037E\r", errc::modbus_ascii_end, 16);   // CR, no LF
  fails(":1103006B00037E\rX", errc::modbus_ascii_end, 17);  // CR, something else
  fails(":1103006B00037E\n", errc::modbus_ascii_end, 16);   // LF without CR
  fails(":1103006B:01", errc::modbus_ascii_end, 9);         // a ':' restarts: consumed stops there
  fails(":1103006B\r:01", errc::modbus_ascii_end, 10);
  fails(":01FF\r\n", errc::modbus_pdu_length, 7);  // too short: address and LRC, no PDU
  CHECK(decode_ascii(view(chars(":0101FE\r\n")), out).is_complete());  // the shortest: FC only
  fails(":\r\n", errc::modbus_pdu_length, 3);
  fails(":F8030000000104\r\n", errc::modbus_slave_address, 17);
  CHECK(decode_ascii(view(ascii(0xF7, {0x07})), out).is_complete());  // 247: the last unicast
  // too long: 256 bytes (a 254-byte PDU)
  std::string s = ":01";
  for (std::size_t i = 0; i < max_pdu_size + 1U; ++i) {
    s += "00";
  }
  s += "FF\r\n";
  const auto r = decode_ascii(view(chars(s)), out);
  CHECK(r.error() == errc::modbus_pdu_length);
  // the caller's buffer is too short for the frame
  std::uint8_t small[4] = {};
  CHECK(decode_ascii(view(chars(":1103006B00037E\r\n")), mutable_byte_view(small, 4)).error() ==
        errc::buffer_too_small);
  CHECK(decode_ascii(view(chars(":1103006B00037E\r\n")), mutable_byte_view(out, 7)).is_complete());
}

TEST_CASE("ascii framer: a frame split at every character boundary, and one character at a time") {
  const bytes pdu = {0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02};
  const bytes frame = ascii(0x11, pdu);
  for (std::size_t cut = 0; cut <= frame.size(); ++cut) {
    ascii_framer f(framer_role::server, {0x11});
    std::vector<frame_note> got;
    for (const auto& part : {bytes(frame.begin(), frame.begin() + static_cast<long>(cut)),
                             bytes(frame.begin() + static_cast<long>(cut), frame.end())}) {
      const auto r = f.feed(view(part));
      if (!r.is_incomplete()) {
        CHECK(r.consumed() == part.size());
        got.push_back(note_frame(r));
      }
    }
    REQUIRE(got.size() == 1U);
    CHECK(got[0] == frame_event(0x11, pdu));
  }
  for (std::size_t chunk = 1; chunk <= frame.size(); ++chunk) {
    ascii_framer f(framer_role::server, {0x11});
    CHECK(fed_notes(f, view(frame), chunk, note_frame) ==
          std::vector<frame_note>{frame_event(0x11, pdu)});
  }
  ascii_framer p(framer_role::server, {0x11});
  CHECK(put_notes(p, view(frame), note_frame) == std::vector<frame_note>{frame_event(0x11, pdu)});
}

TEST_CASE("ascii framer: concatenated frames, garbage between them, a ':' restarts a frame") {
  const bytes a = {0x03, 0x00, 0x6B, 0x00, 0x03};
  const bytes b = {0x06, 0x00, 0x01, 0x00, 0x03};
  const bytes stream = cat(
      {ascii(0x11, a), ascii(0x11, b), chars(std::string("noise\r\n\x00\xff", 9)), ascii(0x11, a),
       chars(":11030") /* cut short by a new ':' */, ascii(0x11, b),
       chars(":1103G") /* non-hex: hunt for the next ':' */, chars("1234\r\n"), ascii(0x11, a)});
  const std::vector<frame_note> want = {
      frame_event(0x11, a), frame_event(0x11, b),
      frame_event(0x11, a), failure_event(errc::modbus_ascii_end),
      frame_event(0x11, b), failure_event(errc::modbus_ascii_character),
      frame_event(0x11, a)};
  for (std::size_t chunk = 1; chunk <= stream.size(); chunk += 3) {
    ascii_framer f(framer_role::server, {0x11});
    CHECK(fed_notes(f, view(stream), chunk, note_frame) == want);
    CHECK(f.dropped() == 9U + 6U);  // the noise, and the characters after the bad one
  }
  ascii_framer p(framer_role::server, {0x11});
  CHECK(put_notes(p, view(stream), note_frame) == want);
}

TEST_CASE("ascii framer: the errors of a frame, each reported once, and the next frame read") {
  const bytes good = ascii(0x11, {0x03, 0x00, 0x6B, 0x00, 0x03});
  const struct {
    const char* in;
    frame_note want;
  } cases[] = {
      {":1103006B00037F\r\n", failure_event(errc::crc_mismatch, 0x7E, 0x7F)},
      {":1103006B00037\r\n", failure_event(errc::modbus_ascii_odd_digits)},
      {":1103006B00037E\rX", failure_event(errc::modbus_ascii_end)},
      {":1103006B00037E\n", failure_event(errc::modbus_ascii_end)},
      {":11030Z", failure_event(errc::modbus_ascii_character)},
      {":11EE\r\n", failure_event(errc::modbus_pdu_length)},
      {":F8030000000104\r\n", failure_event(errc::modbus_slave_address)},
  };
  for (const auto& c : cases) {
    CAPTURE(c.in);
    ascii_framer f(framer_role::server, {0x11});
    const bytes stream = cat({chars(c.in), good});
    CHECK(fed_notes(f, view(stream), 5, note_frame) ==
          std::vector<frame_note>{c.want, frame_event(0x11, {0x03, 0x00, 0x6B, 0x00, 0x03})});
  }
  // too long: the 256th byte fails at once (never more than 255 held)
  std::string s = ":11";
  for (std::size_t i = 0; i < 300; ++i) {
    s += "00";
  }
  ascii_framer f(framer_role::server, {0x11});
  std::vector<frame_note> got;
  std::size_t most = 0;
  for (const std::uint8_t c : cat({chars(s), good})) {
    if (f.put(c)) {
      got.push_back(note_frame(f.result()));
    }
    most = std::max(most, f.pending());
  }
  CHECK(most == max_ascii_bytes);
  CHECK(got == std::vector<frame_note>{failure_event(errc::modbus_pdu_length),
                                       frame_event(0x11, {0x03, 0x00, 0x6B, 0x00, 0x03})});
}

TEST_CASE("ascii framer: idle() is the inter-character timeout, a frame cut short is truncated") {
  ascii_framer f(framer_role::server, {0x11});
  const auto none = f.idle();
  CHECK(none.is_incomplete());  // nothing held: the next character, as feed() asks for
  CHECK(none.needed() == 1U);
  CHECK(f.feed(view(chars(":1103006B00"))).is_incomplete());
  CHECK(f.inside());
  CHECK(f.pending() == 5U);
  const auto r = f.idle();
  CHECK(r.error() == errc::truncated);
  CHECK(r.consumed() == 0U);  // a timeout takes no character
  CHECK(!f.inside());
  CHECK(f.pending() == 0U);
  CHECK(f.idle().is_incomplete());
  // the rest of the frame after the timeout is garbage until the next ':'
  const bytes rest = cat({chars("037E\r\n"), ascii(0x11, {0x07})});
  CHECK(fed_notes(f, view(rest), 4, note_frame) ==
        std::vector<frame_note>{frame_event(0x11, {0x07})});
  CHECK(f.dropped() == 6U);
  // cut short after CR
  CHECK(f.feed(view(chars(":1107E8\r"))).is_incomplete());
  CHECK(f.idle().error() == errc::truncated);
}

TEST_CASE("ascii framer roles: server address and broadcast, client's sent(), listener") {
  const bytes pdu = {0x06, 0x00, 0x01, 0x00, 0x03};
  const bytes stream = cat({ascii(0x11, pdu), ascii(0x12, pdu), ascii(0x00, pdu)});
  ascii_framer server(framer_role::server, {0x11});
  CHECK(fed_notes(server, view(stream), 7, note_frame) ==
        std::vector<frame_note>{frame_event(0x11, pdu), frame_event(0x00, pdu)});
  CHECK(server.skipped() == 1U);
  ascii_framer either(framer_role::either, {0x12});  // `either`: a server
  CHECK(fed_notes(either, view(stream), 7, note_frame) ==
        std::vector<frame_note>{frame_event(0x12, pdu), frame_event(0x00, pdu)});
  ascii_framer listener(framer_role::listener);
  CHECK(fed_notes(listener, view(stream), 7, note_frame) ==
        std::vector<frame_note>{frame_event(0x11, pdu), frame_event(0x12, pdu),
                                frame_event(0x00, pdu)});
  ascii_framer client(framer_role::client);  // before any sent(): any slave
  CHECK(fed_notes(client, view(stream), 7, note_frame).size() == 3U);
  client.sent(view(ascii(0x12, pdu)));
  CHECK(fed_notes(client, view(stream), 7, note_frame) ==
        std::vector<frame_note>{frame_event(0x12, pdu)});
  client.sent(view(chars(":zz")));  // an unreadable address: any
  CHECK(fed_notes(client, view(stream), 7, note_frame).size() == 3U);
  client.sent(view(chars("x12")));
  CHECK(fed_notes(client, view(stream), 7, note_frame).size() == 3U);
  for (const char* unreadable : {":1", ":1z", ":z1"}) {
    client.sent(view(ascii(0x12, pdu)));
    client.sent(view(chars(unreadable)));
    CHECK(fed_notes(client, view(stream), 7, note_frame).size() == 3U);
  }
  ascii_framer configured(framer_role::client, {0x00});
  configured = ascii_framer(framer_role::client, {0x11});
  CHECK(fed_notes(configured, view(stream), 7, note_frame) ==
        std::vector<frame_note>{frame_event(0x11, pdu)});
  // sent() drops a partial frame
  ascii_framer partial(framer_role::client, {0x11});
  CHECK(partial.feed(view(chars(":1106"))).is_incomplete());
  partial.sent(view(ascii(0x11, pdu)));
  CHECK(!partial.inside());
}

TEST_CASE("ascii listener: each frame a request or its response, by pairing") {
  const bytes read = {0x03, 0x00, 0x10, 0x00, 0x01};
  const bytes answer = {0x03, 0x02, 0x12, 0x34};
  const bytes refused = {0x83, 0x02};
  const bytes write = {0x06, 0x00, 0x01, 0x00, 0x03};
  // the directions heard, frame by frame: true for a response
  const auto directions = [](ascii_framer& rx, const std::vector<bytes>& frames,
                             std::size_t timeout_after = 99) {
    std::vector<bool> heard;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      REQUIRE(rx.feed(view(frames[i])).is_complete());
      heard.push_back(rx.heard_response());
      if (i == timeout_after) {
        rx.no_response();
      }
    }
    return heard;
  };
  ascii_framer rx(framer_role::listener);
  CHECK(!rx.heard_response());
  // request, its answer, request, its exception, then a request whose answer never comes
  // followed by another request (to another slave), and that one's answer
  CHECK(directions(rx,
                   {ascii(0x11, read), ascii(0x11, answer), ascii(0x11, read), ascii(0x11, refused),
                    ascii(0x11, write), ascii(0x12, read), ascii(0x12, answer)}) ==
        std::vector<bool>{false, true, false, true, false, false, true});
  // not a response: another slave, another function, after a broadcast, after a response
  ascii_framer other(framer_role::listener);
  CHECK(directions(other, {ascii(0x11, read), ascii(0x12, answer), ascii(0x12, write),
                           ascii(0x00, write), ascii(0x12, write), ascii(0x11, read),
                           ascii(0x11, answer), ascii(0x11, answer)}) ==
        std::vector<bool>{false, false, false, false, false, false, true, false});
  // a master repeating its request after the response time: no_response() makes it a request
  ascii_framer repeated(framer_role::listener);
  CHECK(directions(repeated, {ascii(0x11, read), ascii(0x11, read), ascii(0x11, answer)}, 0) ==
        std::vector<bool>{false, false, true});
  // and with function 01, no_response() or a response leaves no function expected (none is 0)
  const bytes coils = {0x01, 0x00, 0x00, 0x00, 0x08};
  const bytes coils_answer = {0x01, 0x01, 0x5A};
  ascii_framer again(framer_role::listener);
  CHECK(directions(again, {ascii(0x11, coils), ascii(0x11, coils), ascii(0x11, coils_answer)}, 0) ==
        std::vector<bool>{false, false, true});
  ascii_framer answered(framer_role::listener);
  CHECK(directions(answered, {ascii(0x11, coils), ascii(0x11, coils_answer), ascii(0x11, coils),
                              ascii(0x11, coils_answer)}) ==
        std::vector<bool>{false, true, false, true});
  ascii_framer unpaired(framer_role::listener);  // the same without it: paired, as the rule says
  CHECK(directions(unpaired, {ascii(0x11, read), ascii(0x11, read), ascii(0x11, answer)}) ==
        std::vector<bool>{false, true, false});
  // the other roles never pair
  ascii_framer server(framer_role::server, {0x11});
  CHECK(directions(server, {ascii(0x11, read), ascii(0x11, answer)}) ==
        std::vector<bool>{false, false});
}

TEST_CASE("ascii framer: the delimiter after CR may be changed (FC08 sub-function 03)") {
  ascii_options options{0x11, '!'};
  ascii_framer f(framer_role::server, options);
  bytes frame = ascii(0x11, {0x07});
  frame.back() = '!';
  CHECK(fed_notes(f, view(cat({frame, ascii(0x11, {0x07})})), 3, note_frame) ==
        std::vector<frame_note>{frame_event(0x11, {0x07}), failure_event(errc::modbus_ascii_end)});
}

TEST_CASE("ascii framer put(): byte by byte, the results of feed() in chunks (random streams)") {
  splitmix64 rng(0xa5c11);
  const std::vector<bytes> pdus = {{0x03, 0x00, 0x6B, 0x00, 0x03},
                                   {0x07},
                                   {0x83, 0x02},
                                   {0x10, 0x00, 0x01, 0x00, 0x01, 0x02, 0xAB, 0xCD}};
  for (int round = 0; round < 300; ++round) {
    bytes stream;
    for (int part = 0; part < 6; ++part) {
      const std::uint64_t kind = rng.below(6);
      bytes frame = ascii(static_cast<std::uint8_t>(rng.below(3) + 0x10U),
                          pdus[static_cast<std::size_t>(rng.below(4))]);
      if (kind == 0) {  // a character changed
        frame[static_cast<std::size_t>(rng.below(frame.size()))] = rng.byte();
      } else if (kind == 1) {  // cut short
        frame.resize(static_cast<std::size_t>(rng.below(frame.size())));
      } else if (kind == 2) {  // noise
        frame.assign(static_cast<std::size_t>(rng.below(12)), 0);
        for (auto& c : frame) {
          c = rng.byte();
        }
      } else if (kind == 3) {  // lowercase
        for (auto& c : frame) {
          c = static_cast<std::uint8_t>(c >= 'A' && c <= 'F' ? c + 0x20 : c);
        }
      }
      stream.insert(stream.end(), frame.begin(), frame.end());
    }
    const framer_role role = rng.below(2) == 0 ? framer_role::server : framer_role::listener;
    ascii_framer by_feed(role, {0x11});
    ascii_framer by_put(role, {0x11});
    const auto fed =
        fed_notes(by_feed, view(stream), static_cast<std::size_t>(1 + rng.below(40)), note_frame);
    CHECK(put_notes(by_put, view(stream), note_frame) == fed);
    CHECK(by_feed.pending() == by_put.pending());
    CHECK(by_feed.dropped() == by_put.dropped());
  }
  // what put() settles took one character: the one put
  ascii_framer f(framer_role::server, {0x11});
  const bytes frame = ascii(0x11, {0x07});
  for (std::size_t i = 0; i + 1U < frame.size(); ++i) {
    CHECK(!f.put(frame[i]));
  }
  REQUIRE(f.put(frame.back()));
  CHECK(f.result().is_complete());
  CHECK(f.result().consumed() == 1U);
  CHECK(!f.put(':'));
  REQUIRE(f.put('G'));
  CHECK(f.result().error() == errc::modbus_ascii_character);
  CHECK(f.result().consumed() == 1U);
}

namespace {
// A firmware's framer: a `static`, default-constructed (docs/design.md: all zeros, .bss).
const ascii_framer static_framer;
}  // namespace

TEST_CASE("ascii framer: a default-constructed framer is all zeros, the delimiter LF") {
  unsigned char raw[sizeof static_framer] = {};
  std::memcpy(raw, &static_framer, sizeof static_framer);
  std::size_t nonzero = 0;
  for (const unsigned char b : raw) {
    nonzero += b != 0U ? 1U : 0U;
  }
  CHECK(nonzero == 0U);
  CHECK(static_framer.options().delimiter == '\n');
  CHECK(static_framer.options().address == 0U);
  // every delimiter is kept, LF and NUL included
  for (const unsigned d : {0x00U, 0x0AU, 0x21U, 0xFFU}) {
    const ascii_framer f(framer_role::server, {0x11, static_cast<std::uint8_t>(d)});
    CHECK(f.options().delimiter == d);
    CHECK(f.options().address == 0x11U);
  }
  ascii_framer lf;  // the default framer frames with LF
  CHECK(fed_notes(lf, view(ascii(0x00, {0x07})), 4, note_frame) ==
        std::vector<frame_note>{frame_event(0x00, {0x07})});
}

TEST_CASE("decode_ascii: the delimiter after CR may be changed too") {
  std::uint8_t out[max_ascii_bytes] = {};
  bytes frame = ascii(0x11, {0x07});
  CHECK(decode_ascii(view(frame), out, '\n').is_complete());
  CHECK(decode_ascii(view(frame), out, '!').error() == errc::modbus_ascii_end);
  frame.back() = '!';
  const auto r = decode_ascii(view(frame), out, '!');
  REQUIRE(r.is_complete());
  CHECK(r.consumed() == frame.size());
  CHECK(bytes(r->pdu.begin(), r->pdu.end()) == bytes{0x07});
  CHECK(decode_ascii(view(frame), out).error() == errc::modbus_ascii_end);  // LF by default
}

namespace {
// Holding registers 0..9, register i holding 0x100 + i.
struct ten_registers {
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              span<std::uint16_t> out) const {
    if (function != 0x03 || address + out.size() > 10U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = static_cast<std::uint16_t>(0x100U + address + i);
    }
    return 0;
  }
};
}  // namespace

TEST_CASE("ascii server, the recipe of docs/modbus.md §7: serve_frame, then encode_ascii") {
  ten_registers dev;
  ascii_framer rx(framer_role::server, {0x11});
  // FC03 of registers 2..3, then one past the end (exception 02), then a broadcast
  const bytes stream =
      cat({ascii(0x11, {0x03, 0x00, 0x02, 0x00, 0x02}), ascii(0x11, {0x03, 0x00, 0x09, 0x00, 0x02}),
           ascii(0x00, {0x03, 0x00, 0x00, 0x00, 0x01})});
  std::vector<bytes> replies;
  feed_chunks(rx, view(stream), 5, [&](const decode_result<ascii_frame>& r) {
    REQUIRE(r.is_complete());
    const ascii_frame& f = r.value();
    std::uint8_t rtu[max_rtu_size] = {};
    const result<std::size_t> n = serve_frame(dev, 0x11, rtu_frame{f.slave, f.pdu, 0}, rtu);
    REQUIRE(n);
    if (n.value() == 0U) {
      replies.emplace_back();  // a broadcast: executed, not answered
      return true;
    }
    std::uint8_t out[max_ascii_size] = {};
    const auto m = encode_ascii(rtu[0], byte_view(rtu + 1, n.value() - 3U), out);
    REQUIRE(m);
    replies.emplace_back(out, out + m.value());
    return true;
  });
  CHECK(replies == std::vector<bytes>{chars(":11030401020103E1\r\n"), chars(":1183026A\r\n"), {}});
}
