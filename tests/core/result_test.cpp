// Results: result<T> (value or error) and decode_result<T> (complete, incomplete or failed).
#include "motionbus/core/result.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <type_traits>
#include <utility>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/span.hpp"

#include "../support/run_time.hpp"

using namespace motionbus;

namespace {

struct frame {
  std::uint8_t id = 0;
  std::uint32_t position = 0;
};

// A toy decoder with the three outcomes: a 1-byte tag 0x55, then one payload byte.
decode_result<frame> toy_decode(byte_view in) {
  if (in.empty()) {
    return need_input{2};
  }
  if (in[0] != 0x55) {
    return decode_failure{errc::no_frame, 1};
  }
  if (in.size() < 2) {
    return need_input{1};
  }
  return decode_result<frame>::complete(frame{in[1], 7}, 2);
}

// The same toy decoder, its result settled in place through an outcome.
decode_result<frame> toy_build(byte_view in) {
  decode_result<frame> r = need_input{1};
  decode_result<frame>::outcome o(r);
  if (in.empty()) {
    o.need(2);
  } else if (in[0] != 0x55) {
    o.fail(errc::no_frame, 1);
  } else if (in.size() < 2) {
    o.need(1);
  } else {
    frame f;  // fields not named here stay value-initialised
    f.id = in[1];
    o.complete_value(2, f);
  }
  return r;
}

// Whether a result has the byte names (consumed(), needed()) or the bit names.
template <class R, class = void>
struct has_byte_names : std::false_type {};
template <class R>
struct has_byte_names<R, std::void_t<decltype(std::declval<const R&>().consumed()),
                                     decltype(std::declval<const R&>().needed())>>
    : std::true_type {};
template <class R, class = void>
struct has_bit_names : std::false_type {};
template <class R>
struct has_bit_names<R, std::void_t<decltype(std::declval<const R&>().consumed_bits()),
                                    decltype(std::declval<const R&>().needed_bits())>>
    : std::true_type {};

template <class T, class Steps>
decode_result<T> settled(Steps steps) {
  decode_result<T> r = need_input{1};
  steps(typename decode_result<T>::outcome(r));
  return r;
}

}  // namespace

TEST_CASE("decode_result built in place: the same outcomes as the converting constructors") {
  const std::uint8_t inputs[][3] = {{0x55, 0x09, 0xEE}, {0x00, 0x09, 0xEE}};
  for (const auto& in : inputs) {
    for (std::size_t n = 0; n <= 3; ++n) {
      CAPTURE(n);
      const auto a = toy_decode(byte_view(in, n));
      const auto b = toy_build(byte_view(in, n));
      CHECK(a.status() == b.status());
      CHECK(a.error() == b.error());
      CHECK(a.consumed() == b.consumed());
      CHECK(a.needed() == b.needed());
      CHECK(a->id == b->id);
      CHECK(b->position == 0);  // fields the decoder does not set stay value-initialised
    }
  }
  // Steps that settle nothing: incomplete, 1 unit needed, the value reads as value-initialised.
  const auto idle = settled<frame>([](decode_result<frame>::outcome) {});
  CHECK(idle.is_incomplete());
  CHECK(idle.needed() == 1);
  CHECK(idle.consumed() == 0);
  CHECK(idle.error() == errc::ok);
  CHECK(idle->id == 0);
  // fail carries evidence; an ok code is never reported as success; need(0) needs 1.
  const auto crc = settled<int>(
      [](decode_result<int>::outcome o) { o.fail(errc::crc_mismatch, 4, 0x4B, 0x12); });
  CHECK(crc.is_failed());
  CHECK(crc.expected() == 0x4B);
  CHECK(crc.received() == 0x12);
  CHECK(crc.consumed() == 4);
  const auto odd = settled<int>([](decode_result<int>::outcome o) { o.fail(errc::ok, 0); });
  CHECK(odd.is_failed());
  CHECK(odd.error() == errc::invalid_argument);
  const auto zero = settled<int>([](decode_result<int>::outcome o) { o.need(0); });
  CHECK(zero.is_incomplete());
  CHECK(zero.needed() == 1);
  // complete_in_place: the value is the caller's to set, member by member, in the result.
  const auto whole = settled<frame>([](decode_result<frame>::outcome o) {
    frame& f = o.complete_in_place(2);
    f.id = 3;
    f.position = 9;
  });
  CHECK(whole.is_complete());
  CHECK(whole.consumed() == 2);
  CHECK(whole->id == 3);
  CHECK(whole->position == 9);
}

TEST_CASE("a decoder counting bits says so: consumed_bits(), needed_bits()") {
  using bit_result = decode_result<int, input_unit::bits>;
  const bit_result done = bit_result::complete(7, 42);
  CHECK(done.consumed_bits() == 42);
  const bit_result more = need_input{9};
  CHECK(more.needed_bits() == 9);
  CHECK(more.consumed_bits() == 0);
  const bit_result bad = decode_failure{errc::biss_no_ack, 64};
  CHECK(bad.consumed_bits() == 64);
}

TEST_CASE("decode_result: complete, incomplete and failed") {
  constexpr std::uint8_t good[] = {0x55, 0x09, 0xEE};
  const auto ok = toy_decode(good);
  CHECK(ok.is_complete());
  CHECK(static_cast<bool>(ok));
  CHECK(ok.value().id == 9);
  CHECK(ok->position == 7);
  CHECK(ok.consumed() == 2);
  CHECK(ok.error() == errc::ok);

  const auto more = toy_decode(byte_view(good, 1));
  CHECK(more.is_incomplete());
  CHECK(!more);
  CHECK(more.needed() == 1);
  CHECK(more.value().id == 0);  // value-initialised

  constexpr std::uint8_t bad[] = {0x00};
  const auto fail = toy_decode(bad);
  CHECK(fail.is_failed());
  CHECK(fail.status() == decode_status::failed);
  CHECK(fail.error() == errc::no_frame);
  CHECK(fail.consumed() == 1);

  const decode_result<int> crc = decode_failure{errc::crc_mismatch, 4, 0x4B37, 0x1234};
  CHECK(crc.expected() == 0x4B37);
  CHECK(crc.received() == 0x1234);
  // an "ok" failure code is never reported as success
  const decode_result<int> odd = decode_failure{errc::ok, 0, 0, 0};
  CHECK(odd.is_failed());
  CHECK(odd.error() != errc::ok);
  const decode_result<int> zero = need_input{0};
  CHECK(zero.needed() == 1);
}

TEST_CASE("result: value or error") {
  const result<int> v = 42;
  CHECK(v.ok());
  CHECK(*v == 42);
  CHECK(v.value_or(1) == 42);
  const result<int> e = errc::truncated;
  CHECK(!e.ok());
  CHECK(e.error() == errc::truncated);
  CHECK(e.value() == 0);
  CHECK(e.value_or(1) == 1);
  const result<int> not_ok = errc::ok;
  CHECK(!not_ok.ok());
}

TEST_CASE("results at run time: an ok error code, set_consumed() of an incomplete result") {
  // The cases above with constants may be folded while compiling; these run.
  const result<int> r(testutil::at_run_time(errc::ok));
  CHECK_FALSE(r.ok());
  CHECK(r.error() == errc::invalid_argument);
  const decode_result<int> odd = decode_failure{testutil::at_run_time(errc::ok), 0, 0, 0};
  CHECK(odd.error() == errc::invalid_argument);
  decode_result<int> more = need_input{testutil::at_run_time(std::size_t{3})};
  more.set_consumed(5);  // nothing for an incomplete result
  CHECK(more.needed() == 3);
  CHECK(more.consumed() == 0);
  decode_result<int> fail = decode_failure{testutil::at_run_time(errc::no_frame), 1};
  fail.set_consumed(4);
  CHECK(fail.consumed() == 4);
  const decode_result<int> none;  // default-constructed: incomplete, at least one more byte
  CHECK(none.is_incomplete());
  CHECK(none.needed() == 1);
}

TEST_CASE("the unit is in the names: a byte result has no bit names, a bit result no byte names") {
  using byte_result = decode_result<int>;
  using bit_result = decode_result<int, input_unit::bits>;
  CHECK_FALSE(std::is_same<byte_result, bit_result>::value);
  CHECK(has_byte_names<byte_result>::value);
  CHECK_FALSE(has_bit_names<byte_result>::value);
  CHECK(has_bit_names<bit_result>::value);
  CHECK_FALSE(has_byte_names<bit_result>::value);
}

TEST_CASE("need_input{} is one more unit; decode_failure{code} drops nothing and has no evidence") {
  const decode_result<int> more = need_input{};
  CHECK(more.is_incomplete());
  CHECK(more.needed() == 1);
  const decode_result<int> bad = decode_failure{errc::no_frame};
  CHECK(bad.is_failed());
  CHECK(bad.consumed() == 0);
  CHECK(bad.expected() == 0);
  CHECK(bad.received() == 0);
  // fail(e, consumed) of an outcome: no evidence either
  const auto plain = settled<int>([](decode_result<int>::outcome o) { o.fail(errc::no_frame, 3); });
  CHECK(plain.consumed() == 3);
  CHECK(plain.expected() == 0);
  CHECK(plain.received() == 0);
}

TEST_CASE("an outcome settles a result whatever it held: a stream object's last result") {
  decode_result<int> r = decode_result<int>::complete(5, 2);
  decode_result<int>::outcome(r).need(3);
  CHECK(r.is_incomplete());
  CHECK(r.needed() == 3);
  CHECK(r.consumed() == 0);
  CHECK(r.value() == 0);
  decode_result<int> f = decode_failure{errc::crc_mismatch, 4, 0x4B, 0x12};
  decode_result<int>::outcome(f).need(1);
  CHECK(f.is_incomplete());
  CHECK(f.needed() == 1);
  CHECK(f.error() == errc::ok);
  CHECK(f.expected() == 0);
  decode_result<int>::outcome(f).fail(errc::no_frame, 1);
  CHECK(f.is_failed());
  CHECK(f.error() == errc::no_frame);
  CHECK(f.expected() == 0);
  CHECK(f.received() == 0);
}
