// The internals of T-format decoding (detail::), apart from the API tests: the two forms of
// decode_response (MOTIONBUS_SMALL_CODE) and the ID3 fast path must give the same outcomes,
// errors, counts, evidence and values as each other and as the generic layout decoder.
#include "motionbus/tformat/codec.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../support/prng.hpp"
#include "../support/tformat.hpp"

using namespace motionbus;
using namespace motionbus::tformat;
using namespace testutil;

TEST_CASE("the ID3 fast path agrees with the generic layout decoder on random frames") {
  // The speed form takes ID3 through detail::decode_read_all (one 64-bit load); it must give
  // exactly what the generic template gives, for good frames, bad CRCs, reserved SF bits and
  // every resolution option.
  testutil::splitmix64 rng(0x1D3);
  int complete = 0;
  int failed = 0;
  for (int i = 0; i < 20000; ++i) {
    std::vector<std::uint8_t> f(11);
    f[0] = 0x1A;
    for (std::size_t k = 1; k < 10; ++k) {
      f[k] = rng.byte();
    }
    const auto mode = rng.below(4);
    if (mode != 0U) {  // mostly sparse values, so that every check is reached
      f[1] = static_cast<std::uint8_t>(f[1] & 0xF0U);
      f[4] = static_cast<std::uint8_t>(f[4] & (mode == 1U ? 0x01U : 0x7FU));
      f[8] = mode == 3U ? f[8] : std::uint8_t{0};
    }
    std::uint8_t x = 0;
    for (std::size_t k = 0; k < 10; ++k) {
      x = static_cast<std::uint8_t>(x ^ f[k]);
    }
    f[10] = rng.below(8) == 0U ? rng.byte() : x;
    decode_options o;
    o.res = {static_cast<std::uint8_t>(1U + rng.below(40)),
             static_cast<std::uint8_t>(1U + rng.below(40))};
    o.check_unused_bits = rng.below(4) != 0U;
    o.resolution_from_enid = rng.below(2) != 0U;
    const auto fast = tformat::detail::decode_response_fast(view(f), o);
    const auto generic = tformat::detail::decode_status_frame<11, true, true, true, true>(
        view(f), data_id::read_all, o);
    CAPTURE(i);
    REQUIRE(fast.status() == generic.status());
    complete += fast.is_complete() ? 1 : 0;
    failed += fast.is_failed() ? 1 : 0;
    CHECK(fast.error() == generic.error());
    CHECK(fast.consumed() == generic.consumed());
    CHECK(fast.expected() == generic.expected());
    CHECK(fast.received() == generic.received());
    const auto& a = fast.value();
    const auto& b = generic.value();
    CHECK((a.id == b.id && a.cf == b.cf && a.sf == b.sf && a.abs == b.abs && a.enid == b.enid &&
           a.abm == b.abm && a.almc == b.almc && a.crc == b.crc));
  }
  CHECK(complete > 2000);  // both outcomes well represented
  CHECK(failed > 2000);
}

TEST_CASE("the size form of decode_response agrees with the speed form on every kind of input") {
  // MOTIONBUS_SMALL_CODE selects decode_response_small (one table-driven path) instead of
  // decode_response_fast; both must give the same outcome, error, counts, evidence and value:
  // every Data ID, truncations, bad CFs, bad CRCs, reserved SF bits, EEPROM busy, resolutions.
  testutil::splitmix64 rng(0x5A11);
  const auto good = valid_responses();
  int outcomes[3] = {};
  for (int i = 0; i < 60000; ++i) {
    std::vector<std::uint8_t> f;
    if (rng.below(4) == 0U) {  // anything at all
      f.resize(static_cast<std::size_t>(rng.below(13)));
      for (auto& b : f) {
        b = rng.byte();
      }
    } else {  // a valid frame, then damaged in one way or another
      f = good[static_cast<std::size_t>(rng.below(static_cast<std::uint32_t>(good.size())))];
      const auto mode = rng.below(6);
      if (mode == 0U && !f.empty()) {
        f.resize(static_cast<std::size_t>(rng.below(static_cast<std::uint32_t>(f.size()))));
      } else if (mode == 1U) {
        f[static_cast<std::size_t>(rng.below(static_cast<std::uint32_t>(f.size())))] ^=
            static_cast<std::uint8_t>(1U << rng.below(8));  // one bit flipped
      } else if (mode == 2U && f.size() > 2U) {
        f[1] = rng.byte();  // SF / ADF anything, CRC fixed up
        f.back() = xor_of(std::vector<std::uint8_t>(f.begin(), f.end() - 1));
      } else if (mode == 3U && f.size() > 5U) {
        f[4] = rng.byte();  // high ABS / ABM bits, CRC fixed up
        f.back() = xor_of(std::vector<std::uint8_t>(f.begin(), f.end() - 1));
      } else if (mode == 4U) {
        f.push_back(rng.byte());  // trailing byte: not consumed
      }
    }
    decode_options o;
    o.res = {static_cast<std::uint8_t>(1U + rng.below(40)),
             static_cast<std::uint8_t>(1U + rng.below(40))};
    o.check_unused_bits = rng.below(4) != 0U;
    o.resolution_from_enid = rng.below(2) != 0U;
    const auto small = tformat::detail::decode_response_small(view(f), o);
    const auto fast = tformat::detail::decode_response_fast(view(f), o);
    CAPTURE(i);
    REQUIRE(small.status() == fast.status());
    ++outcomes[static_cast<int>(small.status())];
    CHECK(small.error() == fast.error());
    CHECK(small.consumed() == fast.consumed());
    CHECK(small.needed() == fast.needed());
    CHECK(small.expected() == fast.expected());
    CHECK(small.received() == fast.received());
    const auto& a = small.value();
    const auto& b = fast.value();
    CHECK((a.id == b.id && a.cf == b.cf && a.sf == b.sf && a.abs == b.abs && a.enid == b.enid &&
           a.abm == b.abm && a.almc == b.almc && a.crc == b.crc && a.address == b.address &&
           a.busy == b.busy && a.edf == b.edf));
  }
  // complete, incomplete and failed all well represented
  CHECK(outcomes[static_cast<int>(decode_status::complete)] > 10000);
  CHECK(outcomes[static_cast<int>(decode_status::incomplete)] > 3000);
  CHECK(outcomes[static_cast<int>(decode_status::failed)] > 10000);
  // decode_response is the form the build selected.
  const auto r = decode_response(view(good[3]));
  CHECK(r.is_complete());
  CHECK(r.value().abs == tformat::detail::decode_response_small(view(good[3]), {}).value().abs);
}
