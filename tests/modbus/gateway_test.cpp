// The TCP-to-RTU gateway core (modbus/gateway.hpp) driven by a harness: simulated client
// connections, a simulated clock, and devices on the serial line behind a server framer (the
// generic dispatch for units 1-4, the SM unit emulator).
#include "motionbus/modbus/gateway.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "../support/modbus.hpp"
#include "../support/prng.hpp"
#include "motionbus/devices/sm_unit_emulator.hpp"
#include "motionbus/modbus/server.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

namespace {

using line_device = unit_device;  // tests/support/modbus.hpp

bytes mbap(std::uint16_t transaction, std::uint8_t unit, const bytes& pdu) {
  std::uint8_t out[max_tcp_size] = {};
  return output(encode_tcp(transaction, unit, view(pdu), out), out);
}

bytes fc03(std::uint16_t address, std::uint16_t quantity) {
  return {0x03, static_cast<std::uint8_t>(address >> 8U), static_cast<std::uint8_t>(address),
          static_cast<std::uint8_t>(quantity >> 8U), static_cast<std::uint8_t>(quantity)};
}

// The normal response of a line_device of `unit` to fc03(address, quantity).
bytes fc03_answer(std::uint8_t unit, std::uint16_t address, std::uint16_t quantity) {
  bytes out{0x03, static_cast<std::uint8_t>(2U * quantity)};
  for (std::uint16_t i = 0; i < quantity; ++i) {
    out.push_back(unit);
    out.push_back(static_cast<std::uint8_t>(address + i));
  }
  return out;
}

struct reply {
  std::uint16_t transaction;
  std::uint8_t unit;
  std::uint8_t exception;  // the gateway's own, else 0
  bytes pdu;
};

template <std::size_t Connections = 8, std::size_t Queue = 16>
struct harness {
  explicit harness(gateway_options o = {}) : options(o), gw(o) {}

  gateway_options options;
  basic_gateway<Connections, Queue> gw;
  std::uint32_t now = 0;
  std::uint32_t latency_us = 3000;  // from a request's end to its response on the line
  // The line's devices: units 1-4 (a unit without one never answers).
  line_device devices[4] = {{1}, {2}, {3}, {4}};
  std::function<std::size_t(const rtu_frame&, mutable_byte_view)> serve =
      [this](const rtu_frame& f, mutable_byte_view out) {
        return serve_units(
                   [this](std::uint8_t u) -> line_device* {
                     return u == 0 ? &devices[0] : u - 1U < 4U ? &devices[u - 1U] : nullptr;
                   },
                   f, out)
            .value();
      };
  rtu_server_framer device_rx{{1, frame_end::silence, report_id_format::standard, 247}};
  std::vector<bytes> line;  // what the gateway wrote to the line
  std::vector<reply> replies[Connections];
  std::vector<errc> closes[Connections];
  std::size_t chunk = 0;       // the device's response in chunks of this size (0: whole)
  std::uint32_t earliest = 0;  // when the line may take the next request

  void record(const gateway_step& s) {
    if (s.action == gateway_action::to_client) {
      const auto t = decode_tcp(s.bytes);
      REQUIRE(t.is_complete());
      REQUIRE(t.consumed() == s.bytes.size());
      CHECK(t->transaction == s.transaction);
      replies[s.connection].push_back(
          {t->transaction, t->unit, s.exception, bytes(t->pdu.begin(), t->pdu.end())});
    } else if (s.action == gateway_action::close) {
      closes[s.connection].push_back(s.error);
    }
  }

  // Connection c sends `in`, as one chunk; the line runs after it when `run` says so.
  void client(std::size_t c, const bytes& in, bool run = true) {
    feed_client(gw, c, view(in), [&](const gateway_step& s) { record(s); });
    if (run) {
      settle();
    }
  }

  // What is due now: requests onto the line (served by the devices, their responses back to
  // the gateway after latency_us), replies to clients.
  void settle() {
    int steps = 0;
    poll_all(gw, now, [&](const gateway_step& s) {
      REQUIRE(++steps < 1000);
      record(s);
      if (s.action == gateway_action::to_line) {
        // the line is free: t3.5 after the last response, the turnaround after a broadcast
        CHECK(static_cast<std::int32_t>(now - earliest) >= 0);
        line.push_back(bytes(s.bytes.begin(), s.bytes.end()));
        answer(line.back());
      }
    });
  }

  void answer(const bytes& adu) {
    now += static_cast<std::uint32_t>(adu.size()) * options.line.char_us;  // on the line
    earliest = adu[0] == 0 ? now + options.turnaround_us : now;
    auto r = device_rx.feed(view(adu));
    if (r.is_incomplete()) {
      r = device_rx.idle();  // no length rule: the silence after it ends it
    }
    REQUIRE(r.is_complete());
    std::uint8_t out[256] = {};
    const std::size_t n = serve(r.value(), out);
    if (n == 0U) {
      return;
    }
    now += latency_us;
    const std::size_t step = chunk == 0U ? n : chunk;
    for (std::size_t at = 0; at < n; at += step) {
      const byte_view in(out + at, std::min(step, n - at));
      now += static_cast<std::uint32_t>(in.size()) * options.line.char_us;  // received by now
      feed_line(gw, in, now, [&](const gateway_step& s) { record(s); });
    }
    earliest = now + options.line.t35_us;
  }

  // Runs the clock until nothing is due.
  void drain() {
    for (int guard = 0; guard < 1000; ++guard) {
      settle();
      const std::uint32_t w = gw.wait_us(now);
      if (w == ~std::uint32_t{0}) {
        return;
      }
      now += w;
    }
    FAIL("wait_us() never ended");
  }
};

}  // namespace

TEST_CASE("gateway: 8 clients interleaved on one line, each gets its own transactions back") {
  harness<8, 32> h;  // room for every client's 4 pipelined requests
  testutil::splitmix64 rng(25);
  // each client: 4 requests to units 1-4 with its own transaction ids, in random chunks,
  // the connections' chunks interleaved
  bytes streams[8];
  std::size_t at[8] = {};
  for (std::uint8_t c = 0; c < 8; ++c) {
    for (std::uint8_t i = 0; i < 4; ++i) {
      const bytes a = mbap(static_cast<std::uint16_t>(0x1000U * c + i),
                           static_cast<std::uint8_t>(1U + (c + i) % 4U), fc03(c, 1U + i));
      streams[c].insert(streams[c].end(), a.begin(), a.end());
    }
  }
  for (bool left = true; left;) {
    left = false;
    for (std::size_t c = 0; c < 8; ++c) {
      const std::size_t rest = streams[c].size() - at[c];
      if (rest == 0U) {
        continue;
      }
      left = true;
      const std::size_t n =
          std::min<std::size_t>(rest, static_cast<std::size_t>(1U + rng.below(9)));
      h.now += static_cast<std::uint32_t>(rng.below(4000));  // the chunks arrive over time
      h.client(c, bytes(streams[c].begin() + static_cast<std::ptrdiff_t>(at[c]),
                        streams[c].begin() + static_cast<std::ptrdiff_t>(at[c] + n)));
      at[c] += n;
    }
  }
  h.drain();
  CHECK(h.line.size() == 32);
  for (std::uint8_t c = 0; c < 8; ++c) {
    CAPTURE(c);
    REQUIRE(h.replies[c].size() == 4);
    for (std::uint8_t i = 0; i < 4; ++i) {
      const reply& r = h.replies[c][i];
      const auto unit = static_cast<std::uint8_t>(1U + (c + i) % 4U);
      CHECK(r.transaction == 0x1000U * c + i);
      CHECK(r.unit == unit);
      CHECK(r.exception == 0);
      CHECK(r.pdu == fc03_answer(unit, c, static_cast<std::uint16_t>(1U + i)));
    }
    CHECK(h.closes[c].empty());
  }
  CHECK(h.gw.queued() == 0);
  CHECK(h.gw.timeouts() == 0);
  CHECK(h.gw.discarded() == 0);
  CHECK(!h.gw.awaiting());
}

TEST_CASE("gateway: a unit that does not answer gives 0B after the response timeout") {
  gateway_options o;
  o.response_timeout_us = 50000;
  o.line = serial_line_timing(9600);
  harness<2, 4> h(o);
  h.client(0, mbap(7, 9, fc03(0, 2)), false);  // unit 9: no device on the line
  h.client(1, mbap(8, 2, fc03(1, 1)), false);
  gateway_step s = h.gw.poll(h.now);
  REQUIRE(s.action == gateway_action::to_line);
  CHECK(bytes(s.bytes.begin(), s.bytes.end()) == rtu(9, fc03(0, 2)));
  const std::uint32_t end = h.now + 8U * o.line.char_us;  // the request's last byte
  CHECK(h.gw.wait_us(h.now) == end + o.response_timeout_us - h.now);
  CHECK(h.gw.poll(end + o.response_timeout_us - 1U).action == gateway_action::none);
  s = h.gw.poll(end + o.response_timeout_us);
  REQUIRE(s.action == gateway_action::to_client);
  h.record(s);
  CHECK(s.connection == 0);
  CHECK(s.exception == 0x0B);
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].transaction == 7);
  CHECK(h.replies[0][0].unit == 9);
  CHECK(h.replies[0][0].pdu == bytes{0x83, 0x0B});
  CHECK(h.gw.timeouts() == 1);
  // the line goes on with the next request, t3.5 after the timeout at the latest
  h.now = end + o.response_timeout_us;
  h.drain();
  REQUIRE(h.replies[1].size() == 1);
  CHECK(h.replies[1][0].pdu == fc03_answer(2, 1, 1));
  // a response that comes after the timeout is discarded, not sent to anyone
  h.client(0, mbap(9, 9, fc03(0, 2)), false);
  h.now += h.gw.wait_us(h.now);  // t3.5 after the last response
  REQUIRE(h.gw.poll(h.now).action == gateway_action::to_line);
  h.now += 8U * o.line.char_us + o.response_timeout_us;
  s = h.gw.poll(h.now);
  CHECK(s.exception == 0x0B);
  const bytes late = rtu(9, {0x03, 0x04, 0, 0, 0, 0});
  s = h.gw.from_line(view(late), h.now + 100);
  CHECK(s.action == gateway_action::none);
  CHECK(s.consumed == late.size());
  CHECK(h.gw.discarded() == 1);
}

TEST_CASE("gateway: a full queue is answered with 0A at once, the queued requests go on") {
  harness<2, 2> h;
  h.client(0, mbap(1, 1, fc03(0, 1)), false);
  h.client(0, mbap(2, 2, fc03(0, 1)), false);
  CHECK(h.gw.queued() == 2);
  h.client(1, mbap(3, 3, fc03(0, 1)), false);  // full: the gateway is overloaded
  REQUIRE(h.replies[1].size() == 1);
  CHECK(h.replies[1][0].transaction == 3);
  CHECK(h.replies[1][0].exception == 0x0A);
  CHECK(h.replies[1][0].pdu == bytes{0x83, 0x0A});
  CHECK(h.line.empty());
  h.drain();
  REQUIRE(h.replies[0].size() == 2);
  CHECK(h.replies[0][0].transaction == 1);
  CHECK(h.replies[0][1].transaction == 2);
  CHECK(h.replies[0][1].pdu == fc03_answer(2, 0, 1));
  // room again: the same request now goes through
  h.client(1, mbap(4, 3, fc03(0, 1)));
  h.drain();
  REQUIRE(h.replies[1].size() == 2);
  CHECK(h.replies[1][1].pdu == fc03_answer(3, 0, 1));
}

TEST_CASE("gateway: a broadcast is forwarded, never answered, and followed by the turnaround") {
  gateway_options o;
  o.turnaround_us = 200000;
  harness<2, 4> h(o);
  h.client(0, mbap(5, 0, {0x06, 0, 1, 0x12, 0x34}), false);
  h.client(1, mbap(6, 3, fc03(2, 1)), false);
  gateway_step s = h.gw.poll(h.now);
  REQUIRE(s.action == gateway_action::to_line);
  CHECK(bytes(s.bytes.begin(), s.bytes.end()) == rtu(0, {0x06, 0, 1, 0x12, 0x34}));
  h.answer(bytes(s.bytes.begin(), s.bytes.end()));
  CHECK(h.devices[0].writes == 1);  // executed by the device the line's lookup gives for 0
  const std::uint32_t end = 8U * o.line.char_us;
  CHECK(h.gw.poll(end + o.turnaround_us - 1U).action == gateway_action::none);
  CHECK(h.gw.wait_us(end) == o.turnaround_us);
  h.now = end + o.turnaround_us;
  h.drain();
  CHECK(h.replies[0].empty());  // never answered
  REQUIRE(h.replies[1].size() == 1);
  CHECK(h.replies[1][0].pdu == fc03_answer(3, 2, 1));
  CHECK(h.line.size() == 1);  // the FC03 (the broadcast was written above)
  // a broadcast read has no path (broadcasts are writes, Serial Line §2.1)
  h.client(0, mbap(7, 0, fc03(0, 1)));
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].pdu == bytes{0x83, 0x0A});
}

TEST_CASE("gateway: answer_broadcasts answers a broadcast write once it is on the line") {
  gateway_options o;
  o.answer_broadcasts = true;
  harness<1, 2> h(o);
  h.client(0, mbap(0x55AA, 0, {0x10, 0, 1, 0, 2, 4, 0, 1, 0, 2}));
  h.drain();
  REQUIRE(h.line.size() == 1);
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].transaction == 0x55AA);
  CHECK(h.replies[0][0].unit == 0);
  CHECK(h.replies[0][0].pdu == bytes{0x10, 0, 1, 0, 2});
}

TEST_CASE("gateway: requests are checked before the line; allow-lists and read-only") {
  gateway_options o;
  o.units = unit_set::none().add(1).add(2);
  o.functions = functions_of(0x03, 0x06, 0x08);
  harness<1, 4> h(o);
  const auto own = [&](const bytes& adu) {
    h.replies[0].clear();
    h.client(0, adu);
    REQUIRE(h.replies[0].size() == 1);
    return h.replies[0][0].pdu;
  };
  CHECK(own(mbap(1, 3, fc03(0, 1))) == bytes{0x83, 0x0A});                   // unit not allowed
  CHECK(own(mbap(1, 0, {0x06, 0, 1, 0, 1})) == bytes{0x86, 0x0A});           // nor broadcasts
  CHECK(own(mbap(1, 248, fc03(0, 1))) == bytes{0x83, 0x0A});                 // no such slave
  CHECK(own(mbap(1, 1, {0x10, 0, 1, 0, 1, 2, 0, 1})) == bytes{0x90, 0x01});  // function
  CHECK(own(mbap(1, 1, fc03(0, 0))) == bytes{0x83, 0x03});                   // PDU: quantity 0
  CHECK(own(mbap(1, 1, fc03(0xFFFF, 2))) == bytes{0x83, 0x02});              // past 0xFFFF
  CHECK(own(mbap(1, 1, {0x83, 0x02})) == bytes{0x83, 0x01});                 // an exception
  CHECK(h.line.empty());  // none of them reached the line
  CHECK(own(mbap(1, 2, {0x06, 0, 1, 0, 1})) == bytes{0x06, 0, 1, 0, 1});  // allowed: forwarded
  CHECK(h.line.size() == 1);

  gateway_options ro;
  ro.read_only = true;
  harness<1, 4> r(ro);
  const auto answer = [&](const bytes& adu) {
    r.replies[0].clear();
    r.client(0, adu);
    r.drain();
    REQUIRE(r.replies[0].size() == 1);
    return r.replies[0][0];
  };
  CHECK(answer(mbap(1, 1, {0x06, 0, 1, 0, 1})).pdu == bytes{0x86, 0x01});
  CHECK(answer(mbap(1, 1, {0x10, 0, 1, 0, 1, 2, 0, 1})).pdu == bytes{0x90, 0x01});
  CHECK(answer(mbap(1, 1, {0x17, 0, 1, 0, 1, 0, 2, 0, 1, 2, 0, 3})).pdu == bytes{0x97, 0x01});
  CHECK(answer(mbap(1, 1, {0x08, 0, 1, 0, 0})).pdu == bytes{0x88, 0x01});  // restart comms
  CHECK(answer(mbap(1, 1, {0x41, 1, 2})).pdu == bytes{0xC1, 0x01});        // unknown: may write
  CHECK(r.line.empty());
  const reply read = answer(mbap(1, 4, fc03(3, 2)));
  CHECK(read.exception == 0);
  CHECK(read.pdu == fc03_answer(4, 3, 2));
  // Return Query Data goes through (the line's device has no FC08: it answers 01 itself)
  const reply echo = answer(mbap(1, 1, {0x08, 0, 0, 0xAB, 0xCD}));
  CHECK(echo.exception == 0);
  CHECK(echo.pdu == bytes{0x88, 0x01});
  CHECK(r.devices[0].writes + r.devices[3].writes == 0);
  CHECK(r.line.size() == 2);
}

TEST_CASE("gateway: bad MBAP input closes that connection; the others and the line go on") {
  harness<4, 8> h;
  h.client(3, mbap(30, 1, fc03(0, 1)), false);  // queued before the bad input
  bytes proto = mbap(1, 1, fc03(0, 1));
  proto[3] = 1;  // protocol id 1
  h.client(0, bytes(proto.begin(), proto.begin() + 4), false);
  CHECK(h.closes[0] == std::vector<errc>{errc::invalid_argument});
  bytes huge = mbap(2, 1, fc03(0, 1));
  huge[4] = 0x01;  // length 0x0106: an ADU over 260 bytes
  h.client(1, huge, false);
  CHECK(h.closes[1] == std::vector<errc>{errc::modbus_pdu_length});
  bytes lies = mbap(3, 1, fc03(0, 1));
  lies.push_back(0x00);  // one byte more than FC03 has, and the length counts it
  lies[5] = static_cast<std::uint8_t>(lies[5] + 1U);
  h.client(2, lies, false);
  CHECK(h.closes[2] == std::vector<errc>{errc::modbus_pdu_length});
  bytes short_one = mbap(4, 1, {0x10, 0, 1, 0, 2, 4, 0, 1, 0, 2});
  short_one[5] = static_cast<std::uint8_t>(short_one[5] - 2U);  // its byte count says 4 more
  short_one.resize(short_one.size() - 2U);
  h.client(2, short_one, false);  // a slot closed and used again: a new connection
  CHECK(h.closes[2].size() == 2);
  bytes empty = mbap(5, 1, fc03(0, 1));
  empty[5] = 1;  // the unit alone, no PDU
  h.client(0, bytes(empty.begin(), empty.begin() + 7), false);
  CHECK(h.closes[0].size() == 2);
  CHECK(h.closes[3].empty());
  h.drain();
  REQUIRE(h.replies[3].size() == 1);  // the good connection is answered
  CHECK(h.replies[3][0].transaction == 30);
  CHECK(h.replies[3][0].pdu == fc03_answer(1, 0, 1));
  for (std::size_t c = 0; c < 3; ++c) {
    CHECK(h.replies[c].empty());
  }
  CHECK(h.line.size() == 1);
  // a closed slot starts afresh: a whole request there now works
  h.client(1, mbap(11, 2, fc03(4, 2)));
  h.drain();
  REQUIRE(h.replies[1].size() == 1);
  CHECK(h.replies[1][0].pdu == fc03_answer(2, 4, 2));
  // a connection index the gateway has no slot for
  const gateway_step s = h.gw.from_client(4, view(mbap(1, 1, fc03(0, 1))));
  CHECK(s.action == gateway_action::close);
  CHECK(s.error == errc::invalid_argument);
}

TEST_CASE("gateway: half a header then nothing; close() drops the connection and its queue") {
  harness<3, 8> h;
  const bytes a = mbap(1, 1, fc03(0, 1));
  h.client(0, bytes(a.begin(), a.begin() + 3), false);  // half a header, then silence
  h.client(1, mbap(2, 2, fc03(0, 1)), false);
  h.client(1, mbap(3, 3, fc03(0, 1)), false);
  h.client(2, mbap(4, 4, fc03(0, 1)), false);
  CHECK(h.gw.queued() == 3);
  const gateway_step first = h.gw.poll(h.now);  // connection 1's first request on the line
  REQUIRE(first.action == gateway_action::to_line);
  h.gw.close(0);  // the I/O's idle timeout
  h.gw.close(1);  // connection 1 goes: its queued request is dropped, its request on the
                  // line runs to its end and the response goes to no one
  CHECK(h.gw.queued() == 1);
  CHECK(h.gw.dropped() == 1);
  h.answer(bytes(first.bytes.begin(), first.bytes.end()));
  h.drain();
  CHECK(h.replies[0].empty());
  CHECK(h.replies[1].empty());
  REQUIRE(h.replies[2].size() == 1);
  CHECK(h.replies[2][0].transaction == 4);
  CHECK(h.line.size() == 1);  // connection 2's (the first was written above)
  // connection 0's slot, used again: the half header before close() is gone
  h.client(0, mbap(5, 1, fc03(1, 1)));
  h.drain();
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].transaction == 5);
  h.gw.close(7);  // no such slot: nothing
  CHECK(h.gw.queued() == 0);
}

TEST_CASE("gateway: the SM unit emulator behind it answers as through serve_rtu") {
  devices::sm_unit::emulator emu;
  devices::sm_unit::emulator direct;
  harness<1, 2> h;
  h.serve = [&](const rtu_frame& f, mutable_byte_view out) {
    return serve_frame(emu, 1, f, out).value();
  };
  for (const bytes& pdu : {fc03(0, 3), fc03(100, 8), bytes{0x04, 0x01, 0x2C, 0x00, 0x02},
                           bytes{0x06, 0, 0, 0, 5}, bytes{0x11}}) {
    h.replies[0].clear();
    h.client(0, mbap(0x4242, 1, pdu));
    h.drain();
    REQUIRE(h.replies[0].size() == 1);
    CHECK(h.replies[0][0].pdu == serve_pdu(direct, 1, pdu));
  }
  CHECK(h.gw.timeouts() == 0);
}

TEST_CASE("gateway: a response in pieces, frames that are no response, an unknown function") {
  harness<1, 2> h;
  h.chunk = 1;  // the response byte by byte, char_us apart
  h.client(0, mbap(1, 2, fc03(0, 3)));
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].pdu == fc03_answer(2, 0, 3));
  // another function from the addressed slave, then the response: the first is discarded
  h.client(0, mbap(2, 3, fc03(1, 1)), false);
  CHECK(h.gw.poll(h.now).action == gateway_action::none);  // t3.5 after the last response
  CHECK(h.gw.wait_us(h.now) == h.options.line.t35_us);
  h.now += h.gw.wait_us(h.now);
  gateway_step s = h.gw.poll(h.now);
  REQUIRE(s.action == gateway_action::to_line);
  const bytes wrong = rtu(3, {0x06, 0, 1, 0, 1});
  s = h.gw.from_line(view(wrong), h.now);
  CHECK(s.action == gateway_action::none);  // held: no length rule for 06 after an 03
  CHECK(h.gw.wait_us(h.now) == h.options.line.t35_us);
  h.now += h.options.line.t35_us;
  CHECK(h.gw.poll(h.now).action == gateway_action::none);  // the silence ends it
  CHECK(h.gw.discarded() == 1);
  CHECK(h.gw.awaiting());
  const bytes right = rtu(3, fc03_answer(3, 1, 1));
  s = h.gw.from_line(view(right), h.now);
  REQUIRE(s.action == gateway_action::to_client);
  CHECK(s.consumed == right.size());
  // a function the length rule does not know: the t3.5 silence ends its response
  h.serve = [](const rtu_frame& f, mutable_byte_view out) {
    return encode_rtu(f.slave, byte_view(bytes{0x41, 9, 8, 7}.data(), 4), out).value();
  };
  h.chunk = 0;
  h.replies[0].clear();
  h.client(0, mbap(3, 1, {0x41, 1}));
  CHECK(h.replies[0].empty());     // held until the silence
  CHECK(h.gw.wait_us(h.now) > 0);  // t3.5 from its last byte
  h.drain();
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].pdu == bytes{0x41, 9, 8, 7});
}

TEST_CASE("gateway: the clock may wrap") {
  gateway_options o;
  o.response_timeout_us = 10000;
  harness<1, 2> h(o);
  h.now = 0xFFFFF000U;
  h.earliest = h.now;
  h.client(0, mbap(1, 9, fc03(0, 1)));  // no answer: the timeout runs across the wrap
  h.client(0, mbap(2, 1, fc03(0, 1)));
  CHECK(h.replies[0].empty());
  h.drain();
  REQUIRE(h.replies[0].size() == 2);
  CHECK(h.replies[0][0].exception == 0x0B);
  CHECK(h.replies[0][1].pdu == fc03_answer(1, 0, 1));
  CHECK(h.now < 0x1000000U);
}

TEST_CASE("gateway: a broadcast's answer or a 0B for a connection closed meanwhile goes nowhere") {
  gateway_options o;
  o.answer_broadcasts = true;
  o.response_timeout_us = 20000;
  harness<2, 4> h(o);
  h.client(0, mbap(1, 0, {0x06, 0, 1, 0, 2}), false);
  REQUIRE(h.gw.poll(h.now).action == gateway_action::to_line);
  CHECK(h.gw.wait_us(h.now) == 0);             // its answer is due
  h.gw.close(0);                               // before the I/O polls for it
  h.client(1, mbap(2, 9, fc03(0, 1)), false);  // no device: will time out
  h.drain();
  CHECK(h.replies[0].empty());
  REQUIRE(h.replies[1].size() == 1);
  CHECK(h.replies[1][0].exception == 0x0B);
  // a request on the line whose connection goes: no 0B for it, the next request goes on
  h.client(1, mbap(3, 9, fc03(0, 1)), false);
  h.client(0, mbap(4, 1, fc03(0, 1)), false);
  h.now += h.gw.wait_us(h.now);
  REQUIRE(h.gw.poll(h.now).action == gateway_action::to_line);
  h.gw.close(1);
  CHECK(h.gw.awaiting());  // the line's timing is kept
  h.drain();
  CHECK(h.replies[1].size() == 1);
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].pdu == fc03_answer(1, 0, 1));
  CHECK(h.gw.timeouts() == 2);
  // FC15 (write file record) broadcast: no normal response the codec builds, so none
  h.client(0, mbap(5, 0, {0x15, 0x09, 0x06, 0, 1, 0, 0, 0, 1, 0x12, 0x34}));
  h.drain();
  CHECK(h.replies[0].size() == 1);
  CHECK(h.line.back()[1] == 0x15);
}

TEST_CASE("gateway: read_only lets Read Device Identification and Return Query Data through") {
  gateway_options o;
  o.read_only = true;
  harness<1, 2> h(o);
  h.client(0, mbap(1, 1, {0x2B, 0x0E, 0x01, 0x00}));
  h.client(0, mbap(2, 1, {0x2B, 0x0D, 0x01, 0x00}));  // CANopen: may write
  h.client(0, mbap(3, 1, {0x08, 0x00}));              // too short to tell: refused
  h.drain();
  REQUIRE(h.replies[0].size() == 3);
  CHECK(h.replies[0][0].transaction == 1);  // forwarded: the device has no FC2B, its 01
  CHECK(h.replies[0][0].exception == 0);
  CHECK(h.replies[0][0].pdu == bytes{0xAB, 0x01});
  CHECK(h.replies[0][1].transaction == 2);
  CHECK(h.replies[0][1].exception == 0x01);  // refused by the gateway: CANopen
  CHECK(h.replies[0][2].transaction == 3);
  CHECK(h.replies[0][2].exception == 0x01);
  CHECK(h.replies[0][2].pdu == bytes{0x88, 0x01});
  CHECK(h.line.size() == 1);
  // a function above 63 is refused when the function set is not all of them
  gateway_options f;
  f.functions = functions_of(0x03);
  harness<1, 2> g(f);
  g.client(0, mbap(1, 1, {0x41, 0x00}));
  REQUIRE(g.replies[0].size() == 1);
  CHECK(g.replies[0][0].pdu == bytes{0xC1, 0x01});
  // a count missing from an FC10: not a lying length (the rule cannot tell), an exception 03
  g.options.functions = all_functions;
  harness<1, 2> k;
  k.client(0, mbap(1, 1, {0x10, 0x00, 0x01, 0x00}));
  REQUIRE(k.replies[0].size() == 1);
  CHECK(k.replies[0][0].pdu == bytes{0x90, 0x03});
  CHECK(k.closes[0].empty());
}

TEST_CASE("gateway: line bytes nobody asked for, and garbage while a response is awaited") {
  harness<1, 2> h;
  const bytes stray = rtu(1, fc03_answer(1, 0, 1));
  CHECK(h.gw.from_line(view(stray), 0).consumed == stray.size());
  CHECK(h.gw.from_line(byte_view{}, 0).consumed == 0);
  CHECK(h.gw.discarded() == 1);
  CHECK(h.gw.wait_us(0) == ~std::uint32_t{0});  // nothing due, ever
  h.client(0, mbap(1, 1, fc03(0, 1)), false);
  const std::uint32_t t35 = h.options.line.t35_us;
  CHECK(h.gw.wait_us(0) == t35);  // the line is free t3.5 after the stray bytes
  CHECK(h.gw.poll(t35 - 1U).action == gateway_action::none);
  REQUIRE(h.gw.poll(t35).action == gateway_action::to_line);
  // from the slave asked, an FC03 whose byte count wants more than an RTU frame can hold, and
  // more: held to a full buffer, resynchronised, and no response
  bytes garbage(300, 0x00);
  garbage[0] = 0x01;
  garbage[1] = 0x03;
  garbage[2] = 0xFF;
  std::size_t at = 0;
  while (at < garbage.size()) {
    const gateway_step s =
        h.gw.from_line(byte_view(garbage.data() + at, garbage.size() - at), t35 + 9U);
    CHECK(s.action == gateway_action::none);
    at += s.consumed;
  }
  CHECK(h.gw.awaiting());
  h.now = t35 + 9U;
  h.drain();  // the silence fails what is held (discarded), then the timeout answers
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].exception == 0x0B);
  CHECK(h.gw.discarded() == 2);
  CHECK(h.gw.wait_us(h.now) == ~std::uint32_t{0});
}

TEST_CASE("gateway: a line that never falls silent does not hold the gateway") {
  gateway_options o;
  o.response_timeout_us = 10000;
  harness<1, 2> h(o);
  h.client(0, mbap(1, 9, fc03(0, 1)), false);
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const std::uint32_t deadline = 8U * o.line.char_us + o.response_timeout_us;
  const std::uint32_t last_call = deadline + 256U * o.line.char_us;
  const std::uint8_t babble[1] = {0x55};
  std::uint32_t t = 0;
  for (; t < last_call + 10U * o.line.char_us; t += o.line.char_us) {
    // from_line itself answers 0B once its time is past the last call (the deadline wins)
    gateway_step s = h.gw.from_line(byte_view(babble, 1), t);
    if (s.action == gateway_action::none) {
      CHECK(h.gw.wait_us(t) <= o.line.t35_us);
      s = h.gw.poll(t);
    }
    if (s.action != gateway_action::none) {
      CHECK(s.exception == 0x0B);
      break;
    }
  }
  CHECK(t >= last_call);  // not before the longest frame's time past the deadline
  CHECK(t < last_call + o.line.char_us);
  CHECK(h.gw.timeouts() == 1);
  CHECK(!h.gw.awaiting());
}

TEST_CASE("gateway: idle for 2^31..2^32 us, the next request still goes on the line at once") {
  harness<1, 2> h;
  h.client(0, mbap(1, 1, fc03(0, 1)));  // answered: the line is quiet for t3.5 after it
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.gw.wait_us(h.now) == ~std::uint32_t{0});
  for (const std::uint32_t idle : {0x80000000U, 2400000000U, 0xC0000000U}) {
    CAPTURE(idle);
    h.now += idle;
    h.earliest = h.now;
    h.client(0, mbap(2, 1, fc03(0, 1)), false);
    CHECK(h.gw.wait_us(h.now) == 0);  // (was up to 35.8 min: a deadline gone stale)
    const gateway_step s = h.gw.poll(h.now);
    REQUIRE(s.action == gateway_action::to_line);
    h.answer(bytes(s.bytes.begin(), s.bytes.end()));
  }
  CHECK(h.replies[0].size() == 4);
  // idle for all but a moment of 2^32 us: the time looks a little before the quiet period
  // (as a clock read before the bytes it reports): a wait of one transaction's time at most
  h.now += 0xFFFFFF00U;
  h.client(0, mbap(3, 1, fc03(0, 1)), false);
  const std::uint32_t transaction = h.options.response_timeout_us + h.options.turnaround_us +
                                    2U * 256U * h.options.line.char_us + h.options.line.t35_us;
  CHECK(h.gw.wait_us(h.now) <= transaction);
}

TEST_CASE("gateway: a broadcast's answer is its own, whatever is answered before it is due") {
  gateway_options o;
  o.answer_broadcasts = true;
  harness<2, 4> h(o);
  h.client(0, mbap(0x1111, 0, {0x06, 0, 1, 0x12, 0x34}), false);
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  h.client(1, mbap(0x2222, 250, fc03(0, 1)), false);  // 0A to connection 1 in between
  REQUIRE(h.replies[1].size() == 1);
  CHECK(h.replies[1][0].pdu == bytes{0x83, 0x0A});
  h.record(h.gw.poll(0));
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].transaction == 0x1111);
  CHECK(h.replies[0][0].unit == 0);
  CHECK(h.replies[0][0].pdu == bytes{0x06, 0, 1, 0x12, 0x34});
}

TEST_CASE("gateway: after a 0B a late response is discarded, not taken for the next request") {
  gateway_options o;
  o.response_timeout_us = 100000;
  harness<2, 4> h(o);
  h.client(0, mbap(0xA, 1, fc03(0, 1)), false);
  h.client(1, mbap(0xB, 1, fc03(0, 1)), false);
  gateway_step s = h.gw.poll(0);
  REQUIRE(s.action == gateway_action::to_line);
  const bytes a_answer = rtu(1, {0x03, 0x02, 0xAA, 0xAA});  // the slave's answer to A...
  const std::uint32_t deadline = 8U * o.line.char_us + o.response_timeout_us;
  s = h.gw.poll(deadline);
  CHECK(s.exception == 0x0B);
  CHECK(s.connection == 0);
  CHECK(h.gw.poll(deadline).action == gateway_action::none);  // t3.5 of silence first
  CHECK(h.gw.wait_us(deadline) == o.line.t35_us);
  // ...sent late, within that t3.5: discarded, and the line is quiet t3.5 after it again
  const std::uint32_t late = deadline + 2000U;
  s = h.gw.from_line(view(a_answer), late);
  CHECK(s.action == gateway_action::none);
  CHECK(h.gw.discarded() == 1);
  CHECK(h.gw.poll(late + o.line.t35_us - 1U).action == gateway_action::none);
  s = h.gw.poll(late + o.line.t35_us);
  REQUIRE(s.action == gateway_action::to_line);
  CHECK(s.connection == 1);
  // the deadline wins: a response that begins after it is not taken, though poll() has not
  // run since; from_line answers the 0B
  const std::uint32_t b_deadline = late + o.line.t35_us + 8U * o.line.char_us + 100000U;
  const bytes b_answer = rtu(1, fc03_answer(1, 0, 1));
  s = h.gw.from_line(view(b_answer), b_deadline + 10U);
  CHECK(s.action == gateway_action::to_client);
  CHECK(s.consumed == b_answer.size());  // taken (and not framed)
  CHECK(s.connection == 1);
  CHECK(s.exception == 0x0B);
  CHECK(h.gw.timeouts() == 2);
  CHECK(h.gw.discarded() == 2);
  CHECK(!h.gw.awaiting());
}

TEST_CASE("gateway: FC14/15 requests are checked as a server checks them before the line") {
  harness<1, 4> h;
  h.client(0, mbap(1, 1, {0x14}), false);                          // no byte count: 03
  h.client(0, mbap(2, 1, {0x14, 7, 5, 0, 1, 0, 0, 0, 1}), false);  // reference type 5: 02
  h.client(0, mbap(3, 1, {0x14, 7, 6, 0, 0, 0, 0, 0, 1}), false);  // file 0: 02
  h.client(0, mbap(4, 1, {0x15, 9, 6, 0, 1, 0, 0, 0, 2, 0x12, 0x34}), false);  // cut: 03
  REQUIRE(h.replies[0].size() == 4);
  CHECK(h.replies[0][0].pdu == bytes{0x94, 0x03});
  CHECK(h.replies[0][1].pdu == bytes{0x94, 0x02});
  CHECK(h.replies[0][2].pdu == bytes{0x94, 0x02});
  CHECK(h.replies[0][3].pdu == bytes{0x95, 0x03});
  CHECK(h.gw.queued() == 0);
  h.client(0, mbap(5, 1, {0x14, 7, 6, 0, 1, 0, 0, 0, 1}), false);  // a good one goes on
  CHECK(h.gw.queued() == 1);
  h.drain();
  CHECK(h.line.size() == 1);
}

TEST_CASE("gateway: a response timeout too long for the clock is clamped; connection 256") {
  gateway_options o;
  o.response_timeout_us = 0xFFFFFFFFU;  // (was an immediate 0B: its deadline wrapped)
  harness<1, 2> h(o);
  h.client(0, mbap(1, 9, fc03(0, 1)), false);
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const std::uint32_t deadline = 8U * o.line.char_us + (std::uint32_t{1} << 30U);  // the clamp
  CHECK(h.gw.poll(1000).action == gateway_action::none);
  CHECK(h.gw.wait_us(0) == deadline);
  CHECK(h.gw.poll(deadline - 1U).action == gateway_action::none);
  CHECK(h.gw.poll(deadline).exception == 0x0B);
  // a slot past 255 is named 255 (none), not its low byte (a live connection)
  const bytes a = mbap(2, 1, fc03(0, 1));
  const gateway_step s = h.gw.from_client(256, view(a));
  CHECK(s.action == gateway_action::close);
  CHECK(s.connection == 255);
  CHECK(s.error == errc::invalid_argument);
  CHECK(s.consumed == a.size());  // all of it taken: the I/O's loop ends
  int steps = 0;
  feed_client(h.gw, 1, view(a), [&](const gateway_step& c) {
    CHECK(c.action == gateway_action::close);
    CHECK(c.connection == 1);
    REQUIRE(++steps < 10);
  });
  CHECK(steps == 1);
}

TEST_CASE("gateway: bytes during a broadcast's turnaround keep it, near its end extend it") {
  gateway_options o;
  o.turnaround_us = 100000;
  harness<1, 2> h(o);
  h.client(0, mbap(1, 0, {0x06, 0, 1, 0, 2}), false);
  h.client(0, mbap(2, 1, fc03(0, 1)), false);
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const std::uint32_t end = 8U * o.line.char_us + o.turnaround_us;  // of the turnaround
  const bytes noise{0x55, 0xAA};
  CHECK(h.gw.from_line(view(noise), 10000).action == gateway_action::none);
  CHECK(h.gw.wait_us(10000) == end - 10000U);  // not shortened to t3.5
  CHECK(h.gw.from_line(view(noise), end - 10U).action == gateway_action::none);
  CHECK(h.gw.wait_us(end - 10U) == o.line.t35_us);  // t3.5 after the last byte heard
  CHECK(h.gw.poll(end).action == gateway_action::none);
  CHECK(h.gw.poll(end - 10U + o.line.t35_us).action == gateway_action::to_line);
  CHECK(h.gw.discarded() == 2);
}

TEST_CASE(
    "gateway: gateway_options::fc11 frames the line's FC11 responses in the device's layout") {
  // The SM unit's FC11 answer: two version bytes, no byte count (SM unit guideline §11).
  const auto sm_fc11 = [](const rtu_frame& f, mutable_byte_view out) {
    const std::uint8_t pdu[] = {0x11, 0x02, 0x03};
    return f.pdu.size() == 1U && f.pdu[0] == 0x11 ? encode_rtu(f.slave, byte_view(pdu), out).value()
                                                  : std::size_t{0};
  };
  gateway_options o;
  o.fc11 = report_id_format::two_bytes_no_count;
  harness<1, 2> sm(o);
  sm.serve = sm_fc11;
  sm.client(0, mbap(0x0711, 1, bytes{0x11}));
  // taken at its last byte, as the layout sizes it: no silence waited for
  REQUIRE(sm.replies[0].size() == 1);
  CHECK(sm.replies[0][0].transaction == 0x0711);
  CHECK(sm.replies[0][0].exception == 0);
  CHECK(sm.replies[0][0].pdu == bytes{0x11, 0x02, 0x03});

  // The specification's layout (the default) reads 02 as a byte count: the frame is one byte
  // short of it, so the response is not taken at its last byte, only once t3.5 of silence has
  // ended it (poll), and then forwarded as it is.
  harness<1, 2> standard;
  standard.serve = sm_fc11;
  standard.client(0, mbap(0x0711, 1, bytes{0x11}));
  CHECK(standard.replies[0].empty());
  const std::uint32_t last_byte = standard.now;
  standard.drain();
  REQUIRE(standard.replies[0].size() == 1);
  CHECK(standard.replies[0][0].exception == 0);
  CHECK(standard.replies[0][0].pdu == bytes{0x11, 0x02, 0x03});
  CHECK(standard.now - last_byte >= standard.options.line.t35_us);
}

TEST_CASE("gateway: read_only refuses the other diagnostics and an MEI request without its type") {
  gateway_options o;
  o.read_only = true;
  harness<1, 2> h(o);
  h.client(0, mbap(1, 1, {0x08, 0x00, 0x01, 0x00, 0x00}));  // Restart Communications
  h.client(0, mbap(2, 1, {0x08, 0x01, 0x00, 0x00, 0x00}));  // sub-function 0x0100
  h.client(0, mbap(3, 1, {0x2B}));                          // no MEI type
  h.drain();
  REQUIRE(h.replies[0].size() == 3);
  for (std::size_t i = 0; i < 3; ++i) {
    CAPTURE(i);
    CHECK(h.replies[0][i].transaction == i + 1U);
    CHECK(h.replies[0][i].exception == 0x01);
  }
  CHECK(h.line.empty());
}

TEST_CASE("gateway: a response cut short, then silence past the last call: dropped, then 0B") {
  gateway_options o;
  o.response_timeout_us = 10000;
  harness<1, 2> h(o);
  h.client(0, mbap(1, 9, fc03(0, 1)), false);
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const std::uint32_t deadline = 8U * o.line.char_us + o.response_timeout_us;
  const std::uint32_t last_call = deadline + 256U * o.line.char_us;
  // the first 3 of a response's 7 bytes, then nothing: held (the framer cannot end it)
  const bytes part = {0x09, 0x03, 0x02};
  const std::uint32_t heard = 12U * o.line.char_us;
  CHECK(h.gw.from_line(view(part), heard).action == gateway_action::none);
  CHECK(h.gw.wait_us(heard) == o.line.t35_us);  // the silence that ends what is held
  // the I/O wakes up only past the last call (a time already reached: wait 0), where the
  // bytes held are too late to be a response: dropped, and the timeout answers
  CHECK(h.gw.wait_us(last_call) == 0);
  const gateway_step s = h.gw.poll(last_call);
  REQUIRE(s.action == gateway_action::to_client);
  CHECK(s.exception == 0x0B);
  CHECK(h.gw.discarded() == 1);
  CHECK(h.gw.timeouts() == 1);
  CHECK(!h.gw.awaiting());
}

TEST_CASE("unit_set: removing a unit removes that unit alone, for each of the 256") {
  for (unsigned u = 0; u < 256U; ++u) {
    CAPTURE(u);
    unit_set s;  // all
    s.remove(static_cast<std::uint8_t>(u));
    unsigned wrong = 0;
    for (unsigned v = 0; v < 256U; ++v) {
      wrong += s.contains(static_cast<std::uint8_t>(v)) == (v != u) ? 0U : 1U;
    }
    CHECK(wrong == 0U);
    s.add(static_cast<std::uint8_t>(u));
    CHECK(s.contains(static_cast<std::uint8_t>(u)));
  }
}

TEST_CASE("unit_set::none() holds no unit, for each of the 256") {
  const unit_set none = unit_set::none();
  unsigned held = 0;
  for (unsigned u = 0; u < 256U; ++u) {
    held += none.contains(static_cast<std::uint8_t>(u)) ? 1U : 0U;
  }
  CHECK(held == 0U);
  // a gateway allowed one unit answers every other with 0A, nothing on the line
  gateway_options o;
  o.units = unit_set::none().add(1);
  harness<1, 2> h(o);
  for (unsigned u = 2; u <= 247U; ++u) {
    h.client(0, mbap(static_cast<std::uint16_t>(u), static_cast<std::uint8_t>(u), fc03(0, 1)));
  }
  REQUIRE(h.replies[0].size() == 246);
  unsigned refused = 0;
  for (const reply& r : h.replies[0]) {
    refused += r.exception == 0x0A ? 1U : 0U;
  }
  CHECK(refused == 246U);
  CHECK(h.line.empty());
}

TEST_CASE("line_timing's default is 19200 baud 8E1; serial_line_timing's is one stop bit") {
  const line_timing d{};
  const line_timing even_one = serial_line_timing(19200, parity::even, 1);
  CHECK(d.char_us == even_one.char_us);  // 11 bits at 19200 baud: 572.9 us
  CHECK(d.t35_us == even_one.t35_us);
  CHECK(d.char_us == character_time_us(19200, parity::even, 1));
  CHECK(d.t35_us == t35_us(19200, parity::even, 1));
  const line_timing defaults = serial_line_timing(19200);  // parity even, one stop bit
  CHECK(defaults.char_us == even_one.char_us);
  CHECK(defaults.t35_us == even_one.t35_us);
  CHECK(serial_line_timing(9600, parity::none).char_us == character_time_us(9600, parity::none, 1));
}

TEST_CASE("gateway_options' defaults: a 1 s response timeout, a 100 ms turnaround") {
  const gateway_options d{};
  CHECK(d.response_timeout_us == 1000000U);
  CHECK(d.turnaround_us == 100000U);           // Serial Line §2.4.1: typically 100 to 200 ms
  harness<1, 4> h;                             // the defaults, in use
  h.client(0, mbap(1, 9, fc03(0, 1)), false);  // no device at 9
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const std::uint32_t end = 8U * d.line.char_us;
  CHECK(h.gw.poll(end + 999999U).action == gateway_action::none);
  const gateway_step s = h.gw.poll(end + 1000000U);
  CHECK(s.action == gateway_action::to_client);
  CHECK(s.exception == 0x0B);
  // a broadcast, then the turnaround before the next request
  const std::uint32_t t0 = end + 1000000U + d.line.t35_us;
  h.client(0, mbap(2, 0, {0x06, 0, 1, 0, 2}), false);
  h.client(0, mbap(3, 1, fc03(0, 1)), false);
  REQUIRE(h.gw.poll(t0).action == gateway_action::to_line);
  const std::uint32_t after = t0 + 8U * d.line.char_us + 100000U;
  CHECK(h.gw.poll(after - 1U).action == gateway_action::none);
  CHECK(h.gw.poll(after).action == gateway_action::to_line);
}

TEST_CASE("gateway_step: a default step is none, naming nothing; other steps keep its defaults") {
  const gateway_step d{};
  CHECK(d.action == gateway_action::none);
  CHECK(d.connection == 0);
  CHECK(d.exception == 0);
  CHECK(d.error == errc::ok);
  CHECK(d.transaction == 0);
  CHECK(d.bytes.empty());
  CHECK(d.consumed == 0);
  harness<2, 2> h;
  h.client(1, mbap(0x1234, 1, fc03(0, 1)), false);
  const gateway_step s = h.gw.poll(0);  // to_line: connection, transaction and bytes
  REQUIRE(s.action == gateway_action::to_line);
  CHECK(s.connection == 1);
  CHECK(s.transaction == 0x1234);
  CHECK(s.exception == 0);
  CHECK(s.error == errc::ok);
  CHECK(s.consumed == 0);  // (poll takes no bytes)
  const gateway_step none = h.gw.poll(1);
  CHECK(none.action == gateway_action::none);
  CHECK(none.connection == 0);
  CHECK(none.transaction == 0);
  CHECK(none.consumed == 0);
}

TEST_CASE("gateway: read_only forwards every read, Return Query Data and MEI 0E however short") {
  gateway_options o;
  o.read_only = true;
  harness<1, 16> h(o);
  const bytes reads[] = {
      {0x01, 0, 0, 0, 1},
      {0x02, 0, 0, 0, 1},
      {0x03, 0, 0, 0, 1},
      {0x04, 0, 0, 0, 1},
      {0x07},
      {0x0B},
      {0x0C},
      {0x11},
      {0x14, 7, 6, 0, 1, 0, 0, 0, 1},
      {0x18, 0, 0},
      {0x08, 0, 0},  // Return Query Data with no data
  };
  std::uint16_t id = 0;
  for (const bytes& pdu : reads) {
    h.client(0, mbap(++id, 9, pdu), false);  // unit 9: none answers, nothing to wait for
  }
  CHECK(h.replies[0].empty());  // none refused
  CHECK(h.gw.queued() == 11);
  // a Read Device Identification too short to be one is refused by the PDU's own check (03),
  // not by read_only (01): its MEI type says it is a read
  h.client(0, mbap(12, 9, {0x2B, 0x0E}), false);
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].pdu == bytes{0xAB, 0x03});
  // the writes are refused, each with 01
  h.replies[0].clear();
  const bytes writes[] = {{0x05, 0, 1, 0xFF, 0},
                          {0x06, 0, 1, 0, 1},
                          {0x0F, 0, 0, 0, 8, 1, 0xFF},
                          {0x10, 0, 1, 0, 1, 2, 0, 1},
                          {0x15, 9, 6, 0, 1, 0, 0, 0, 1, 0x12, 0x34},
                          {0x16, 0, 1, 0xFF, 0xFF, 0, 0},
                          {0x12},
                          {0x19}};
  for (const bytes& pdu : writes) {
    h.client(0, mbap(++id, 9, pdu), false);
  }
  REQUIRE(h.replies[0].size() == 8);
  for (const reply& r : h.replies[0]) {
    CHECK(r.exception == 0x01);
  }
  // the reads go on the line as they came
  h.drain();
  REQUIRE(h.line.size() == 11);
  for (std::size_t i = 0; i < 11; ++i) {
    CAPTURE(i);
    CHECK(h.line[i] == rtu(9, reads[i]));
  }
}

TEST_CASE("gateway: broadcasts of each write go on the line; FC17, a read too, has no path") {
  harness<1, 8> h;
  const bytes writes[] = {{0x05, 0, 1, 0xFF, 0},
                          {0x06, 0, 1, 0, 1},
                          {0x0F, 0, 0, 0, 8, 1, 0xFF},
                          {0x10, 0, 1, 0, 1, 2, 0, 1},
                          {0x15, 9, 6, 0, 1, 0, 0, 0, 1, 0x12, 0x34},
                          {0x16, 0, 1, 0xFF, 0xFF, 0, 0}};
  std::uint16_t id = 0;
  for (const bytes& pdu : writes) {
    h.client(0, mbap(++id, 0, pdu), false);
  }
  h.client(0, mbap(++id, 0, {0x17, 0, 1, 0, 1, 0, 2, 0, 1, 2, 0, 3}), false);
  REQUIRE(h.replies[0].size() == 1);  // the FC17 alone
  CHECK(h.replies[0][0].transaction == 7);
  CHECK(h.replies[0][0].pdu == bytes{0x97, 0x0A});
  h.drain();
  REQUIRE(h.line.size() == 6);
  for (std::size_t i = 0; i < 6; ++i) {
    CAPTURE(i);
    CHECK(h.line[i] == rtu(0, writes[i]));
  }
  CHECK(h.replies[0].size() == 1);  // broadcasts are not answered
}

TEST_CASE("gateway: unit 247, the last slave address, goes on the line") {
  harness<1, 2> h;
  h.client(0, mbap(1, 247, fc03(0, 1)), false);
  CHECK(h.replies[0].empty());
  const gateway_step s = h.gw.poll(0);
  REQUIRE(s.action == gateway_action::to_line);
  CHECK(bytes(s.bytes.begin(), s.bytes.end()) == rtu(247, fc03(0, 1)));
}

TEST_CASE("gateway: a function set of all but one refuses the functions 64 and up") {
  gateway_options o;
  o.functions = ~function_set{0} & ~(function_set{1} << 5U);  // all but 05: not all_functions
  harness<1, 2> h(o);
  for (const unsigned code : {0x40U, 0x41U, 0x64U, 0x7FU}) {
    const auto f = static_cast<std::uint8_t>(code);
    CAPTURE(f);
    h.replies[0].clear();
    h.client(0, mbap(1, 1, {f, 0x01}));
    REQUIRE(h.replies[0].size() == 1);
    CHECK(h.replies[0][0].exception == 0x01);
    CHECK(h.replies[0][0].pdu == bytes{static_cast<std::uint8_t>(f | 0x80U), 0x01});
  }
  h.replies[0].clear();
  h.client(0, mbap(2, 1, {0x05, 0, 1, 0xFF, 0}));
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].pdu == bytes{0x85, 0x01});
  CHECK(h.line.empty());
}

TEST_CASE("gateway: close() in the middle of an ADU; the slot's next request is framed afresh") {
  harness<1, 2> h;
  const bytes a = mbap(1, 1, {0x10, 0, 1, 0, 2, 4, 0, 1, 0, 2});  // 17 bytes
  h.client(0, bytes(a.begin(), a.begin() + 9), false);            // its header and more: size known
  h.gw.close(0);
  h.client(0, mbap(2, 2, fc03(0, 1)));  // 12 bytes: a whole request of its own
  h.drain();
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].transaction == 2);
  CHECK(h.replies[0][0].pdu == fc03_answer(2, 0, 1));
  CHECK(h.closes[0].empty());
}

TEST_CASE("gateway: bytes held at the last call, then more: from_line's 0B discards them") {
  gateway_options o;
  o.response_timeout_us = 10000;
  harness<1, 2> h(o);
  h.client(0, mbap(1, 9, fc03(0, 1)), false);
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const std::uint32_t deadline = 8U * o.line.char_us + o.response_timeout_us;
  const std::uint32_t last_call = deadline + 256U * o.line.char_us;
  const bytes part = {0x09, 0x03, 0x02};
  CHECK(h.gw.from_line(view(part), 12U * o.line.char_us).action == gateway_action::none);
  CHECK(h.gw.discarded() == 0);
  // no poll since: the next bytes come past the last call; the held ones are too late
  const bytes rest = {0x00, 0x01};
  const gateway_step s = h.gw.from_line(view(rest), last_call);
  REQUIRE(s.action == gateway_action::to_client);
  CHECK(s.exception == 0x0B);
  CHECK(s.consumed == rest.size());
  CHECK(h.gw.discarded() == 2);  // the bytes held, and these
  CHECK(h.gw.timeouts() == 1);
  CHECK(!h.gw.awaiting());
}

TEST_CASE("gateway: the longest request (a 253-byte PDU) goes on the line whole") {
  harness<2, 2> h;
  bytes pdu(253, 0xFF);  // FC08 Return Query Data, 250 data bytes: an MBAP length of 254
  pdu[0] = 0x08;
  pdu[1] = 0x00;
  pdu[2] = 0x00;
  h.client(0, mbap(1, 9, pdu), false);
  CHECK(h.gw.queued() == 1);
  h.gw.close(2);  // the first slot past the last: no such slot, nothing changes
  h.gw.close(1);  // a connection with nothing queued
  CHECK(h.gw.queued() == 1);
  CHECK(h.gw.dropped() == 0);
  const gateway_step s = h.gw.poll(0);
  REQUIRE(s.action == gateway_action::to_line);
  CHECK(bytes(s.bytes.begin(), s.bytes.end()) == rtu(9, pdu));  // 256 bytes, the longest ADU
}

TEST_CASE("gateway: basic_gateway<1, 1>, one connection and a queue of one, forwards each") {
  harness<1, 1> h;
  for (std::uint16_t i = 0; i < 3; ++i) {
    CAPTURE(i);
    h.client(0, mbap(i, 2, fc03(i, 1)));
    h.drain();
    REQUIRE(h.replies[0].size() == i + 1U);
    CHECK(h.replies[0][i].transaction == i);
    CHECK(h.replies[0][i].pdu == fc03_answer(2, i, 1));
    CHECK(h.line.back() == rtu(2, fc03(i, 1)));
  }
  CHECK(h.line.size() == 3);
}

TEST_CASE("gateway: a time one transaction's length before a quiet period counts as inside it") {
  harness<1, 2> h;
  const gateway_options& o = h.options;
  const std::uint32_t heard = 5000000;
  const bytes stray{0x55};
  CHECK(h.gw.from_line(view(stray), heard).action == gateway_action::none);  // quiet for t3.5
  h.client(0, mbap(1, 1, fc03(0, 1)), false);
  CHECK(h.gw.wait_us(heard) == o.line.t35_us);
  // one transaction: the response timeout, the turnaround and two of the longest frames
  const std::uint32_t transaction =
      o.response_timeout_us + o.turnaround_us + 2U * 256U * o.line.char_us;
  CHECK(h.gw.wait_us(heard - transaction) == transaction + o.line.t35_us);  // inside: the wait
  CHECK(h.gw.poll(heard - transaction).action == gateway_action::none);
  CHECK(h.gw.wait_us(heard - transaction - 1U) == 0);  // any earlier: past it
  CHECK(h.gw.poll(heard - transaction - 1U).action == gateway_action::to_line);
}

TEST_CASE("gateway: a response after garbage the framer gives up on, in the same chunk, is taken") {
  // 300 bytes from the slave asked, FC03, that frame nothing: the framer holds them to a full
  // buffer and fails on them there (its length rule, then the CRC, rule them out) in the
  // middle of the chunk; the I/O's loop hands on the rest, which ends with the response
  testutil::splitmix64 rng(247);
  bytes in{0x01, 0x03};
  for (int i = 0; i < 298; ++i) {
    in.push_back(rng.byte());
  }
  const bytes response = rtu(1, {0x03, 0x02, 0xAB, 0xCD});
  in.insert(in.end(), response.begin(), response.end());
  harness<1, 2> h;
  h.client(0, mbap(7, 1, fc03(0, 1)), false);
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const gateway_step first = h.gw.from_line(view(in), 5000);
  CHECK(first.action == gateway_action::none);
  CHECK(first.consumed < in.size());  // up to the failure: the rest is the next call's
  h.now = 5000;
  feed_line(h.gw, byte_view(in.data() + first.consumed, in.size() - first.consumed), h.now,
            [&](const gateway_step& s) { h.record(s); });
  h.drain();
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].transaction == 7);
  CHECK(h.replies[0][0].exception == 0);
  CHECK(h.replies[0][0].pdu == bytes{0x03, 0x02, 0xAB, 0xCD});
  CHECK(h.gw.timeouts() == 0);
}

TEST_CASE(
    "gateway: a deadline is past from it to under 2^31 us after it (half the clock's range)") {
  // The deadlines live on half the wrapping clock's range (gateway_options, docs/modbus.md
  // §12): a time less than 2^31 us after one is at or past it; 2^31 after it is 2^31 before.
  harness<1, 2> h;
  h.client(0, mbap(1, 9, fc03(0, 1)), false);  // no device at 9
  REQUIRE(h.gw.poll(0).action == gateway_action::to_line);
  const std::uint32_t deadline = 8U * h.options.line.char_us + h.options.response_timeout_us;
  CHECK(h.gw.wait_us(deadline + 0x80000000U) == 0x80000000U);
  CHECK(h.gw.poll(deadline + 0x80000000U).action == gateway_action::none);
  CHECK(h.gw.wait_us(deadline + 0x7FFFFFFFU) == 0);
  const gateway_step s = h.gw.poll(deadline + 0x7FFFFFFFU);
  CHECK(s.action == gateway_action::to_client);
  CHECK(s.exception == 0x0B);
}

TEST_CASE("gateway: a new gateway's clock just before the wrap; a response its silence ends") {
  // No quiet period has begun: the next request goes t3.5 after the response's last byte,
  // wherever the I/O's clock starts (here 0.5 s before it wraps)
  harness<1, 2> h;
  h.serve = [](const rtu_frame& f, mutable_byte_view out) {
    return encode_rtu(f.slave, byte_view(bytes{0x41, 9, 8, 7}.data(), 4), out).value();
  };
  h.now = 0U - 500000U;
  h.earliest = h.now;
  h.client(0, mbap(1, 1, {0x41, 1}));  // no length rule: the t3.5 silence ends its response
  CHECK(h.replies[0].empty());
  h.now += h.gw.wait_us(h.now);
  h.settle();
  REQUIRE(h.replies[0].size() == 1);
  CHECK(h.replies[0][0].pdu == bytes{0x41, 9, 8, 7});
  h.client(0, mbap(2, 2, fc03(0, 1)));  // and the I/O's poll_all after it
  REQUIRE(h.line.size() == 2);          // at once: t3.5 of silence is over already
  CHECK(h.line[1] == rtu(2, fc03(0, 1)));
}

TEST_CASE("gateway: a line timing with no t3.5: bytes heard do not hold the next request") {
  gateway_options o;
  o.line.t35_us = 0;
  harness<1, 2> h(o);
  const bytes stray{0x55};
  CHECK(h.gw.from_line(view(stray), 0).action == gateway_action::none);
  CHECK(h.gw.discarded() == 1);
  h.client(0, mbap(1, 1, fc03(0, 1)), false);
  CHECK(h.gw.wait_us(0) == 0);
  CHECK(h.gw.poll(0).action == gateway_action::to_line);
}

// A new gateway has had no quiet period: its quiet_from_ of 0 is no start of one. (Until
// session 24 it was: quiet() and wait_us() asked quiet_left() with quiet_len_ 0, and a time up
// to one transaction's length before 0, mod 2^32, counted as inside it; the survivors of
// lines 551 and 604 led to it.)
TEST_CASE("gateway: a new gateway's first stray bytes hold the line t3.5, wherever its clock is") {
  harness<1, 2> h;
  const std::uint32_t t35 = h.options.line.t35_us;
  const std::uint32_t heard = 0xFFFF0000U;  // the I/O's clock, 65.5 ms before it wraps
  const bytes stray{0x55};
  CHECK(h.gw.from_line(view(stray), heard).action == gateway_action::none);
  h.client(0, mbap(1, 1, fc03(0, 1)), false);
  CHECK(h.gw.wait_us(heard) == t35);                                // was 65536
  CHECK(h.gw.poll(heard + t35).action == gateway_action::to_line);  // was none until 0
  // and wait_us() with no quiet period at all: a response ended by its silence at a clock
  // 0.5 s before the wrap, then a request: poll() sends it at once, wait_us() says to wait
  harness<1, 2> k;
  k.serve = [](const rtu_frame& f, mutable_byte_view out) {
    return encode_rtu(f.slave, byte_view(bytes{0x41, 9, 8, 7}.data(), 4), out).value();
  };
  k.now = 0U - 500000U;
  k.earliest = k.now;
  k.client(0, mbap(1, 1, {0x41, 1}));
  k.now += k.gw.wait_us(k.now);
  k.settle();
  REQUIRE(k.replies[0].size() == 1);
  k.client(0, mbap(2, 2, fc03(0, 1)), false);
  CHECK(k.gw.wait_us(k.now) == 0);  // was 488118, though poll(k.now) sent it
}

TEST_CASE("gateway_action's numbers are the header's: an I/O may log or export them") {
  // the numbers the enumeration writes out (the meter's gateway harness exports an action as
  // its number); a step that closes a connection is 4
  CHECK(static_cast<unsigned>(gateway_action::none) == 0);
  CHECK(static_cast<unsigned>(gateway_action::queued) == 1);
  CHECK(static_cast<unsigned>(gateway_action::to_client) == 2);
  CHECK(static_cast<unsigned>(gateway_action::to_line) == 3);
  CHECK(static_cast<unsigned>(gateway_action::close) == 4);
}

TEST_CASE("gateway: from_line with no bytes is no byte: the silence that ends a response holds") {
  // an I/O that calls from_line with every read, also those that found nothing: a response
  // whose function gives no length ends t3.5 after its last byte, not after the last call
  basic_gateway<1, 2> gw{gateway_options{}};
  const std::uint32_t t35 = gateway_options{}.line.t35_us;
  const bytes request = mbap(7, 1, {0x41, 0x01});
  REQUIRE(gw.from_client(0, view(request)).action == gateway_action::queued);
  REQUIRE(gw.poll(0).action == gateway_action::to_line);
  std::uint8_t adu[16] = {};
  const std::uint8_t pdu[] = {0x41, 0x09, 0x08, 0x07};
  const auto n = encode_rtu(1, byte_view(pdu, sizeof pdu), mutable_byte_view(adu, sizeof adu));
  REQUIRE(n.ok());
  const std::uint32_t last = 10000;
  CHECK(gw.from_line(byte_view(adu, n.value()), last).action == gateway_action::none);
  const std::uint8_t nothing[1] = {};
  for (std::uint32_t at = last + 100U; at < last + t35; at += 100U) {
    CAPTURE(at);
    CHECK(gw.from_line(byte_view(nothing, 0), at).consumed == 0U);
  }
  CHECK(gw.wait_us(last + t35 - 1U) == 1U);
  const gateway_step s = gw.poll(last + t35);
  REQUIRE(s.action == gateway_action::to_client);
  CHECK(s.transaction == 7);
}
