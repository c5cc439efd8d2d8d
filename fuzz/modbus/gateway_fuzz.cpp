// The TCP-to-RTU gateway core (modbus/gateway.hpp) under a script of events the input spells:
// client bytes on three connections (raw, or well-formed MBAP requests), line bytes (raw, or
// a device's answer to the request on the line), time passing, polls, closes. Oracles, from a
// model of the queue the gateway's own steps describe:
//   - every MBAP response is well formed (protocol 0, its length exact); an answer from the
//     line, a broadcast's (by policy) or a 0B goes to a request that was
//     queued, on the line, not answered yet and not dropped by a close: each at most once;
//   - the line carries the requests in the order they were queued (a close takes its
//     connection's out), each a CRC-valid RTU ADU of the very unit and PDU the client sent
//     (the model frames each connection's MBAP stream itself), for an allowed unit, a read
//     under read_only, and meeting the Application Protocol's rules for its function
//     (spec_ok: written from the spec, not the decoder under test); never a request before
//     the last unicast was answered or its connection closed, never before the turnaround
//     after a broadcast nor before t3.5 after a 0B;
//   - a 0B comes no sooner than the response timeout after the request's end, and a line
//     response no later than the timeout and the longest frame's time;
//   - a free line with requests queued is never held longer than a turnaround, a longest
//     frame and t3.5 (time jumps of up to 2^32 us included);
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
  std::uint8_t unit;
  std::vector<std::uint8_t> pdu;
};

std::uint16_t be16(const std::vector<std::uint8_t>& v, std::size_t at) {
  return static_cast<std::uint16_t>(v[at] << 8U | v[at + 1U]);
}

// Necessary conditions of a request PDU the gateway may forward, from MODBUS Application
// Protocol V1.1b3 §6 (quantities, byte counts, sizes) and §6.14/6.15 (file records).
bool spec_ok(const std::vector<std::uint8_t>& p) {
  const std::size_t n = p.size();
  if (n < 1U || n > 253U) {
    return false;
  }
  switch (p[0]) {
    case 0x01:
    case 0x02: return n == 5U && be16(p, 3) >= 1U && be16(p, 3) <= 2000U;
    case 0x03:
    case 0x04: return n == 5U && be16(p, 3) >= 1U && be16(p, 3) <= 125U;
    case 0x05: return n == 5U && (be16(p, 3) == 0xFF00U || be16(p, 3) == 0U);
    case 0x06: return n == 5U;
    case 0x0F:
      return n >= 6U && be16(p, 3) >= 1U && be16(p, 3) <= 1968U && p[5] == (be16(p, 3) + 7U) / 8U &&
             n == 6U + p[5];
    case 0x10:
      return n >= 6U && be16(p, 3) >= 1U && be16(p, 3) <= 123U && p[5] == 2U * be16(p, 3) &&
             n == 6U + p[5];
    case 0x16: return n == 7U;
    case 0x17:
      return n >= 10U && be16(p, 3) >= 1U && be16(p, 3) <= 125U && be16(p, 7) >= 1U &&
             be16(p, 7) <= 121U && p[9] == 2U * be16(p, 7) && n == 10U + p[9];
    case 0x14:
    case 0x15: {  // sub-requests: reference type 6, file 1.., records 0..0x270F, length 1..
      if (n < 2U || n != 2U + p[1]) {
        return false;
      }
      std::size_t at = 2;
      while (at < n) {
        if (at + 7U > n || p[at] != 6U || be16(p, at + 1U) == 0U || be16(p, at + 3U) > 0x270FU ||
            be16(p, at + 5U) == 0U) {
          return false;
        }
        at += 7U + (p[0] == 0x15 ? 2U * std::size_t{be16(p, at + 5U)} : 0U);
      }
      return at == n;
    }
    default: return true;  // no rule the gateway applies beyond forwarding
  }
}

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
  std::uint32_t quiet_end = 0;  // t3.5 after the last 0B
  bool after_timeout = false;
  std::vector<std::uint8_t> held[connections];  // each connection's ADU so far (the model's)

  explicit model(const mo::gateway_options& o) : options(o), gw(o) {}

  static bool reached(std::uint32_t now, std::uint32_t t) { return now - t < 0x80000000U; }

  // Time passes by `dt` (up to 2^32 - 1 us): the ends it passes are over, wrap or not.
  void advance(std::uint32_t dt) {
    if (after_broadcast && (reached(now, turnaround_end) || dt >= turnaround_end - now)) {
      after_broadcast = false;
    }
    if (after_timeout && (reached(now, quiet_end) || dt >= quiet_end - now)) {
      after_timeout = false;
    }
    now += dt;
  }

  // The longest a free line with requests queued may wait: a broadcast's bytes and its
  // turnaround, or t3.5; and one transaction's time more, for a clock that looks a little
  // before the quiet period's start (docs/modbus.md §12).
  std::uint64_t longest_quiet() const {
    const std::uint64_t frame = std::uint64_t{mo::max_rtu_size} * options.line.char_us;
    return options.turnaround_us + options.line.t35_us + frame +
           (options.response_timeout_us + options.turnaround_us + 2U * frame);
  }

  void check(const mo::gateway_step& s) {
    MOTIONBUS_FUZZ_CHECK(gw.queued() <= queue);
    switch (s.action) {
      case mo::gateway_action::none: break;
      case mo::gateway_action::queued: {
        MOTIONBUS_FUZZ_CHECK(s.connection < connections);
        // the model's own framing of the ADU just taken: header, length, unit, PDU
        const std::vector<std::uint8_t>& a = held[s.connection];
        MOTIONBUS_FUZZ_CHECK(a.size() >= 8U && a[2] == 0 && a[3] == 0 &&
                             be16(a, 4) == a.size() - 6U && be16(a, 0) == s.transaction);
        fifo.push_back(
            {s.connection, s.transaction, a[6], std::vector<std::uint8_t>(a.begin() + 7, a.end())});
        held[s.connection].clear();
        break;
      }
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
    held[c].clear();
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
    MOTIONBUS_FUZZ_CHECK(!after_timeout || reached(now, quiet_end));
    MOTIONBUS_FUZZ_CHECK(!fifo.empty());
    MOTIONBUS_FUZZ_CHECK(fifo.front().connection == s.connection &&
                         fifo.front().transaction == s.transaction);
    on_line = fifo.front();
    fifo.pop_front();
    const auto f = mo::decode_rtu(s.bytes);
    MOTIONBUS_FUZZ_CHECK(f.is_complete() && f.consumed() == s.bytes.size());
    // the unit and PDU the client sent, byte for byte
    MOTIONBUS_FUZZ_CHECK(s.bytes.size() == on_line.pdu.size() + 3U && s.bytes[0] == on_line.unit);
    for (std::size_t i = 0; i < on_line.pdu.size(); ++i) {
      MOTIONBUS_FUZZ_CHECK(s.bytes[1U + i] == on_line.pdu[i]);
    }
    const std::uint8_t unit = f->slave;
    MOTIONBUS_FUZZ_CHECK(options.units.contains(unit) && unit <= 247U);
    MOTIONBUS_FUZZ_CHECK(spec_ok(on_line.pdu));
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
      after_timeout = true;
      quiet_end = now + options.line.t35_us;
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
      // the deadline wins: none after the timeout and the longest frame's time
      MOTIONBUS_FUZZ_CHECK(
          !reached(now, request_end + options.response_timeout_us +
                            std::uint32_t{mo::max_rtu_size} * options.line.char_us + 1U));
      outstanding = false;
    }
  }

  void poll_all() {
    for (int guard = 0;; ++guard) {
      MOTIONBUS_FUZZ_CHECK(guard < 100);
      const mo::gateway_step s = gw.poll(now);
      check(s);
      if (s.action == mo::gateway_action::none) {
        break;
      }
    }
    if (!gw.awaiting() && !answerable && !fifo.empty()) {  // a free line is never held long
      MOTIONBUS_FUZZ_CHECK(gw.wait_us(now) <= longest_quiet());
    }
  }

  void from_client(std::size_t c, mb::byte_view in) {
    while (!in.empty()) {
      const mo::gateway_step s = gw.from_client(c, in);
      MOTIONBUS_FUZZ_CHECK(s.consumed > 0 && s.consumed <= in.size());
      held[c].insert(held[c].end(), in.begin(),
                     in.begin() + static_cast<std::ptrdiff_t>(s.consumed));
      in = in.subspan(s.consumed);
      check(s);
      if (s.action == mo::gateway_action::to_client) {
        held[c].clear();  // the gateway's own answer to the ADU just taken
      }
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

// A request PDU of many kinds, well formed or a little off, from the input.
std::vector<std::uint8_t> request_pdu(input& in) {
  const std::uint8_t kind = in.byte();
  const std::uint8_t a = in.byte();
  const std::uint8_t n = static_cast<std::uint8_t>(in.byte() % 4U);
  switch (kind % 13U) {
    case 0: return {0x03, 0, a, 0, n};
    case 1: return {0x06, 0, a, 0, n};
    case 2: return {0x10, 0, a, 0, 1, 2, 0, n};
    case 3: return {0x01, 0, a, 0, n};
    case 4: return {0x08, 0, n, 0, a};
    case 5: return {0x05, 0, a, n == 0 ? std::uint8_t{0xFF} : std::uint8_t{0}, 0};
    case 6: return {0x16, 0, a, 0xFF, 0x00, 0x00, n};
    case 7: return {0x17, 0, a, 0, 1, 0, 2, 0, 1, 2, 0, n};
    case 8: return {0x2B, static_cast<std::uint8_t>(n == 0 ? 0x0D : 0x0E), 1, 0};
    case 9: return {static_cast<std::uint8_t>(0x41U + n * 0x11U), a};  // 41 52 63 74: unknown
    case 10:  // FC14: one sub-request; its reference type, file or record off by n
      return {0x14,
              7,
              static_cast<std::uint8_t>(n == 1 ? 5 : 6),
              0,
              static_cast<std::uint8_t>(n == 2 ? 0 : 1),
              static_cast<std::uint8_t>(n == 3 ? 0x27 : 0),
              a,
              0,
              1};
    case 11:  // FC15: one sub-request of one record, or its byte count off
      return {0x15, static_cast<std::uint8_t>(n == 1 ? 8 : 9), 6,    0,   1, 0, a,
              0,    static_cast<std::uint8_t>(n == 2 ? 2 : 1), 0x12, 0x34};
    default: {  // FC14 of two sub-requests, the byte count sometimes not 7 each
      return {0x14, static_cast<std::uint8_t>(n == 1 ? 13 : 14),
              6,    0,
              1,    0,
              a,    0,
              1,    6,
              0,    2,
              0,    0,
              0,    static_cast<std::uint8_t>(n + 1U)};
    }
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
          m.advance(static_cast<std::uint32_t>(k) * o.line.char_us);
          m.from_line(mb::byte_view(out + at, k));
        }
        break;
      }
      case 4:
        m.advance(100U * in.byte());
        m.poll_all();
        break;
      case 6: {  // a large jump for an idle line (the clock wraps); while awaiting the I/O
        // polls by wait_us(), at most the response timeout and a frame's time later
        const std::uint32_t jump = static_cast<std::uint32_t>(in.byte()) << 24U | in.byte();
        m.advance(m.gw.awaiting() ? jump % (1U + m.gw.wait_us(m.now)) : jump);
        m.poll_all();
        break;
      }
      case 5:
        m.gw.close(c);  // (dropped(): the model forgets its bytes and requests)
        m.dropped(static_cast<std::uint8_t>(c));
        break;
      default:  // 7: poll until none; with bit 3, one step (others' bytes may come between)
        if ((op & 8U) != 0) {
          m.check(m.gw.poll(m.now));
        } else {
          m.poll_all();
        }
        break;
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
    m.advance(w);
  }
  MOTIONBUS_FUZZ_CHECK(m.fifo.empty() && !m.outstanding && !m.answerable);
  MOTIONBUS_FUZZ_CHECK(m.gw.queued() == 0 && !m.gw.awaiting());
  return 0;
}
