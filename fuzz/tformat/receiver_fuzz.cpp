// T-format stream receiver. Oracles: bounded work and buffer; every frame it reports
// re-encodes to bytes that occur in the input; put() byte by byte reports what feed() in
// chunks does (stream_oracle.hpp); after idle(), a valid frame fed in random chunks is reported
// exactly once and unchanged; with echo::expected, the same response without its echo is
// reported once too (echo_missed()).
// The line listener (tformat::line_listener, both directions of a tapped line) on the same
// input: put() agrees with feed(); every frame it reports is the input's bytes at the place
// the stream's count puts it; after idle(), a read of a closed EEPROM address and its ID3
// reply are reported as a request and its paired ID3 reply, exactly.

// fuzz-max-len: 512 (the receiver and the listener hold at most 11 bytes, the longest frame: a
// stream of 510 bytes holds 46 of them)
#include <motionbus/tformat/codec.hpp>
#include <motionbus/tformat/listener.hpp>
#include <motionbus/tformat/receiver.hpp>

#include <string.h>  // memmem
#include <cstring>
#include <tuple>
#include <vector>

#include "../fuzz_check.hpp"
#include "../stream_oracle.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

// Whether `needle` occurs in `hay`: the C library's memmem (linear and uninstrumented; a memcmp at
// every offset, each traced by the fuzzer's comparison hooks, was not).
bool occurs_in(const std::uint8_t* hay, std::size_t hay_size, const std::uint8_t* needle,
               std::size_t n) {
  return n == 0 || ::memmem(hay, hay_size, needle, n) != nullptr;
}

// A result as the oracle compares it: status, error, evidence, and the frame re-encoded.
auto note(const mb::decode_result<tf::response>& r) {
  std::vector<std::uint8_t> bytes(tf::max_response_size);
  if (r.is_complete()) {
    bytes.resize(tf::encode_response(r.value(), mb::mutable_byte_view(bytes.data(), bytes.size()))
                     .value_or(0));
  }
  return std::make_tuple(r.status(), r.error(), r.expected(), r.received(), bytes);
}

struct listened {
  mb::decode_status status;
  mb::errc error;
  bool response;
  bool id3_reply;
  mb::errc request_error;
  std::size_t end;
  std::vector<std::uint8_t> frame;
  bool operator==(const listened& o) const {
    return status == o.status && error == o.error && response == o.response &&
           id3_reply == o.id3_reply && request_error == o.request_error && end == o.end &&
           frame == o.frame;
  }
};

listened note_heard(const mb::decode_result<tf::heard>& r, std::size_t end) {
  listened e{r.status(), r.error(), false, false, mb::errc::ok, end, {}};
  if (r.is_complete()) {
    e.response = r->is_response;
    e.id3_reply = r->id3_reply;
    e.request_error = r->request_error;
    e.frame.assign(r->bytes.begin(), r->bytes.end());
  }
  return e;
}

// `line` through a listener, one byte at a time (by_put) or in chunks, then the silence.
std::vector<listened> listen(tf::line_listener& l, const std::vector<std::uint8_t>& line,
                             std::size_t chunk, bool by_put) {
  std::vector<listened> out;
  std::size_t fed = 0;
  const auto each = [&](const mb::decode_result<tf::heard>& r) {
    MOTIONBUS_FUZZ_CHECK(l.pending() <= tf::max_response_size);
    MOTIONBUS_FUZZ_CHECK(out.size() <= 2 * line.size() + 4);
    out.push_back(note_heard(r, fed - l.pending()));
    return true;
  };
  if (by_put) {
    for (const std::uint8_t b : line) {
      ++fed;
      mb::put_each(l, b, each);
    }
  } else {
    for (std::size_t at = 0; at < line.size(); at += chunk) {
      const mb::byte_view in(line.data() + at, chunk < line.size() - at ? chunk : line.size() - at);
      std::size_t taken = 0;
      for (;;) {
        const auto r = l.feed(in.subspan(taken));
        if (r.is_incomplete()) {
          fed = at + in.size();
          break;
        }
        taken += r.consumed();
        fed = at + taken;
        each(r);
      }
    }
  }
  for (auto r = l.idle(); !r.is_incomplete(); r = l.idle()) {
    each(r);
  }
  MOTIONBUS_FUZZ_CHECK(l.pending() == 0);
  return out;
}

void check_listener(const std::uint8_t* stream, std::size_t n, std::size_t chunk) {
  const std::vector<std::uint8_t> line(stream, stream + n);
  tf::line_listener by_byte;
  tf::line_listener chunked;
  const auto put = listen(by_byte, line, chunk, true);
  MOTIONBUS_FUZZ_CHECK(put == listen(chunked, line, chunk, false));
  for (const listened& e : put) {
    if (e.status == mb::decode_status::complete) {
      MOTIONBUS_FUZZ_CHECK(
          e.end <= n && e.end >= e.frame.size() &&
          std::memcmp(stream + e.end - e.frame.size(), e.frame.data(), e.frame.size()) == 0);
    }
  }
  // after the silence: EA 06 EC (page 7 address 6, a closed address) and its ID3 reply
  const std::vector<std::uint8_t> exchange = {0xEA, 0x06, 0xEC, 0x1A, 0x00, 0x00, 0x00,
                                              0x00, 0x11, 0x00, 0x00, 0x00, 0x00, 0x0B};
  const auto after = listen(chunked, exchange, chunk, false);
  MOTIONBUS_FUZZ_CHECK(after.size() == 2 && after[0].status == mb::decode_status::complete &&
                       !after[0].response && after[0].frame.size() == 3 &&
                       after[1].status == mb::decode_status::complete && after[1].response &&
                       after[1].id3_reply && after[1].frame.size() == 11);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  tf::receiver_options opt;
  opt.echo_mode = (data[0] & 1U) != 0 ? tf::echo::expected : tf::echo::none;
  opt.check_against_request = (data[0] & 2U) != 0;
  tf::receiver rx(opt);
  tf::receiver by_byte(opt);
  const std::size_t chunk = 1U + data[1] % 16U;
  const std::uint8_t* stream = data + 2;
  const std::size_t stream_size = size - 2;
  if ((data[0] & 4U) != 0 && stream_size > 0) {
    rx.sent(mb::byte_view(stream, stream_size < 4 ? stream_size : 4));
    by_byte.sent(mb::byte_view(stream, stream_size < 4 ? stream_size : 4));
  }
  const auto put_results =
      motionbus_fuzz::results_by_put(by_byte, mb::byte_view(stream, stream_size), note);
  std::vector<decltype(note(rx.result()))> feed_results;
  std::size_t events = 0;
  for (std::size_t at = 0; at < stream_size; at += chunk) {
    mb::byte_view in(stream + at, chunk < stream_size - at ? chunk : stream_size - at);
    for (;;) {
      const auto r = rx.feed(in);
      MOTIONBUS_FUZZ_CHECK(rx.pending() <= tf::max_response_size);
      if (r.is_incomplete()) {
        break;
      }
      MOTIONBUS_FUZZ_CHECK(r.consumed() <= in.size());
      in = in.subspan(r.consumed());
      feed_results.push_back(note(r));
      MOTIONBUS_FUZZ_CHECK(++events <= 2 * stream_size + 2);  // no endless events
      if (r.is_complete()) {
        std::uint8_t out[tf::max_response_size] = {};
        const auto n = tf::encode_response(r.value(), out);
        MOTIONBUS_FUZZ_CHECK(n.ok());
        if (!(r.value().layout().eeprom() && r.value().busy)) {
          MOTIONBUS_FUZZ_CHECK(occurs_in(stream, stream_size, out, n.value()));
        }
      }
    }
  }
  MOTIONBUS_FUZZ_CHECK(put_results == feed_results);
  MOTIONBUS_FUZZ_CHECK(by_byte.pending() == rx.pending());
  // After the line goes idle, the same receiver finds the next transaction whatever came
  // before: the request is sent (and echoed when the line echoes), then the response arrives
  // in chunks and is reported exactly once, unchanged.
  (void)rx.idle();
  const std::uint8_t request[1] = {tf::control_field(tf::data_id::read_all)};
  rx.sent(mb::byte_view(request, 1));
  std::uint8_t wire[1 + tf::max_response_size] = {request[0]};
  tf::response v;
  v.id = tf::data_id::read_all;
  v.abs = static_cast<std::uint32_t>(size) & 0x1FFFFU;
  v.enid = 0x11;
  const std::size_t n =
      tf::encode_response(v, mb::mutable_byte_view(wire + 1, tf::max_response_size)).value();
  const std::size_t skip = opt.echo_mode == tf::echo::expected ? 0U : 1U;
  std::size_t found = 0;
  for (std::size_t at = skip; at < n + 1; at += chunk) {
    mb::byte_view in(wire + at, chunk < n + 1 - at ? chunk : n + 1 - at);
    for (;;) {
      const auto e = rx.feed(in);
      if (e.is_incomplete()) {
        break;
      }
      in = in.subspan(e.consumed());
      MOTIONBUS_FUZZ_CHECK(e.is_complete() && e.value().abs == v.abs);
      ++found;
    }
  }
  MOTIONBUS_FUZZ_CHECK(found == 1);
  if (opt.echo_mode == tf::echo::expected) {  // a line that does not echo after all
    (void)rx.idle();
    rx.sent(mb::byte_view(request, 1));
    found = 0;
    for (std::size_t at = 1; at < n + 1; at += chunk) {
      mb::byte_view in(wire + at, chunk < n + 1 - at ? chunk : n + 1 - at);
      for (;;) {
        const auto e = rx.feed(in);
        if (e.is_incomplete()) {
          break;
        }
        in = in.subspan(e.consumed());
        MOTIONBUS_FUZZ_CHECK(e.is_complete() && e.value().abs == v.abs);
        ++found;
      }
    }
    MOTIONBUS_FUZZ_CHECK(found == 1 && rx.echo_missed());
  }
  check_listener(stream, stream_size, chunk);
  return 0;
}
