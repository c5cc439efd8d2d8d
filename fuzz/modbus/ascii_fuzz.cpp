// Modbus ASCII: decode_ascii and ascii_framer. Oracles: a reference written from the
// specification alone (Modbus over Serial Line V1.02 §2.5.2.1-2.5.2.2, §6.2.1; reference()
// below, which uses nothing of ascii.hpp) reports every frame and every failure, with its
// error code, its LRC figures and the character that settles it, exactly as the framer fed in
// chunks of any size does, and tells whether a frame is still being received; put() byte by
// byte reports the same (stream_oracle.hpp); decode_ascii of an input starting with ':'
// reports the reference's first result, consumed() at the character that settles it, and a
// frame it decodes re-encodes (encode_ascii) to the characters it used (but for lowercase
// digits); never more than 255 bytes held. The delimiter after CR (ascii_options::delimiter),
// the role and, for a client, how its slave is chosen (sent() of a request for one slave, of
// a broadcast or of an unreadable address, options.address, or nothing) are taken from the
// input's first byte. idle() ends any frame; a clean frame after it is delivered exactly once.

// fuzz-max-len: 2048 (four of the longest frame, 513 characters: the framer holds at most 255
// bytes; a longer stream only repeats its states)
#include <motionbus/modbus/ascii.hpp>

#include <tuple>
#include <vector>

#include "../fuzz_check.hpp"
#include "../stream_oracle.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

using noted = std::tuple<mb::decode_status, mb::errc, std::uint32_t, std::uint32_t, std::uint8_t,
                         std::uint8_t, std::vector<std::uint8_t>>;

noted note(const mb::decode_result<mo::ascii_frame>& r) {
  const mo::ascii_frame& f = r.value();
  return noted(r.status(), r.error(), r.expected(), r.received(), f.slave, f.lrc,
               std::vector<std::uint8_t>(f.pdu.begin(), f.pdu.end()));
}

noted failure(mb::errc e, std::uint32_t expected = 0, std::uint32_t received = 0) {
  return noted(mb::decode_status::failed, e, expected, received, 0, 0, {});
}

// --- The reference, from the specification ------------------------------------------------
// §2.5.2.1: a frame starts at ':' (characters before it are not a frame: dropped), holds the
// hexadecimal digits of address, PDU and LRC (2 a byte, 0-9 A-F; lowercase accepted, as
// documented in ascii.hpp), and ends with CR and the delimiter (LF unless Diagnostics 03
// changed it; after CR the delimiter ends the frame whatever it is, and before CR a hex
// digit is a digit: the framer's documented choices). A ':' inside a frame starts a new one
// (but as that delimiter after CR). The frame is then checked: an even
// number of digits, 3..255 bytes (address, function, LRC), the LRC (§2.5.2.2: the sum of all
// bytes, LRC included, is 0 modulo 256), an address of 0..247. Each failure has its error:
//   a ':' inside a frame, a CR not followed by the delimiter, the delimiter without CR:
//                                                              modbus_ascii_end
//   any other character than a digit or CR inside a frame:     modbus_ascii_character
//   an odd number of digits:                                   modbus_ascii_odd_digits
//   fewer than 3 bytes, or a 256th byte (at its second digit): modbus_pdu_length
//   the LRC (expected: the LRC of the others; received: sent): crc_mismatch
//   an address of 248..255:                                    modbus_slave_address

int digit(std::uint8_t c) {
  if (c >= '0' && c <= '9') {
    return c - '0';
  }
  if (c >= 'A' && c <= 'F') {
    return c - 'A' + 10;
  }
  if (c >= 'a' && c <= 'f') {
    return c - 'a' + 10;
  }
  return -1;
}

// Which frames a node keeps: a listener every one, a client its slave's (0: any), a server its
// address's and broadcasts.
struct keeps {
  mo::framer_role role;
  std::uint8_t slave;
  bool operator()(std::uint8_t a) const {
    if (role == mo::framer_role::listener) {
      return true;
    }
    if (role == mo::framer_role::client) {
      return slave == 0U || a == slave;
    }
    return a == slave || a == 0U;
  }
};

struct settled {
  std::size_t at;  // the index of the character that settled it
  noted what;
};

// Every result over `in`; `inside`: a frame is still being received at the end.
std::vector<settled> reference(mb::byte_view in, keeps keep, std::uint8_t delimiter, bool& inside) {
  std::vector<settled> out;
  enum { hunting, digits, after_cr } state = hunting;
  std::vector<int> nibbles;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const std::uint8_t c = in[i];
    const auto fail = [&](mb::errc e, std::uint32_t expected = 0, std::uint32_t received = 0) {
      out.push_back({i, failure(e, expected, received)});
      state = hunting;
    };
    if (state == hunting) {
      if (c == ':') {
        state = digits;
        nibbles.clear();
      }
      continue;
    }
    if (state == digits && digit(c) >= 0) {
      nibbles.push_back(digit(c));
      if (nibbles.size() == 2U * 256U) {  // the 256th byte complete
        fail(mb::errc::modbus_pdu_length);
      }
      continue;
    }
    if (state == digits && c == '\r') {
      state = after_cr;
      continue;
    }
    if (state == digits || c != delimiter) {  // CR and the delimiter end a frame, any other:
      if (c == ':') {                         // restarts: the frame it cuts short has no end
        fail(mb::errc::modbus_ascii_end);
        state = digits;
        nibbles.clear();
      } else if (c == delimiter || state == after_cr) {  // the delimiter alone, CR alone
        fail(mb::errc::modbus_ascii_end);
      } else {
        fail(mb::errc::modbus_ascii_character);
      }
      continue;
    }
    // CR and the delimiter: the frame's checks
    if (nibbles.size() % 2U != 0U) {
      fail(mb::errc::modbus_ascii_odd_digits);
      continue;
    }
    std::vector<std::uint8_t> bytes;
    unsigned sum = 0;
    for (std::size_t k = 0; k < nibbles.size(); k += 2U) {
      bytes.push_back(static_cast<std::uint8_t>(nibbles[k] * 16 + nibbles[k + 1U]));
      sum += bytes.back();
    }
    if (bytes.size() < 3U) {
      fail(mb::errc::modbus_pdu_length);
      continue;
    }
    if (sum % 256U != 0U) {
      const unsigned others = sum - bytes.back();
      fail(mb::errc::crc_mismatch, (256U - others % 256U) % 256U, bytes.back());
      continue;
    }
    if (bytes[0] > 247U) {
      fail(mb::errc::modbus_slave_address);
      continue;
    }
    state = hunting;
    if (keep(bytes[0])) {
      out.push_back(
          {i, noted(mb::decode_status::complete, mb::errc::ok, 0, 0, bytes[0], bytes.back(),
                    std::vector<std::uint8_t>(bytes.begin() + 1, bytes.end() - 1))});
    }
  }
  inside = state != hunting;
  return out;
}

std::vector<noted> results(const std::vector<settled>& s) {
  std::vector<noted> out;
  for (const settled& x : s) {
    out.push_back(x.what);
  }
  return out;
}

std::uint8_t upper(std::uint8_t c) {
  return static_cast<std::uint8_t>(c >= 'a' && c <= 'f' ? c - 0x20 : c);
}

// The character after CR, by the input's choice: LF mostly, else one of those the framer must
// not confuse with the frame's own characters, or any.
std::uint8_t delimiter_of(unsigned pick, std::uint8_t any) {
  const std::uint8_t table[] = {'\n', '\n', '!', '\r', ':', 'A', 'f', 0x00, 0xFF, 'G', '\n'};
  return pick < sizeof table ? table[pick] : any;
}

std::vector<noted> by_chunks(mo::ascii_framer& f, mb::byte_view in, std::size_t chunk) {
  // held: at most 255 decoded bytes; wanted: one character more
  return motionbus_fuzz::by_chunks(f, in, chunk, note, mo::max_ascii_bytes,
                                   mo::max_ascii_bytes + 1U);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) {
    return 0;
  }
  const mo::framer_role roles[] = {mo::framer_role::server, mo::framer_role::client,
                                   mo::framer_role::listener};
  const mo::framer_role role = roles[data[0] % 3U];
  const unsigned client_mode = (data[0] / 3U) % 5U;
  const std::uint8_t delimiter = delimiter_of(data[0] / 15U, data[1]);
  const std::uint8_t address = static_cast<std::uint8_t>(1U + data[1] % 247U);
  const std::size_t chunk = 1U + data[2] % 64U;
  const mb::byte_view stream(data + 3, size - 3);

  // The node: a server of `address`; a listener; a client whose slave is `address` after
  // sent() of a request to it (mode 0), any after sent() of a broadcast or of a request whose
  // address is unreadable (1, 2), `address` from its options and no sent() (3), any with
  // neither (4).
  mo::ascii_options options{address, delimiter};
  keeps keep{role, address};
  std::uint8_t request[mo::max_ascii_size] = {};
  std::size_t request_size = 0;
  if (role == mo::framer_role::client) {
    const std::uint8_t pdu[] = {0x03, 0x00, 0x00, 0x00, 0x01};
    const std::uint8_t to = client_mode == 1U ? 0U : address;
    request_size = mo::encode_ascii(to, pdu, request).value();
    if (client_mode == 2U) {
      request[1] = 'x';
    }
    if (client_mode == 1U || client_mode == 2U || client_mode == 4U) {
      keep.slave = 0;
    }
    if (client_mode == 4U) {
      options.address = 0;
    }
  }
  mo::ascii_framer chunked(role, options);
  if (role == mo::framer_role::client && client_mode <= 2U) {
    chunked.sent(mb::byte_view(request, request_size));
  }
  MOTIONBUS_FUZZ_CHECK(chunked.options().delimiter == delimiter);

  bool inside = false;
  const std::vector<settled> ref = reference(stream, keep, delimiter, inside);
  const std::vector<noted> want = results(ref);
  mo::ascii_framer by_byte = chunked;
  MOTIONBUS_FUZZ_CHECK(by_chunks(chunked, stream, chunk) == want);
  MOTIONBUS_FUZZ_CHECK(chunked.inside() == inside);
  MOTIONBUS_FUZZ_CHECK(motionbus_fuzz::results_by_put(by_byte, stream, note) == want);
  MOTIONBUS_FUZZ_CHECK(by_byte.pending() == chunked.pending());
  MOTIONBUS_FUZZ_CHECK(by_byte.dropped() == chunked.dropped());
  MOTIONBUS_FUZZ_CHECK(by_byte.skipped() == chunked.skipped());

  // decode_ascii: the reference's first result (a listener's: every frame), where it settles
  std::uint8_t bytes[mo::max_ascii_bytes] = {};
  const auto d = mo::decode_ascii(stream, bytes, delimiter);
  MOTIONBUS_FUZZ_CHECK(!d.is_incomplete());
  if (!stream.empty() && stream[0] == ':') {
    bool open = false;
    const std::vector<settled> first =
        reference(stream, keeps{mo::framer_role::listener, 0}, delimiter, open);
    if (first.empty()) {  // the input ends inside the frame
      MOTIONBUS_FUZZ_CHECK(d.error() == mb::errc::modbus_ascii_end);
      MOTIONBUS_FUZZ_CHECK(d.consumed() == stream.size());
    } else {
      MOTIONBUS_FUZZ_CHECK(note(d) == first[0].what);
      const bool restart = d.is_failed() && stream[first[0].at] == ':';
      MOTIONBUS_FUZZ_CHECK(d.consumed() == first[0].at + (restart ? 0U : 1U));
    }
  } else {
    MOTIONBUS_FUZZ_CHECK(d.error() == mb::errc::no_frame);
  }
  if (d.is_complete()) {  // a frame re-encodes to the characters it used
    std::uint8_t text[mo::max_ascii_size] = {};
    const auto n = mo::encode_ascii(d.value().slave, d.value().pdu, text);
    MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == d.consumed());
    for (std::size_t i = 0; i + 1U < n.value(); ++i) {
      MOTIONBUS_FUZZ_CHECK(text[i] == upper(stream[i]));
    }
    MOTIONBUS_FUZZ_CHECK(stream[n.value() - 1U] == delimiter);
  }

  // the inter-character timeout ends what is held; then a clean frame, once
  const auto cut = chunked.idle();
  MOTIONBUS_FUZZ_CHECK(cut.is_incomplete() != inside);
  MOTIONBUS_FUZZ_CHECK(!chunked.inside() && chunked.pending() == 0);
  std::uint8_t frame[32] = {};
  const std::uint8_t pdu[] = {0x06, 0x00, 0x01, 0x00, 0x03};
  const std::size_t k = mo::encode_ascii(address, pdu, frame).value();
  frame[k - 1U] = delimiter;
  const auto got = by_chunks(chunked, mb::byte_view(frame, k), chunk);
  MOTIONBUS_FUZZ_CHECK(got.size() == 1 && std::get<0>(got[0]) == mb::decode_status::complete &&
                       std::get<6>(got[0]).size() == 5);
  return 0;
}
