// Modbus RTU stream framer. Oracles: never holds more than 256 bytes; every frame it delivers
// is CRC-valid, for its address, and re-encodes to bytes that occur in the input; put() byte by
// byte reports what feed() in chunks does (stream_oracle.hpp); after the t3.5 signal a clean
// frame fed in any chunks is delivered exactly once, unchanged.
// The listener (rtu_listener, a tapped line's both directions) on the same input: put() agrees
// with feed() (directions included); every frame is CRC-valid and is the input's bytes at the
// place the stream's count puts it; a clean request and its response after the input, with no
// silence between, are each reported at their place unless a frame reported overlaps them
// (nothing valid behind a bad frame is lost); idle() drains what is held.

// fuzz-max-len: 1024 (3 option bytes and a stream four times the 256 bytes the framer and the
// listener hold at most: a longer stream only repeats their states)
#include <motionbus/modbus/framer.hpp>

#include <string.h>  // memmem
#include <cstring>
#include <tuple>
#include <vector>

#include "../fuzz_check.hpp"
#include "../stream_oracle.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

// Whether `needle` occurs in `hay`: the C library's memmem (linear and uninstrumented; a memcmp at
// every offset, each traced by the fuzzer's comparison hooks, was not).
bool occurs_in(const std::uint8_t* hay, std::size_t hay_size, const std::uint8_t* needle,
               std::size_t n) {
  return n == 0 || ::memmem(hay, hay_size, needle, n) != nullptr;
}

// A result as the oracle compares it: status, error, evidence, and the frame's bytes.
auto note(const mb::decode_result<mo::rtu_frame>& r) {
  const mo::rtu_frame& f = r.value();
  return std::make_tuple(r.status(), r.error(), r.expected(), r.received(), f.slave, f.crc,
                         std::vector<std::uint8_t>(f.pdu.begin(), f.pdu.end()));
}

// The listener on `line`, one byte at a time (put() and the rescan of put_each), then the
// silence: each result with the direction of a frame and the stream index where it ends.
struct listened {
  mb::decode_status status;
  mb::errc error;
  bool response;
  std::size_t end;
  std::vector<std::uint8_t> frame;  // address, PDU, CRC (complete only)
  bool operator==(const listened& o) const {
    return status == o.status && error == o.error && response == o.response && end == o.end &&
           frame == o.frame;
  }
};

template <class Step>
std::vector<listened> listen(mo::rtu_listener& l, std::size_t n, Step&& step) {
  std::vector<listened> out;
  std::size_t fed = 0;
  const auto each = [&](const mb::decode_result<mo::rtu_frame>& r) {
    MOTIONBUS_FUZZ_CHECK(l.pending() <= mo::max_rtu_size);
    listened e{r.status(), r.error(), false, fed - l.pending(), {}};
    if (r.is_complete()) {
      e.response = l.heard_response();
      std::uint8_t out_frame[mo::max_rtu_size] = {};
      const auto k = mo::encode_rtu(r.value().slave, r.value().pdu, out_frame);
      MOTIONBUS_FUZZ_CHECK(k.ok() && k.value() == r.value().pdu.size() + 3U);
      e.frame.assign(out_frame, out_frame + k.value());
    }
    out.push_back(e);
  };
  step(fed, each);
  for (int guard = 0;; ++guard) {
    MOTIONBUS_FUZZ_CHECK(guard < 1000);
    const auto r = l.idle();
    if (r.is_incomplete()) {
      break;
    }
    each(r);
  }
  MOTIONBUS_FUZZ_CHECK(l.pending() == 0);
  (void)n;
  return out;
}

void check_listener(const mo::framer_options& options, const std::uint8_t* stream, std::size_t n,
                    std::size_t chunk) {
  // the input, then a clean request and its response, back to back
  std::vector<std::uint8_t> line(stream, stream + n);
  std::uint8_t frame[mo::max_rtu_size] = {};
  const std::uint8_t request[] = {0x03, 0x00, 0x6B, 0x00, 0x02};
  const std::uint8_t response[] = {0x03, 0x04, 0x00, 0x2A, 0x01, 0x02};
  std::size_t k = mo::encode_rtu(0x11, request, frame).value();
  const std::size_t request_at = line.size();
  line.insert(line.end(), frame, frame + k);
  k = mo::encode_rtu(0x11, response, frame).value();
  const std::size_t response_at = line.size();
  line.insert(line.end(), frame, frame + k);
  mo::rtu_listener by_byte(options);
  mo::rtu_listener chunked(options);
  const auto put = listen(by_byte, line.size(), [&](std::size_t& fed, auto& each) {
    for (const std::uint8_t b : line) {
      ++fed;
      mb::put_each(by_byte, b, [&](const auto& r) {
        each(r);
        return true;
      });
    }
  });
  const auto fed_chunks = listen(chunked, line.size(), [&](std::size_t& fed, auto& each) {
    for (std::size_t at = 0; at < line.size(); at += chunk) {
      const mb::byte_view in(line.data() + at, chunk < line.size() - at ? chunk : line.size() - at);
      std::size_t taken = 0;
      for (int guard = 0;; ++guard) {
        MOTIONBUS_FUZZ_CHECK(guard < 100000);
        const auto r = chunked.feed(in.subspan(taken));
        if (r.is_incomplete()) {
          MOTIONBUS_FUZZ_CHECK(chunked.pending() + r.needed() <= mo::max_rtu_size);
          fed = at + in.size();
          break;
        }
        taken += r.consumed();
        fed = at + taken;
        each(r);
      }
    }
  });
  MOTIONBUS_FUZZ_CHECK(put == fed_chunks);
  bool request_seen = false;
  bool response_seen = false;
  bool request_overlapped = false;
  bool response_overlapped = false;
  const std::size_t request_end = response_at;
  const std::size_t response_end = line.size();
  for (const listened& e : put) {
    if (e.status != mb::decode_status::complete) {
      continue;
    }
    const std::size_t begin = e.end - e.frame.size();
    MOTIONBUS_FUZZ_CHECK(e.end <= line.size() &&
                         std::memcmp(line.data() + begin, e.frame.data(), e.frame.size()) == 0);
    request_seen = request_seen || (begin == request_at && e.end == request_end);
    response_seen = response_seen || (begin == response_at && e.end == response_end && e.response);
    const bool overlaps_request = begin < request_end && e.end > request_at;
    const bool overlaps_response = begin < response_end && e.end > response_at;
    request_overlapped =
        request_overlapped || (overlaps_request && !(begin == request_at && e.end == request_end));
    response_overlapped = response_overlapped ||
                          (overlaps_response && !(begin == response_at && e.end == response_end));
  }
  MOTIONBUS_FUZZ_CHECK(request_seen || request_overlapped);
  // the response is the request's when the request was framed as one (it was not a response)
  MOTIONBUS_FUZZ_CHECK(response_seen || response_overlapped || !request_seen);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) {
    return 0;
  }
  const bool server = (data[0] & 1U) != 0;
  const std::uint8_t address = static_cast<std::uint8_t>(1U + data[1] % 247U);
  const std::size_t chunk = 1U + data[2] % 32U;
  const mo::framer_role role = server ? mo::framer_role::server : mo::framer_role::client;
  mo::framer_options options{address};
  options.fc11 = (data[0] & 2U) != 0 ? mo::report_id_format::two_bytes_no_count
                                     : mo::report_id_format::standard;
  options.ends = (data[0] & 4U) != 0 ? mo::frame_end::silence : mo::frame_end::length;
  mo::rtu_framer f(role, options);
  mo::rtu_framer by_byte(role, options);
  if (!server) {
    const std::uint8_t request_head[2] = {address, static_cast<std::uint8_t>(data[0] >> 3U)};
    f.sent(mb::byte_view(request_head, 2));
    by_byte.sent(mb::byte_view(request_head, 2));
  }
  const std::uint8_t* stream = data + 3;
  const std::size_t n = size - 3;
  const auto put_results = motionbus_fuzz::results_by_put(by_byte, mb::byte_view(stream, n), note);
  std::vector<decltype(note(f.result()))> feed_results;
  for (std::size_t at = 0; at < n; at += chunk) {
    mb::byte_view in(stream + at, chunk < n - at ? chunk : n - at);
    for (int guard = 0;; ++guard) {
      MOTIONBUS_FUZZ_CHECK(guard < 100000);
      const auto r = f.feed(in);
      MOTIONBUS_FUZZ_CHECK(f.pending() <= mo::max_rtu_size);
      if (r.is_incomplete()) {  // never more than the largest ADU wanted
        MOTIONBUS_FUZZ_CHECK(f.pending() + r.needed() <= mo::max_rtu_size);
        break;
      }
      MOTIONBUS_FUZZ_CHECK(r.consumed() <= in.size());
      in = in.subspan(r.consumed());
      feed_results.push_back(note(r));
      if (r.is_complete()) {
        std::uint8_t out[mo::max_rtu_size] = {};
        const auto k = mo::encode_rtu(r.value().slave, r.value().pdu, out);
        MOTIONBUS_FUZZ_CHECK(k.ok() && occurs_in(stream, n, out, k.value()));
        MOTIONBUS_FUZZ_CHECK(r.value().slave == address || (server && r.value().slave == 0));
      }
    }
  }
  MOTIONBUS_FUZZ_CHECK(put_results == feed_results);
  MOTIONBUS_FUZZ_CHECK(by_byte.pending() == f.pending());
  const auto last = f.idle();  // the silence ends what is held: a frame only if it is one
  if (last.is_complete()) {
    std::uint8_t out[mo::max_rtu_size] = {};
    const auto k = mo::encode_rtu(last.value().slave, last.value().pdu, out);
    MOTIONBUS_FUZZ_CHECK(k.ok() && occurs_in(stream, n, out, k.value()));
    MOTIONBUS_FUZZ_CHECK(last.value().slave == address || (server && last.value().slave == 0));
  }
  MOTIONBUS_FUZZ_CHECK(f.pending() == 0);
  // a clean frame after the silence
  std::uint8_t frame[16] = {};
  const std::uint8_t pdu[] = {0x06, 0x00, 0x01, 0x00, 0x03};
  const std::size_t k = mo::encode_rtu(address, pdu, frame).value();
  if (!server) {
    const std::uint8_t request_head[2] = {address, 0x06};
    f.sent(mb::byte_view(request_head, 2));
  }
  std::size_t found = 0;
  for (std::size_t at = 0; at < k; at += chunk) {
    mb::byte_view in(frame + at, chunk < k - at ? chunk : k - at);
    for (;;) {
      const auto r = f.feed(in);
      if (r.is_incomplete()) {
        break;
      }
      in = in.subspan(r.consumed());
      MOTIONBUS_FUZZ_CHECK(r.is_complete() && r.value().pdu.size() == 5);
      ++found;
    }
  }
  MOTIONBUS_FUZZ_CHECK(found == 1);
  check_listener(options, stream, n, chunk);
  return 0;
}
