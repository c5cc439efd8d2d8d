// The TCP-to-RTU gateway core (modbus/gateway.hpp) under a script of events the input spells:
// client bytes on three connections (raw, or well-formed MBAP requests), line bytes (raw, or
// a device's answer to the request on the line), time passing, polls, closes. Oracles, from a
// model of the queue the gateway's own steps describe:
//   - every MBAP response is well formed (protocol 0, its length exact); an answer from the
//     line, a broadcast's (by policy) or a 0B goes to a request that was
//     queued, on the line, not answered yet and not dropped by a close: each at most once;
//   - the line carries the requests in the order they were queued (a close takes its
//     connection's out), each a CRC-valid RTU ADU whose PDU decode_request accepts, for an
//     allowed unit, a read under read_only; never a request before the last unicast was
//     answered or its connection closed, never before the turnaround after a broadcast;
//   - a 0B comes no sooner than the response timeout after the request's end;
//   - at the end, with time run on until nothing is due, every queued unicast request of a
//     connection still open was answered (and every answerable broadcast, by policy).
#include <motionbus/modbus/gateway.hpp>
#include <motionbus/modbus/server.hpp>

#include <cstdint>
#include <deque>
#include <vector>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

constexpr std::size_t connections = 3;
constexpr std::size_t queue = 3;

struct line_device {
  std::uint8_t read_registers(std::uint8_t, std::uint16_t address, mb::span<std::uint16_t> out) {
    if (address + out.size() > 16U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = static_cast<std::uint16_t>(address + i);
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t, mb::span<const std::uint16_t>) { return 0; }
  std::uint8_t read_bits(std::uint8_t, std::uint16_t, std::uint16_t, mb::mutable_byte_view) {
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t, std::uint16_t, mb::byte_view) { return 0; }
};

struct input {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at = 0;
  bool empty() const { return at >= size; }
  std::uint8_t byte() { return at < size ? data[at++] : std::uint8_t{0}; }
  mb::byte_view take(std::size_t n) {
    const std::size_t k = n < size - at ? n : size - at;
    const mb::byte_view v(data + at, k);
    at += k;
    return v;
  }
};

struct queued {
  std::uint8_t connection;
  std::uint16_t transaction;
};

struct model {
  mo::gateway_options options;
  mo::basic_gateway<connections, queue> gw;
  std::uint32_t now = 0;
  std::deque<queued> fifo;           // queued, not yet on the line
  std::vector<std::uint8_t> sent;    // the last request on the line
  queued on_line{};                  // its connection and transaction
  bool outstanding = false;          // a unicast on the line, not answered, not orphaned
  bool answerable = false;           // a broadcast on the line whose answer is due by policy
  std::uint32_t request_end = 0;     // of the last request on the line
  std::uint32_t turnaround_end = 0;  // after the last broadcast
  bool after_broadcast = false;

  explicit model(const mo::gateway_options& o) : options(o), gw(o) {}

  static bool reached(std::uint32_t now, std::uint32_t t) { return now - t < 0x80000000U; }

  void check(const mo::gateway_step& s) {
    MOTIONBUS_FUZZ_CHECK(gw.queued() <= queue);
    switch (s.action) {
      case mo::gateway_action::none: break;
      case mo::gateway_action::queued:
        MOTIONBUS_FUZZ_CHECK(s.connection < connections);
        fifo.push_back({s.connection, s.transaction});
        break;
      case mo::gateway_action::close:
        MOTIONBUS_FUZZ_CHECK(s.error == mb::errc::invalid_argument ||
                             s.error == mb::errc::modbus_pdu_length);
        if (s.connection < connections) {
          dropped(s.connection);
        }
        break;
      case mo::gateway_action::to_line: line(s); break;
      case mo::gateway_action::to_client: client(s); break;
    }
  }

  void dropped(std::uint8_t c) {
    for (auto it = fifo.begin(); it != fifo.end();) {
      it = it->connection == c ? fifo.erase(it) : it + 1;
    }
    if (on_line.connection == c) {
      outstanding = false;  // orphaned: its response goes to no one
      answerable = false;
    }
  }

  void line(const mo::gateway_step& s) {
    MOTIONBUS_FUZZ_CHECK(!outstanding && !answerable);
    MOTIONBUS_FUZZ_CHECK(!after_broadcast || reached(now, turnaround_end));
    MOTIONBUS_FUZZ_CHECK(!fifo.empty());
    MOTIONBUS_FUZZ_CHECK(fifo.front().connection == s.connection &&
                         fifo.front().transaction == s.transaction);
    on_line = fifo.front();
    fifo.pop_front();
    const auto f = mo::decode_rtu(s.bytes);
    MOTIONBUS_FUZZ_CHECK(f.is_complete() && f.consumed() == s.bytes.size());
    const std::uint8_t unit = f->slave;
    MOTIONBUS_FUZZ_CHECK(options.units.contains(unit));
    const auto q = mo::decode_request(f->pdu);
    MOTIONBUS_FUZZ_CHECK(q.is_complete());
    const std::uint8_t fn = f->pdu[0];
    if (options.read_only) {
      MOTIONBUS_FUZZ_CHECK(fn == 0x01 || fn == 0x02 || fn == 0x03 || fn == 0x04 || fn == 0x07 ||
                           fn == 0x0B || fn == 0x0C || fn == 0x11 || fn == 0x14 || fn == 0x18 ||
                           fn == 0x08 || fn == 0x2B);
    }
    sent.assign(s.bytes.begin(), s.bytes.end());
    request_end = now + static_cast<std::uint32_t>(s.bytes.size()) * options.line.char_us;
    after_broadcast = unit == 0;
    if (unit == 0) {
      MOTIONBUS_FUZZ_CHECK(fn == 0x05 || fn == 0x06 || fn == 0x0F || fn == 0x10 || fn == 0x15 ||
                           fn == 0x16);
      turnaround_end = request_end + options.turnaround_us;
      answerable = options.answer_broadcasts && fn != 0x15;
    } else {
      outstanding = true;
    }
  }

  void client(const mo::gateway_step& s) {
    MOTIONBUS_FUZZ_CHECK(s.connection < connections);
    const auto t = mo::decode_tcp(s.bytes);
    MOTIONBUS_FUZZ_CHECK(t.is_complete() && t.consumed() == s.bytes.size());
    MOTIONBUS_FUZZ_CHECK(t->protocol == 0 && t->transaction == s.transaction);
    const std::uint8_t e = s.exception;
    if (e == 0x0B) {  // the timeout: the request on the line
      MOTIONBUS_FUZZ_CHECK(outstanding && s.connection == on_line.connection &&
                           s.transaction == on_line.transaction);
      MOTIONBUS_FUZZ_CHECK(reached(now, request_end + options.response_timeout_us));
      MOTIONBUS_FUZZ_CHECK(t->pdu.size() == 2 && t->pdu[0] == (sent[1] | 0x80U));
      outstanding = false;
    } else if (e != 0) {  // the gateway's own answer to the ADU just taken
      MOTIONBUS_FUZZ_CHECK(e == 0x01 || e == 0x02 || e == 0x03 || e == 0x0A);
      MOTIONBUS_FUZZ_CHECK(t->pdu.size() == 2 && (t->pdu[0] & 0x80U) != 0 && t->pdu[1] == e);
    } else if (answerable) {  // a broadcast's answer
      MOTIONBUS_FUZZ_CHECK(s.connection == on_line.connection &&
                           s.transaction == on_line.transaction && t->unit == 0);
      answerable = false;
    } else {  // the line's response
      MOTIONBUS_FUZZ_CHECK(outstanding && s.connection == on_line.connection &&
                           s.transaction == on_line.transaction && t->unit == sent[0]);
      MOTIONBUS_FUZZ_CHECK((t->pdu[0] & 0x7FU) == sent[1]);
      outstanding = false;
    }
  }

  void poll_all() {
    for (int guard = 0;; ++guard) {
      MOTIONBUS_FUZZ_CHECK(guard < 100);
      const mo::gateway_step s = gw.poll(now);
      check(s);
      if (s.action == mo::gateway_action::none) {
        return;
      }
    }
  }

  void from_client(std::size_t c, mb::byte_view in) {
    while (!in.empty()) {
      const mo::gateway_step s = gw.from_client(c, in);
      MOTIONBUS_FUZZ_CHECK(s.consumed > 0 && s.consumed <= in.size());
      in = in.subspan(s.consumed);
      check(s);
      if (s.action == mo::gateway_action::close) {
        MOTIONBUS_FUZZ_CHECK(in.empty());
      }
    }
  }

  void from_line(mb::byte_view in) {
    while (!in.empty()) {
      const mo::gateway_step s = gw.from_line(in, now);
      MOTIONBUS_FUZZ_CHECK(s.consumed > 0 && s.consumed <= in.size());
      MOTIONBUS_FUZZ_CHECK(s.action == mo::gateway_action::none ||
                           s.action == mo::gateway_action::to_client);
      in = in.subspan(s.consumed);
      check(s);
    }
  }
};

// A well-formed request PDU of a few kinds, from the input.
std::vector<std::uint8_t> request_pdu(input& in) {
  const std::uint8_t kind = in.byte();
  const std::uint8_t a = in.byte();
  const std::uint8_t n = static_cast<std::uint8_t>(in.byte() % 4U);
  switch (kind % 6U) {
    case 0: return {0x03, 0, a, 0, n};
    case 1: return {0x06, 0, a, 0, n};
    case 2: return {0x10, 0, a, 0, 1, 2, 0, n};
    case 3: return {0x01, 0, a, 0, n};
    case 4: return {0x08, 0, n, 0, a};
    default: return {0x05, 0, a, n == 0 ? std::uint8_t{0xFF} : std::uint8_t{0}, 0};
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  input in{data, size};
  const std::uint8_t policy = in.byte();
  mo::gateway_options o;
  o.response_timeout_us = 1000U * (1U + in.byte());
  o.turnaround_us = 1000U * in.byte();
  o.line = mo::serial_line_timing((policy & 0x10U) != 0 ? 115200U : 9600U);
  o.read_only = (policy & 1U) != 0;
  o.answer_broadcasts = (policy & 2U) != 0;
  if ((policy & 4U) != 0) {
    o.units = mo::unit_set::none().add(0).add(1).add(2);
  }
  if ((policy & 8U) != 0) {
    o.functions = mo::functions_of(0x03, 0x06, 0x08, 0x10);
  }
  model m(o);
  m.now = static_cast<std::uint32_t>(in.byte()) << 24U;  // near a wrap, sometimes
  line_device dev;
  while (!in.empty()) {
    const std::uint8_t op = in.byte();
    const std::size_t c = (op >> 4U) % connections;
    switch (op & 7U) {
      case 0: m.from_client(c, in.take(in.byte() % 32U)); break;
      case 1: {  // a well-formed MBAP request
        const std::uint16_t transaction = static_cast<std::uint16_t>(in.byte() << 8U | in.byte());
        const std::uint8_t unit = static_cast<std::uint8_t>(in.byte() % 6U);
        const std::vector<std::uint8_t> pdu = request_pdu(in);
        std::uint8_t adu[mo::max_tcp_size] = {};
        const auto n =
            mo::encode_tcp(transaction, unit, mb::byte_view(pdu.data(), pdu.size()), adu);
        m.from_client(c, mb::byte_view(adu, n.value()));
        break;
      }
      case 2: m.from_line(in.take(in.byte() % 16U)); break;
      case 3: {  // the device answers the request on the line (units 1-3), in pieces
        if (m.sent.empty()) {
          break;
        }
        const auto f = mo::decode_rtu(mb::byte_view(m.sent.data(), m.sent.size()));
        std::uint8_t out[mo::max_rtu_size] = {};
        const auto r = mo::serve_units(
            [&](std::uint8_t u) { return u >= 1U && u <= 3U ? &dev : nullptr; }, f.value(), out);
        const std::size_t piece = 1U + in.byte() % 8U;
        for (std::size_t at = 0; at < r.value(); at += piece) {
          const std::size_t k = piece < r.value() - at ? piece : r.value() - at;
          m.now += static_cast<std::uint32_t>(k) * o.line.char_us;
          m.from_line(mb::byte_view(out + at, k));
        }
        break;
      }
      case 4:
        m.now += 100U * in.byte();
        m.poll_all();
        break;
      case 5:
        m.gw.close(c);
        m.dropped(static_cast<std::uint8_t>(c));
        break;
      default: m.poll_all(); break;
    }
  }
  // Liveness: time runs on until nothing is due; every request still owed is answered.
  for (int guard = 0;; ++guard) {
    MOTIONBUS_FUZZ_CHECK(guard < 100);
    m.poll_all();
    const std::uint32_t w = m.gw.wait_us(m.now);
    if (w == ~std::uint32_t{0}) {
      break;
    }
    m.now += w;
  }
  MOTIONBUS_FUZZ_CHECK(m.fifo.empty() && !m.outstanding && !m.answerable);
  MOTIONBUS_FUZZ_CHECK(m.gw.queued() == 0 && !m.gw.awaiting());
  return 0;
}
