// Modbus ASCII: decode_ascii and ascii_framer. Oracles: decode_ascii of any input either
// decodes a frame whose encode_ascii is the input's first consumed() characters (but for the
// case of lowercase digits) or fails with consumed() <= the input's size; the framer fed in
// chunks of any size reports what a reference reports (the input cut at each ':', each piece's
// frame decoded by decode_ascii: the framer and the decoder agree on every frame and every
// error), put() byte by byte reports the same (stream_oracle.hpp), never more than 255 bytes
// held; a frame for another address is skipped; idle() ends any frame; a clean frame after it is
// delivered exactly once.
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

std::uint8_t upper(std::uint8_t c) {
  return static_cast<std::uint8_t>(c >= 'a' && c <= 'f' ? c - 0x20 : c);
}

bool for_us(mo::framer_role role, std::uint8_t address, std::uint8_t slave) {
  if (role == mo::framer_role::listener) {
    return true;
  }
  return role == mo::framer_role::client ? slave == address
                                         : slave == address || slave == mo::broadcast_address;
}

// The reference: from each ':' of the input, decode_ascii of what follows (the LF delimiter);
// characters outside frames are dropped; a frame cut short by the input's end is left held.
std::vector<noted> reference(mb::byte_view in, mo::framer_role role, std::uint8_t address,
                             bool& inside) {
  std::vector<noted> out;
  std::uint8_t bytes[mo::max_ascii_bytes] = {};
  std::size_t p = 0;
  inside = false;
  while (p < in.size()) {
    if (in[p] != ':') {
      ++p;
      continue;
    }
    const auto r = mo::decode_ascii(in.subspan(p), bytes);
    if (r.is_complete()) {
      if (for_us(role, address, r.value().slave)) {
        out.push_back(note(r));
      }
      p += r.consumed();
      continue;
    }
    // the input's end inside the frame: still held (the decoder's missing_crlf at the end)
    if (r.error() == mb::errc::modbus_ascii_end && r.consumed() == in.size() - p) {
      // the input's end, or its last character (CR then not LF)? one more character tells
      std::vector<std::uint8_t> more(in.begin() + static_cast<std::ptrdiff_t>(p), in.end());
      more.push_back('G');
      if (mo::decode_ascii(mb::byte_view(more.data(), more.size()), bytes).consumed() >
          in.size() - p) {
        inside = true;
        return out;
      }
    }
    out.push_back(note(mb::decode_failure{r.error(), 0, r.expected(), r.received()}));
    p += r.consumed();
  }
  return out;
}

template <class Framer>
std::vector<noted> by_chunks(Framer& f, mb::byte_view in, std::size_t chunk) {
  std::vector<noted> out;
  for (std::size_t at = 0; at < in.size(); at += chunk) {
    mb::byte_view part = in.subspan(at, chunk < in.size() - at ? chunk : in.size() - at);
    for (int guard = 0;; ++guard) {
      MOTIONBUS_FUZZ_CHECK(guard < 100000);
      const auto r = f.feed(part);
      MOTIONBUS_FUZZ_CHECK(f.pending() <= mo::max_ascii_bytes);
      if (r.is_incomplete()) {
        break;
      }
      MOTIONBUS_FUZZ_CHECK(r.consumed() >= 1 && r.consumed() <= part.size());
      part = part.subspan(r.consumed());
      out.push_back(note(r));
    }
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) {
    return 0;
  }
  const mo::framer_role roles[] = {mo::framer_role::server, mo::framer_role::client,
                                   mo::framer_role::listener};
  const mo::framer_role role = roles[data[0] % 3U];
  const std::uint8_t address = static_cast<std::uint8_t>(1U + data[1] % 247U);
  const std::size_t chunk = 1U + data[2] % 64U;
  const mb::byte_view stream(data + 3, size - 3);

  // decode_ascii alone: a frame re-encodes to the characters it used
  std::uint8_t bytes[mo::max_ascii_bytes] = {};
  const auto d = mo::decode_ascii(stream, bytes);
  MOTIONBUS_FUZZ_CHECK(!d.is_incomplete());
  if (d.is_complete()) {
    std::uint8_t text[mo::max_ascii_size] = {};
    const auto n = mo::encode_ascii(d.value().slave, d.value().pdu, text);
    MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == d.consumed());
    for (std::size_t i = 0; i < n.value(); ++i) {
      MOTIONBUS_FUZZ_CHECK(text[i] == upper(stream[i]));
    }
  } else {
    MOTIONBUS_FUZZ_CHECK(d.consumed() <= stream.size());
  }

  const mo::ascii_options options{address};
  bool inside = false;
  const std::vector<noted> want = reference(stream, role, address, inside);
  mo::ascii_framer chunked(role, options);
  if (role == mo::framer_role::client) {
    std::uint8_t request[mo::max_ascii_size] = {};
    const std::uint8_t pdu[] = {0x03, 0x00, 0x00, 0x00, 0x01};
    const std::size_t k = mo::encode_ascii(address, pdu, request).value();
    chunked.sent(mb::byte_view(request, k));
  }
  mo::ascii_framer by_byte = chunked;
  MOTIONBUS_FUZZ_CHECK(by_chunks(chunked, stream, chunk) == want);
  MOTIONBUS_FUZZ_CHECK(chunked.inside() == inside);
  MOTIONBUS_FUZZ_CHECK(motionbus_fuzz::results_by_put(by_byte, stream, note) == want);
  MOTIONBUS_FUZZ_CHECK(by_byte.pending() == chunked.pending());
  MOTIONBUS_FUZZ_CHECK(by_byte.dropped() == chunked.dropped());
  MOTIONBUS_FUZZ_CHECK(by_byte.skipped() == chunked.skipped());

  // the inter-character timeout ends what is held; then a clean frame, once
  const auto cut = chunked.idle();
  MOTIONBUS_FUZZ_CHECK(cut.is_incomplete() != inside);
  MOTIONBUS_FUZZ_CHECK(!chunked.inside() && chunked.pending() == 0);
  std::uint8_t frame[32] = {};
  const std::uint8_t pdu[] = {0x06, 0x00, 0x01, 0x00, 0x03};
  const std::size_t k = mo::encode_ascii(address, pdu, frame).value();
  const auto got = by_chunks(chunked, mb::byte_view(frame, k), chunk);
  MOTIONBUS_FUZZ_CHECK(got.size() == 1 && std::get<0>(got[0]) == mb::decode_status::complete &&
                       std::get<6>(got[0]).size() == 5);
  return 0;
}
