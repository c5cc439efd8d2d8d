// Modbus RTU over TCP: the RTU framer with frame_end::length (no t3.5 silence on a byte
// stream), server and client. Oracles: a reference written from the length rules alone (its
// own table, from the Application Protocol's PDU layouts: request_size(), response_size(); at
// each position: the size the rule gives as bytes arrive; no rule: the byte is garbage; a
// size, held: decode_rtu decides, a failure drops one byte, a frame is taken whole) reports
// exactly what the framer reports, fed in chunks of any size, and leaves exactly as many bytes
// unsettled as the framer holds; put() byte by byte reports the same (stream_oracle.hpp); the
// role fixed by the type reports the same; never more than 256 bytes held or wanted; after
// idle(), a clean frame is delivered exactly once.

// fuzz-max-len: 1024 (a stream four times the 256 bytes the framer holds or wants at most)
#include <motionbus/modbus/framer.hpp>

#include <tuple>
#include <vector>

#include "../fuzz_check.hpp"
#include "../stream_oracle.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

using noted = std::tuple<mb::decode_status, mb::errc, std::uint32_t, std::uint32_t, std::uint8_t,
                         std::uint16_t, std::vector<std::uint8_t>>;

noted note(const mb::decode_result<mo::rtu_frame>& r) {
  const mo::rtu_frame& f = r.value();
  return noted(r.status(), r.error(), r.expected(), r.received(), f.slave, f.crc,
               std::vector<std::uint8_t>(f.pdu.begin(), f.pdu.end()));
}

struct setup {
  bool server;
  std::uint8_t address;   // the server's, or the slave the client asked
  std::uint8_t function;  // the client's request
  mo::report_id_format fc11;
};

// --- The length rules, from the specification (not the framer's predict_*_size) ----------
// MODBUS Application Protocol V1.1b3 §6, each PDU's layout; the ADU adds the address before it
// and the CRC after it (Serial Line §2.5.1). A size in bytes, 0: more bytes are needed to tell,
// no_rule: the function has no length rule (garbage on a stream).
constexpr std::size_t no_rule = static_cast<std::size_t>(-1);

// The ADU's size: `fixed` bytes and the count at `at`, once `at` has arrived.
std::size_t counted(mb::byte_view held, std::size_t at, std::size_t fixed) {
  return held.size() <= at ? 0U : fixed + held[at];
}

std::size_t request_size(mb::byte_view held) {
  switch (held[1]) {
    case 0x01:  // read coils, discrete inputs, holding
    case 0x02:  // and input registers, write one coil
    case 0x03:  // or register: start/address, quantity
    case 0x04:  // or value, 2 bytes each
    case 0x05:
    case 0x06:
    case 0x08: return 8;  // diagnostics: sub-function, one data word (Return Query Data: below)
    case 0x07:            // read exception status, get comm event counter and log, report
    case 0x0B:            // server ID: the function code alone
    case 0x0C:
    case 0x11: return 4;
    case 0x0F:  // write multiple coils, registers: start, quantity, byte count N, N bytes
    case 0x10: return counted(held, 6, 9);
    case 0x14:  // read, write file record: byte count N, N bytes
    case 0x15: return counted(held, 2, 5);
    case 0x16: return 10;                     // mask write register: address, AND mask, OR mask
    case 0x17: return counted(held, 10, 13);  // read and write: 4 words, byte count, bytes
    case 0x18: return 6;                      // read FIFO queue: its address
    case 0x2B: return 7;                      // read device identification: MEI, code, object
    default: return no_rule;
  }
}

// Read Device Identification's response (§6.21): MEI type, code, conformity, more follows,
// next object, the number of objects at ADU byte 7, then each object: id, length, value.
std::size_t device_id_size(mb::byte_view held) {
  if (held.size() < 8U) {
    return 0;
  }
  std::size_t end = 8;
  for (std::size_t k = 0; k < held[7]; ++k) {
    if (end + 2U > held.size()) {  // its header still to come
      return held.size() >= mo::max_rtu_size ? mo::max_rtu_size + 1U : 0U;
    }
    end += 2U + held[end + 1U];
    if (end > held.size()) {  // its value still to come: too long already, or wait
      return end > mo::max_rtu_size            ? end
             : held.size() >= mo::max_rtu_size ? mo::max_rtu_size + 1U
                                               : 0U;
    }
  }
  return end + 2U;
}

std::size_t response_size(mb::byte_view held, std::uint8_t asked, mo::report_id_format fc11) {
  const std::uint8_t f = held[1];
  if (f >= 0x80U) {
    return 5;  // an exception (the framer takes one of any function): its code
  }
  if (f != asked) {
    return no_rule;
  }
  switch (f) {
    case 0x01:  // a byte count N, N bytes
    case 0x02:
    case 0x03:
    case 0x04:
    case 0x0C:
    case 0x14:
    case 0x15:
    case 0x17: return counted(held, 2, 5);
    case 0x11:  // report server ID: counted, or (a device's layout) two bytes
      return fc11 == mo::report_id_format::two_bytes_no_count ? 6U : counted(held, 2, 5);
    case 0x05:  // the request's two words echoed
    case 0x06:
    case 0x08:
    case 0x0B:
    case 0x0F:
    case 0x10: return 8;
    case 0x07: return 5;   // the status byte
    case 0x16: return 10;  // the request echoed
    case 0x18:             // a 2-byte byte count N (FIFO count and values), N bytes
      return held.size() < 4U ? 0U : 6U + (std::size_t{held[2]} << 8U | held[3]);
    case 0x2B: return device_id_size(held);
    default: return no_rule;
  }
}

std::size_t predict(const setup& s, mb::byte_view held) {
  if (held.size() < 2U) {
    return 0;
  }
  return s.server ? request_size(held) : response_size(held, s.function, s.fc11);
}

bool for_us(const setup& s, std::uint8_t slave) {
  return s.server ? slave == s.address || slave == mo::broadcast_address : slave == s.address;
}

bool crc_ok(mb::byte_view adu) {
  return mo::crc16::compute(adu.first(adu.size() - 2U)) == mb::load_le16(adu, adu.size() - 2U);
}

// The reference framing of `in` by the length rules alone; `left`: the bytes it leaves unsettled
// at the end (a frame still arriving).
std::vector<noted> reference(const setup& s, mb::byte_view in, std::size_t& left) {
  std::vector<noted> out;
  std::size_t p = 0;
  for (;;) {
    const std::size_t rem = in.size() - p;
    const mb::byte_view at = in.subspan(p);
    std::size_t total = 0;
    for (std::size_t k = 2; k <= rem && total == 0; ++k) {  // the size as the bytes arrive
      total = predict(s, at.first(k));
      if (total == 0 && k == mo::max_rtu_size) {
        total = mo::max_rtu_size + 1U;  // never more than 256 bytes wanted
      }
    }
    if (total == 0) {
      left = rem;
      return out;
    }
    if (total == no_rule) {  // no rule: garbage
      ++p;
      continue;
    }
    if (total < 3U || !mo::pdu_size_ok(total - 3U)) {
      out.push_back(note(mb::decode_failure{mb::errc::modbus_pdu_length, 0}));
      ++p;
      continue;
    }
    if (rem < total) {
      left = rem;
      return out;
    }
    // FC08 Return Query Data: 8 + 2k bytes, the first length at which the CRC matches
    if (total == 8U && at[1] == 0x08U && at[2] == 0U && at[3] == 0U) {
      const std::size_t held = rem < mo::max_rtu_size ? rem : mo::max_rtu_size;
      std::size_t length = 8;
      while (length <= held && !crc_ok(at.first(length))) {
        length += 2U;
      }
      if (length <= held) {
        total = length;
      } else if (length <= mo::max_rtu_size) {
        left = rem;  // the CRC may still match at a length to come
        return out;
      }
    }
    const auto f = mo::decode_rtu(at.first(total));
    if (f.is_failed()) {
      out.push_back(note(mb::decode_failure{f.error(), 0, f.expected(), f.received()}));
      ++p;
      continue;
    }
    if (for_us(s, f.value().slave)) {
      out.push_back(note(mb::decode_result<mo::rtu_frame>::complete(f.value(), total)));
    }
    p += total;
  }
}

template <class Framer>
std::vector<noted> by_chunks(Framer& f, mb::byte_view in, std::size_t chunk) {
  return motionbus_fuzz::by_chunks(f, in, chunk, note, mo::max_rtu_size, mo::max_rtu_size);
}

template <class Framer>
void start(Framer& f, const setup& s) {
  if (!s.server) {
    const std::uint8_t head[2] = {s.address, s.function};
    f.sent(mb::byte_view(head, 2));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4) {
    return 0;
  }
  setup s{};
  s.server = (data[0] & 1U) != 0;
  s.address = static_cast<std::uint8_t>(1U + data[1] % 247U);
  s.function = data[3];
  s.fc11 = (data[0] & 2U) != 0 ? mo::report_id_format::two_bytes_no_count
                               : mo::report_id_format::standard;
  const std::size_t chunk = 1U + data[2] % 64U;
  const mb::byte_view stream(data + 4, size - 4);
  mo::framer_options options{s.address, mo::frame_end::length, s.fc11};
  const mo::framer_role role = s.server ? mo::framer_role::server : mo::framer_role::client;

  std::size_t left = 0;
  const std::vector<noted> want = reference(s, stream, left);

  mo::rtu_framer chunked(role, options);
  start(chunked, s);
  MOTIONBUS_FUZZ_CHECK(by_chunks(chunked, stream, chunk) == want);
  MOTIONBUS_FUZZ_CHECK(chunked.pending() == left);

  mo::rtu_framer by_byte(role, options);
  start(by_byte, s);
  MOTIONBUS_FUZZ_CHECK(motionbus_fuzz::results_by_put(by_byte, stream, note) == want);
  MOTIONBUS_FUZZ_CHECK(by_byte.pending() == left);

  if (s.server) {
    mo::rtu_server_framer fixed(options);
    MOTIONBUS_FUZZ_CHECK(by_chunks(fixed, stream, chunk) == want);
  } else {
    mo::rtu_client_framer fixed(options);
    start(fixed, s);
    MOTIONBUS_FUZZ_CHECK(by_chunks(fixed, stream, chunk) == want);
  }

  // the connection goes quiet (the user's idle timer): what is held ends; then a clean frame
  (void)chunked.idle();
  MOTIONBUS_FUZZ_CHECK(chunked.pending() == 0);
  std::uint8_t frame[16] = {};
  const std::uint8_t pdu[] = {0x06, 0x00, 0x01, 0x00, 0x03};
  const std::size_t k = mo::encode_rtu(s.address, pdu, frame).value();
  setup echo = s;
  echo.function = 0x06;
  start(chunked, echo);
  const auto got = by_chunks(chunked, mb::byte_view(frame, k), chunk);
  MOTIONBUS_FUZZ_CHECK(got.size() == 1 && std::get<0>(got[0]) == mb::decode_status::complete &&
                       std::get<6>(got[0]).size() == 5);
  return 0;
}
