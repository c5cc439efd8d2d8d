// The T-format stream receiver: frames sized by their CF, byte by byte and in chunks; the
// adapter's echo skipped or missed; garbage and bad frames dropped with no valid frame lost
// behind them; responses checked against the request; idle().
#include "motionbus/tformat/receiver.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "../support/bytes.hpp"
#include "../support/prng.hpp"
#include "../support/stream.hpp"
#include "motionbus/tformat/codec.hpp"

using namespace motionbus;
using namespace motionbus::tformat;

using testutil::view;
using testutil::with_crc;

TEST_CASE("receiver: byte by byte and in chunks, lengths from the CF") {
  const auto a = with_crc({0x1A, 0x00, 0x01, 0x02, 0x01, 0x11, 0x05, 0x00, 0x00, 0x00});
  const auto b = with_crc({0x92, 0x00, 0x11});
  std::vector<std::uint8_t> stream = a;
  stream.insert(stream.end(), b.begin(), b.end());
  for (std::size_t chunk = 1; chunk <= stream.size(); ++chunk) {
    receiver rx;
    std::vector<response> got;
    testutil::feed_chunks(rx, view(stream), chunk, [&](const auto& r) {
      REQUIRE(r.is_complete());
      got.push_back(r.value());
      return true;
    });
    CAPTURE(chunk);
    REQUIRE(got.size() == 2);
    CHECK(got[0].abs == 0x010201);
    CHECK(got[0].abm == 5);
    CHECK(got[1].enid == 0x11);
    CHECK(rx.pending() == 0);
  }
}

TEST_CASE("receiver: echo skipped, garbage dropped, no valid frame lost after a bad one") {
  std::uint8_t req[4] = {};
  const std::size_t n = encode_request(data_id::eeprom_write, 4, 0x99, req).value();
  const auto resp = with_crc({0x32, 0x04, 0x99});

  // The adapter echoes the request (identical bytes to the response!), then the response.
  receiver_options opt;
  opt.echo_mode = echo::expected;
  receiver rx(opt);
  rx.sent(byte_view(req, n));
  std::vector<std::uint8_t> stream(req, req + n);
  stream.insert(stream.end(), resp.begin(), resp.end());
  auto r = rx.feed(byte_view(stream.data(), stream.size()));
  REQUIRE(r.is_complete());
  CHECK(r.consumed() == 8);
  CHECK(r->edf == 0x99);
  CHECK(rx.echoes_skipped() == 4);
  CHECK(rx.feed(byte_view{}).is_incomplete());

  // echo::expected on a line that does not echo (issue 23): the response's CF 0x92 equals
  // the request, but the four bytes decode as the response that answers it (an echo would put
  // the CF where the SF is): delivered, and echo_missed() tells the line does not echo.
  receiver rx2(opt);
  std::uint8_t rq[1] = {};
  (void)encode_request(data_id::read_enid, rq);
  rx2.sent(rq);
  const auto enid = with_crc({0x92, 0x00, 0x11});
  std::vector<std::uint8_t> s2 = enid;
  r = rx2.feed(byte_view(s2.data(), s2.size()));
  REQUIRE(r.is_complete());
  CHECK(r->enid == 0x11);
  CHECK(r.consumed() == 4);
  CHECK(rx2.echo_missed());
  CHECK(rx2.echoes_skipped() == 0);
  CHECK(rx2.dropped() == 0);
  // the same, byte by byte, for every Data ID with a CF-only request; and with the echo there,
  // the echo is still skipped and echo_missed() is false
  for (const data_id id : {data_id::read_abs, data_id::read_abm, data_id::read_enid,
                           data_id::read_all, data_id::reset_errors}) {
    CAPTURE(static_cast<int>(id));
    std::uint8_t q[1] = {};
    (void)encode_request(id, q);
    std::vector<std::uint8_t> frame = {q[0], 0x00};
    frame.resize(layout_of(id).size - 1U, 0x00);
    if (id == data_id::read_enid) {
      frame[2] = 0x11;
    }
    frame = with_crc(frame);
    for (const bool echoed : {false, true}) {
      receiver by_byte(opt);
      by_byte.sent(byte_view(q, 1));
      std::vector<std::uint8_t> line;
      if (echoed) {
        line.push_back(q[0]);
      }
      line.insert(line.end(), frame.begin(), frame.end());
      int complete = 0;
      testutil::put_bytes(by_byte, view(line), [&](const auto& e) {
        complete += e.is_complete() ? 1 : 0;
        return true;
      });
      CHECK(complete == 1);
      CHECK(by_byte.echo_missed() == !echoed);
      CHECK(by_byte.echoes_skipped() == (echoed ? 1U : 0U));
    }
  }
  // an echo and no response: the echo, held to tell it from a response, is skipped at idle()
  receiver quiet(opt);
  quiet.sent(rq);
  CHECK(quiet.feed(byte_view(rq, 1)).is_incomplete());
  CHECK(quiet.idle().is_incomplete());
  CHECK(quiet.echoes_skipped() == 1);

  // Garbage, then a corrupted frame, then a valid one right behind it.
  receiver rx3;
  const auto good = with_crc({0x02, 0x00, 0x10, 0x00, 0x00});
  auto corrupt = good;
  corrupt[3] ^= 0x04;
  std::vector<std::uint8_t> s3 = {0xFF, 0x00, 0x55};
  s3.insert(s3.end(), corrupt.begin(), corrupt.end());
  s3.insert(s3.end(), good.begin(), good.end());
  std::vector<errc> events;
  std::vector<response> frames;
  feed_all(rx3, byte_view(s3.data(), s3.size()), [&](const auto& e) {
    if (e.is_complete()) {
      frames.push_back(e.value());
    } else {
      events.push_back(e.error());
    }
    return true;
  });
  REQUIRE(frames.size() == 1);
  CHECK(frames[0].abs == 0x10);
  REQUIRE(!events.empty());
  CHECK(events[0] == errc::crc_mismatch);
  CHECK(rx3.dropped() >= 3);

  // idle() drops a partial frame
  receiver rx4;
  CHECK(rx4.feed(byte_view(good.data(), 3)).is_incomplete());
  CHECK(rx4.pending() == 3);
  const auto cut = rx4.idle();
  CHECK(cut.error() == errc::truncated);
  CHECK(cut.consumed() == 3);  // the bytes dropped
  CHECK(rx4.idle().is_incomplete());
  CHECK(rx4.pending() == 0);
}

TEST_CASE("receiver: responses checked against the request") {
  receiver rx;
  std::uint8_t rq[1] = {};
  (void)encode_request(data_id::read_abs, rq);
  rx.sent(rq);
  const auto other = with_crc({0x8A, 0x00, 0x01, 0x00, 0x00});
  auto r = rx.feed(byte_view(other.data(), other.size()));
  CHECK(r.error() == errc::tformat_cf_mismatch);
  const auto comm_alarm = with_crc({0x1A, 0x40, 0, 0, 0, 0x11, 0, 0, 0, 0});
  r = rx.feed(byte_view(comm_alarm.data(), comm_alarm.size()));
  CHECK(r.error() == errc::tformat_communication_alarm);
}

TEST_CASE("receiver put(): byte by byte, the results of feed() in chunks (random streams)") {
  // Responses of every layout, their echoes, corrupted and cut-short copies and noise, with
  // and without an echoing line and the check against the request: put() takes the inline
  // paths (a first byte, a byte inside a frame, a frame's last byte) where feed() decides in
  // its scan; both must report the same results in the same order.
  testutil::splitmix64 rng(7);
  const std::vector<std::vector<std::uint8_t>> frames = {
      with_crc({0x1A, 0x00, 0x21, 0x43, 0x01, 0x11, 0x02, 0x00, 0x00, 0x00}),   // ID3
      with_crc({0x02, 0x00, 0x21, 0x43, 0x01}),                                 // ID0
      with_crc({0x92, 0x00, 0x17}),                                             // ID2
      with_crc({0x8A, 0x00, 0x05, 0x00, 0x00}),                                 // ID1
      with_crc({0x32, 0x05, 0x5A}),                                             // ID6 (ADF EDF)
      with_crc({0x1A, 0x40, 0x21, 0x43, 0x01, 0x11, 0x02, 0x00, 0x00, 0x00})};  // ca0 set
  using note = std::vector<std::uint32_t>;
  const auto record = [](const decode_result<response>& r) {
    return note{static_cast<std::uint32_t>(r.status()),
                static_cast<std::uint32_t>(r.error()),
                r.expected(),
                r.received(),
                r.value().abs,
                r.value().cf};
  };
  int complete = 0;
  for (int round = 0; round < 400; ++round) {
    receiver_options opt;
    opt.echo_mode = rng.below(2) == 0 ? echo::expected : echo::none;
    opt.check_against_request = rng.below(2) == 0;
    receiver chunked(opt);
    receiver by_byte(opt);
    const std::uint8_t request[3] = {0x1A, 0x05, 0x5A};
    const std::size_t request_size = rng.below(2) == 0 ? 1U : 3U;
    if (request_size == 3U) {
      const std::uint8_t eeprom[3] = {0x32, 0x05, 0x5A};
      chunked.sent(byte_view(eeprom, 3));
      by_byte.sent(byte_view(eeprom, 3));
    } else {
      chunked.sent(byte_view(request, 1));
      by_byte.sent(byte_view(request, 1));
    }
    std::vector<std::uint8_t> s;
    while (s.size() < 120U) {
      const std::uint64_t kind = rng.below(8);
      if (kind == 0U) {
        s.insert(s.end(), request, request + request_size);  // an echo
      } else if (kind < 6U) {
        auto f = frames[static_cast<std::size_t>(rng.below(frames.size()))];
        if (kind == 4U) {
          testutil::flip_a_byte(rng, f);
        } else if (kind == 5U) {
          testutil::cut_short(rng, f);
        }
        s.insert(s.end(), f.begin(), f.end());
      } else {
        s.push_back(rng.byte());
      }
    }
    const std::size_t chunk = 1U + static_cast<std::size_t>(rng.below(20));
    const std::vector<note> expected = testutil::fed_notes(chunked, view(s), chunk, record);
    const std::vector<note> got = testutil::put_notes(by_byte, view(s), record);
    for (const note& e : expected) {
      complete += e[0] == static_cast<std::uint32_t>(decode_status::complete) ? 1 : 0;
    }
    CAPTURE(round);
    CHECK(got == expected);
    CHECK(by_byte.pending() == chunked.pending());
    CHECK(by_byte.dropped() == chunked.dropped());
  }
  CHECK(complete > 1000);
}

TEST_CASE("receiver: random garbage between valid frames never loses a frame") {
  testutil::splitmix64 rng(42);
  const auto good = with_crc({0x1A, 0x00, 0x21, 0x43, 0x01, 0x11, 0x02, 0x00, 0x00, 0x00});
  for (int round = 0; round < 200; ++round) {
    std::vector<std::uint8_t> s;
    int expected = 0;
    for (int k = 0; k < 5; ++k) {
      const std::size_t garbage = static_cast<std::size_t>(rng.below(6));
      for (std::size_t g = 0; g < garbage; ++g) {
        // garbage that is never a valid CF: break the sync code
        s.push_back(static_cast<std::uint8_t>(rng.byte() | 0x01));
      }
      s.insert(s.end(), good.begin(), good.end());
      ++expected;
    }
    receiver rx;
    int frames = 0;
    feed_all(rx, byte_view(s.data(), s.size()), [&](const auto& e) {
      if (e.is_complete()) {
        ++frames;
        CHECK(e->abs == 0x014321);
      }
      return true;
    });
    CHECK(frames == expected);
  }
}

TEST_CASE(
    "receiver: one byte at a time (a receive interrupt), with garbage, an echo, a bad frame") {
  const auto a = with_crc({0x1A, 0x00, 0x01, 0x02, 0x01, 0x11, 0x05, 0x00, 0x00, 0x00});
  auto bad = a;
  bad[3] ^= 0x40U;                                  // CRC mismatch
  std::vector<std::uint8_t> stream = {0x00, 0xFF};  // garbage: no valid CF
  stream.insert(stream.end(), bad.begin(), bad.end());
  stream.insert(stream.end(), a.begin(), a.end());
  receiver rx;
  CHECK(rx.result().is_incomplete());  // before any
  std::vector<errc> outcomes;
  for (const std::uint8_t byte : stream) {
    if (!rx.put(byte)) {
      continue;
    }
    auto r = rx.result();
    while (!r.is_incomplete()) {
      outcomes.push_back(r.error());
      CHECK(r.consumed() == 1);
      if (r.is_complete()) {
        CHECK(r->abs == 0x010201);
      }
      r = rx.feed(byte_view());  // a rejected frame: rescan what is held
    }
  }
  REQUIRE(outcomes.size() == 2);
  CHECK(outcomes[0] == errc::crc_mismatch);
  CHECK(outcomes[1] == errc::ok);
  CHECK(rx.dropped() >= 2);

  // The echo of the request, byte by byte, then the response.
  receiver echoing(receiver_options{echo::expected});
  const std::uint8_t request[1] = {0x1A};
  echoing.sent(byte_view(request, 1));
  std::vector<std::uint8_t> line = {0x1A};
  line.insert(line.end(), a.begin(), a.end());
  int complete = 0;
  for (const std::uint8_t byte : line) {
    if (echoing.put(byte)) {
      complete += echoing.result().is_complete() ? 1 : 0;
    }
  }
  CHECK(complete == 1);
  CHECK(echoing.echoes_skipped() == 1);
}

TEST_CASE("receiver: a bad frame followed by a whole good one in the same chunk") {
  const auto a = with_crc({0x1A, 0x00, 0x01, 0x02, 0x01, 0x11, 0x05, 0x00, 0x00, 0x00});
  std::vector<std::uint8_t> stream = a;
  stream.insert(stream.end(), a.begin(), a.end());
  stream.push_back(0x1A);                                          // and the start of a third
  stream.at(3) = static_cast<std::uint8_t>(stream.at(3) ^ 0x40U);  // the first: CRC mismatch
  receiver rx;
  const auto first = rx.feed(byte_view(stream.data(), 11));
  CHECK(first.error() == errc::crc_mismatch);
  // The next call takes the good frame: the bad one's bytes after its CF are rescanned, and
  // the good frame is whole once its bytes arrive.
  byte_view rest(stream.data() + 11, stream.size() - 11);
  int complete = 0;
  for (int guard = 0; guard < 40; ++guard) {
    const auto r = rx.feed(rest);
    if (r.is_incomplete()) {
      break;
    }
    rest = rest.subspan(r.consumed());
    complete += r.is_complete() ? 1 : 0;
  }
  CHECK(complete == 1);
  CHECK(rx.pending() == 1);
  CHECK(rx.options().echo_mode == echo::none);
  CHECK(rx.options().check_against_request);
  CHECK(rx.options().decode.res.single_turn_bits == 17);
}

TEST_CASE("receiver: a shorter frame inside a rejected one is found in the bytes held") {
  // An ID3 response with a bad CRC whose fields 1..6 are a whole ID0 response (02 00 05 06 01,
  // CRC 00): rescanned from its second byte, the ID0 frame is decoded from what is held.
  const std::uint8_t line[11] = {0x1A, 0x02, 0x00, 0x05, 0x06, 0x01, 0x00, 0x00, 0x00, 0x00, 0x55};
  receiver rx;
  const auto first = rx.feed(byte_view(line, sizeof line));
  CHECK(first.error() == errc::crc_mismatch);
  const auto second = rx.feed(byte_view());
  REQUIRE(second.is_complete());
  CHECK(second->id == data_id::read_abs);
  CHECK(second->abs == 0x010605);
  CHECK(second.consumed() == 0);  // nothing of this call's (empty) input
}
TEST_CASE("receiver: bytes that are not the awaited echo are parsed as the response") {
  receiver_options opt;
  opt.echo_mode = echo::expected;
  receiver rx(opt);
  std::uint8_t req[4] = {};
  const std::size_t n = encode_request(data_id::eeprom_read, 5, 0, req).value();
  rx.sent(byte_view(req, n));
  // no echo on the line: the response comes straight away; its first two bytes equal the
  // request's (CF, ADF), the third does not
  const std::vector<std::uint8_t> resp = with_crc({0xEA, 0x05, 0x77});
  const auto r = rx.feed(byte_view(resp.data(), resp.size()));
  REQUIRE(r.is_complete());
  CHECK(r->edf == 0x77);
  CHECK(rx.echoes_skipped() == 0);
}

TEST_CASE("receiver: options() gives back each option it was built with") {
  receiver_options opt;
  opt.echo_mode = echo::expected;
  opt.check_against_request = false;
  CHECK(receiver(opt).options().echo_mode == echo::expected);
  CHECK_FALSE(receiver(opt).options().check_against_request);
  receiver_options mt;
  mt.decode.res.multi_turn_bits = 20;  // the multi-turn width alone
  CHECK(receiver(mt).options().decode.res.multi_turn_bits == 20);
  CHECK(receiver(mt).options().decode.res.single_turn_bits == resolution{}.single_turn_bits);
  receiver_options unused;
  unused.decode.check_unused_bits = false;  // the unused-bits check alone
  CHECK_FALSE(receiver(unused).options().decode.check_unused_bits);
  CHECK(receiver(receiver_options{}).options().decode.check_unused_bits);
}

TEST_CASE("receiver: idle() with an echo awaited: part of it, or other bytes, are truncated") {
  receiver_options opt;
  opt.echo_mode = echo::expected;
  receiver rx(opt);
  std::uint8_t req[4] = {};
  const std::size_t n = encode_request(data_id::eeprom_read, 5, 0, req).value();
  REQUIRE(n == 3);
  // one byte of the three-byte echo, then the silence: truncated, the byte dropped
  rx.sent(byte_view(req, n));
  CHECK(rx.feed(byte_view(req, 1)).is_incomplete());
  auto r = rx.idle();
  CHECK(r.error() == errc::truncated);
  CHECK(r.consumed() == 1);
  CHECK(rx.echoes_skipped() == 0);
  // three bytes that are not the request (its last one changed): not the echo, truncated
  rx.sent(byte_view(req, n));
  std::uint8_t other[3] = {req[0], req[1], static_cast<std::uint8_t>(req[2] ^ 0x01U)};
  CHECK(rx.feed(byte_view(other, 3)).is_incomplete());  // a response's first three bytes
  REQUIRE(rx.pending() == 3);
  r = rx.idle();
  CHECK(r.error() == errc::truncated);
  CHECK(r.consumed() == 3);
  CHECK(rx.echoes_skipped() == 0);
  // the whole echo then the silence: skipped, nothing to report
  rx.sent(byte_view(req, n));
  CHECK(rx.feed(byte_view(req, n)).is_incomplete());
  CHECK(rx.idle().is_incomplete());
  CHECK(rx.echoes_skipped() == 3);
  // an empty request awaits no echo
  rx.sent(byte_view());
  CHECK(rx.idle().is_incomplete());
}

TEST_CASE("receiver: echo expected, no echo, an IDD response whose EDF is the request's CRC") {
  // The request EA 06 EC; the response's first three bytes repeat it (its EDF 0xEC is the
  // request's CRC), its fourth is its CRC (0): the response, not an echo (an echo's next byte
  // would be a CF, never 0).
  receiver_options opt;
  opt.echo_mode = echo::expected;
  receiver rx(opt);
  std::uint8_t req[3] = {};
  REQUIRE(encode_request(data_id::eeprom_read, 6, 0, req).value() == 3);
  REQUIRE(req[2] == 0xEC);
  rx.sent(byte_view(req, 3));
  const auto resp = with_crc({0xEA, 0x06, 0xEC});
  REQUIRE(resp[3] == 0x00);
  const auto r = rx.feed(view(resp));
  REQUIRE(r.is_complete());
  CHECK(r->address == 0x06);
  CHECK(r->edf == 0xEC);
  CHECK(r.consumed() == 4);
  CHECK(rx.echo_missed());
  CHECK(rx.echoes_skipped() == 0);
}

namespace {
// put() of every byte of `bytes`; the number of put()s that returned true.
int put_all(receiver& rx, const std::vector<std::uint8_t>& bytes) {
  int settled = 0;
  for (const std::uint8_t b : bytes) {
    settled += rx.put(b) ? 1 : 0;
  }
  return settled;
}
}  // namespace

TEST_CASE("receiver: echo's numbers are interface (the Python binding casts an int)") {
  CHECK(static_cast<int>(echo::none) == 0);
  CHECK(static_cast<int>(echo::expected) == 1);
  receiver_options o;
  o.echo_mode = static_cast<echo>(1);
  CHECK(receiver(o).options().echo_mode == echo::expected);
}

TEST_CASE("receiver: a resolution other than the default in one field alone is used") {
  // ABS of 23 bits (0x7FFFFF) with single_turn_bits 23; ABM of 20 bits with multi_turn_bits 20
  const auto id3 = with_crc({0x1A, 0x00, 0xFF, 0xFF, 0x7F, 0x17, 0xFF, 0xFF, 0x0F, 0x00});
  receiver_options st;
  st.decode.res.single_turn_bits = 23;
  st.decode.res.multi_turn_bits = 20;
  receiver rx(st);
  const auto r = rx.feed(view(id3));
  REQUIRE(r.is_complete());
  CHECK(r->abs == 0x7FFFFF);
  CHECK(r->abm == 0xFFFFF);
  const auto id0 = with_crc({0x02, 0x00, 0xFF, 0xFF, 0x7F});
  receiver_options only_st;
  only_st.decode.res.single_turn_bits = 23;  // the multi-turn bits the default
  receiver a(only_st);
  REQUIRE(a.feed(view(id0)).is_complete());
  const auto id1 = with_crc({0x8A, 0x00, 0xFF, 0xFF, 0x0F});
  receiver_options only_mt;
  only_mt.decode.res.multi_turn_bits = 20;  // the single-turn bits the default
  receiver b(only_mt);
  REQUIRE(b.feed(view(id1)).is_complete());
  CHECK(receiver{}.feed(view(id1)).error() == errc::out_of_range);  // 16 bits by default
}

TEST_CASE("receiver: sent() drops a partial frame and clears the missed echo") {
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  receiver rx;
  const std::uint8_t req[1] = {0x02};
  rx.sent(byte_view(req, 1));
  CHECK(put_all(rx, {0x02, 0x00, 0x40}) == 0);  // part of a response
  CHECK(rx.pending() == 3U);
  rx.sent(byte_view(req, 1));  // sent again: what was held is dropped
  CHECK(rx.pending() == 0U);
  CHECK(put_all(rx, id0) == 1);
  REQUIRE(rx.result().is_complete());
  CHECK(rx.result()->abs == 123456);
  CHECK(rx.result().consumed() == 1U);  // put(): one byte taken

  receiver_options eo;
  eo.echo_mode = echo::expected;
  receiver e(eo);
  e.sent(byte_view(req, 1));
  REQUIRE(e.feed(view(id0)).is_complete());  // the response without the echo
  CHECK(e.echo_missed());
  e.sent(byte_view(req, 1));
  CHECK_FALSE(e.echo_missed());  // "until the next sent()"
}

TEST_CASE("receiver: echo::none skips no echo and misses none") {
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  receiver rx;
  const std::uint8_t req[1] = {0x02};
  rx.sent(byte_view(req, 1));
  const auto r = rx.feed(view(id0));
  REQUIRE(r.is_complete());
  CHECK(r.consumed() == id0.size());
  CHECK_FALSE(rx.echo_missed());
  CHECK(rx.echoes_skipped() == 0U);
  // an empty request frame: nothing to echo, nothing to check
  receiver_options eo;
  eo.echo_mode = echo::expected;
  receiver e(eo);
  e.sent(byte_view{});
  REQUIRE(e.feed(view(id0)).is_complete());
  CHECK_FALSE(e.echo_missed());
  CHECK(e.echoes_skipped() == 0U);
}

TEST_CASE("receiver: feed() of part of a response needs its remaining bytes") {
  receiver rx;
  const auto id3 = with_crc({0x1A, 0x00, 0x01, 0x02, 0x01, 0x11, 0x05, 0x00, 0x00, 0x00});
  const auto r = rx.feed(view(id3).first(5));
  REQUIRE(r.is_incomplete());
  CHECK(r.needed() == 6U);
  const auto r2 = rx.feed(view(id3).subspan(5, 2));
  REQUIRE(r2.is_incomplete());
  CHECK(r2.needed() == 4U);
}

TEST_CASE("receiver: idle() counts what it drops, and a frame after it starts afresh") {
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  receiver rx;
  const auto none = rx.idle();
  REQUIRE(none.is_incomplete());
  CHECK(none.needed() == 1U);
  CHECK(put_all(rx, {0x02, 0x00, 0x40}) == 0);
  const auto cut = rx.idle();
  CHECK(cut.error() == errc::truncated);
  CHECK(cut.consumed() == 3U);
  CHECK(rx.dropped() == 3U);
  CHECK(rx.pending() == 0U);
  CHECK(put_all(rx, id0) == 1);  // byte by byte after the silence
  REQUIRE(rx.result().is_complete());
  CHECK(rx.result()->abs == 123456);
}

TEST_CASE("receiver: an echo held whole at the silence is skipped, and the next bytes are read") {
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  receiver_options eo;
  eo.echo_mode = echo::expected;
  receiver rx(eo);
  const std::uint8_t req[1] = {0x02};
  rx.sent(byte_view(req, 1));
  CHECK_FALSE(rx.put(0x02));  // the echo
  CHECK(rx.idle().is_incomplete());
  CHECK(rx.echoes_skipped() == 1U);
  CHECK(put_all(rx, id0) == 1);  // a response after the silence: read, no echo awaited
  REQUIRE(rx.result().is_complete());
  CHECK(rx.result()->abs == 123456);
  CHECK(rx.echoes_skipped() == 1U);
  CHECK_FALSE(rx.echo_missed());  // the echo came; none was awaited for these bytes
}

TEST_CASE("receiver: a garbage byte after a skipped echo is dropped at once") {
  // An ID6 request's echo is told at its fourth byte (its response is as long: the echo is
  // assumed), then nothing is held
  receiver_options eo;
  eo.echo_mode = echo::expected;
  receiver rx(eo);
  const auto req = with_crc({0x32, 0x05, 0x42});
  rx.sent(view(req));
  CHECK(put_all(rx, req) == 0);  // the echo, skipped
  CHECK(rx.echoes_skipped() == 4U);
  CHECK(rx.pending() == 0U);
  CHECK_FALSE(rx.put(0xFF));  // no CF
  CHECK(rx.dropped() == 1U);
  CHECK(rx.pending() == 0U);
  CHECK(put_all(rx, req) == 1);  // the response, which repeats the request
  REQUIRE(rx.result().is_complete());
  CHECK(rx.result()->edf == 0x42);
  CHECK(rx.result().consumed() == 1U);
}

TEST_CASE("receiver put(): a response without the awaited echo, settled at its last byte") {
  // echo::expected on a line that does not echo: the response's sixth byte tells (an SF, the
  // CRC matching), and the response is settled by that put(), one byte taken
  const auto id0 = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  receiver_options eo;
  eo.echo_mode = echo::expected;
  receiver rx(eo);
  const std::uint8_t req[1] = {0x02};
  rx.sent(byte_view(req, 1));
  CHECK(put_all(rx, id0) == 1);
  REQUIRE(rx.result().is_complete());
  CHECK(rx.result()->abs == 123456);
  CHECK(rx.result().consumed() == 1U);
  CHECK(rx.echo_missed());
}

TEST_CASE("receiver: a communication alarm compares no field: expected() and received() 0") {
  receiver rx;
  const std::uint8_t req[1] = {0x1A};
  rx.sent(byte_view(req, 1));
  const auto r = rx.feed(view(with_crc({0x1A, 0x40, 0, 0, 0, 0x11, 0, 0, 0, 0})));
  CHECK(r.error() == errc::tformat_communication_alarm);
  CHECK(r.expected() == 0U);
  CHECK(r.received() == 0U);
  CHECK(r.consumed() == 11U);
}

TEST_CASE("receiver: a rejected frame's first byte is counted as dropped") {
  auto bad = with_crc({0x02, 0x00, 0x40, 0xE2, 0x01});
  bad[5] ^= 0x01;
  receiver rx;
  const auto r = rx.feed(view(bad));
  CHECK(r.error() == errc::crc_mismatch);
  CHECK(rx.dropped() == 1U);  // the rest is rescanned
  CHECK(rx.pending() == 5U);
}

namespace {

// A receiver that awaits the echo of the one-byte request `cf` it has just sent, with the
// checks against the request off (what follows is another request's response).
receiver echoing_after(std::uint8_t cf) {
  receiver_options eo;
  eo.echo_mode = echo::expected;
  eo.check_against_request = false;
  receiver rx(eo);
  const std::uint8_t req[1] = {cf};
  rx.sent(byte_view(req, 1));
  return rx;
}

}  // namespace

TEST_CASE("receiver: with an echo awaited, a first byte other than the request's is no echo") {
  // ID3 data (an abnormal request's reply) where the echo of ID0's request was awaited
  const auto id3 = with_crc({0x1A, 0x40, 0x01, 0x00, 0x00, 0x11, 0x00, 0x00, 0x00, 0x00});
  receiver rx = echoing_after(0x02);
  const auto r = rx.feed(view(id3));
  REQUIRE(r.is_complete());
  CHECK(r->id == data_id::read_all);
  CHECK(r->abs == 1U);
  CHECK(rx.echoes_skipped() == 0U);
}

TEST_CASE("receiver: a frame held whole behind a skipped echo is reported at once") {
  // ID3's request echoed, then an ENID response (another request's, unchecked) and idle ones:
  // the eleven bytes an ID3 response would be are no response (an echoed CF stands where the
  // SF is), the echo is skipped and the ENID frame behind it is complete
  const auto enid = with_crc({0x92, 0x00, 0x11});
  std::vector<std::uint8_t> line = {0x1A};
  line.insert(line.end(), enid.begin(), enid.end());
  line.insert(line.end(), 6, 0xFF);
  receiver rx = echoing_after(0x1A);
  const auto r = rx.feed(view(line));
  REQUIRE(r.is_complete());
  CHECK(r->id == data_id::read_enid);
  CHECK(r->enid == 0x11);
  CHECK(rx.echoes_skipped() == 1U);
}

TEST_CASE("receiver: an ID6 response that differs from the request is no echo, reported at once") {
  // echo::expected on a line that does not echo; the EEPROM busy: ADF with bit 7, EDF 00
  receiver_options eo;
  eo.echo_mode = echo::expected;
  receiver rx(eo);
  const auto req = with_crc({0x32, 0x05, 0x42});
  rx.sent(view(req));
  const auto r = rx.feed(view(with_crc({0x32, 0x85, 0x00})));
  REQUIRE(r.is_complete());
  CHECK(r->busy);
  CHECK(r->address == 0x05);
  CHECK(r.consumed() == 4U);
  CHECK(rx.echoes_skipped() == 0U);
}

TEST_CASE("receiver: the ENID-driven resolution is an option kept and used") {
  receiver_options o;
  o.decode.resolution_from_enid = true;
  receiver rx(o);
  CHECK(rx.options().decode.resolution_from_enid);
  // ENID 0x17: 23 single-turn bits, an ABS of 0x7FFFFF in range
  const auto id3 = with_crc({0x1A, 0x00, 0xFF, 0xFF, 0x7F, 0x17, 0x00, 0x00, 0x00, 0x00});
  const auto r = rx.feed(view(id3));
  REQUIRE(r.is_complete());
  CHECK(r->abs == 0x7FFFFF);
  CHECK(receiver{}.feed(view(id3)).error() == errc::out_of_range);  // 17 bits by default
}

TEST_CASE("receiver: a default-constructed receiver has the default options") {
  const receiver_options o = receiver{}.options();
  CHECK(o.echo_mode == echo::none);
  CHECK(o.check_against_request);
  CHECK(o.decode.res.single_turn_bits == 17);
  CHECK(o.decode.res.multi_turn_bits == 16);
  CHECK(o.decode.check_unused_bits);
  CHECK_FALSE(o.decode.resolution_from_enid);
}
