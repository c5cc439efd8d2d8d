// BiSS-C sensor data: CRCs against an independent long-division reference, frames built here
// bit by bit from docs/biss.md §1 and §5 (never by the encoder under test), the start search at
// every line delay and Ack length, every error path, chains of 1–3 slaves.
#include "motionbus/biss/codec.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "../support/bit_strings.hpp"
#include "../support/prng.hpp"
#include "../support/reference_crc.hpp"

using namespace motionbus;
using namespace motionbus::biss;

namespace {

// ---- independent helpers ----------------------------------------------------------------------

using testutil::as_ints;
using testutil::bits_of;
using testutil::bits_of_words;

// The wire CRC of a bit string: long division (reference), inverted when the format says so.
std::uint32_t ref_wire_crc(const crc_format& f, const std::string& covered) {
  const std::uint32_t mask = (std::uint32_t{1} << f.width) - 1U;
  const ref::model m{f.width, f.poly, f.start, false, false, f.inverted ? mask : 0U};
  return ref::crc_of_bits(m, as_ints(covered));
}

struct slave_bits {
  std::uint64_t mt = 0;
  std::uint64_t st = 0;
  bool ne = true;
  bool nw = true;
};

// One slave's fields as a bit string, from the layout description.
std::string slave_string(const slave_layout& l, const slave_bits& v) {
  std::string covered = bits_of(v.mt, l.multi_turn_bits) + bits_of(v.st, l.single_turn_bits) +
                        std::string(l.alignment_bits, '0');
  if (l.has_error) {
    covered.push_back(v.ne ? '1' : '0');
  }
  if (l.has_warning) {
    covered.push_back(v.nw ? '1' : '0');
  }
  return covered + bits_of(ref_wire_crc(l.crc, covered), l.crc.width);
}

std::string frame_string(std::size_t idle, std::size_t ack, bool cds,
                         const std::vector<slave_layout>& chain,
                         const std::vector<slave_bits>& values, const std::string& tail = "") {
  std::string s = std::string(idle, '1') + std::string(ack, '0') + "1" + (cds ? "1" : "0");
  for (std::size_t i = 0; i < chain.size(); ++i) {
    s += slave_string(chain[i], values[i]);
  }
  return s + tail;
}

template <class Word>
std::vector<Word> pack(const std::string& s) {
  constexpr unsigned w = sizeof(Word) * 8U;
  std::vector<Word> out((s.size() + w - 1U) / w + 1U, 0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '1') {
      out[i / w] = static_cast<Word>(out[i / w] | (Word{1} << (w - 1U - i % w)));
    }
  }
  return out;
}

template <class Word>
frame_result<max_chain> decode_string(const std::string& s, const std::vector<slave_layout>& chain,
                                      std::vector<slave_data>& out,
                                      const decode_options& opt = {}) {
  const std::vector<Word> words = pack<Word>(s);
  const auto r = decode_frame(span<const Word>(words.data(), words.size()), s.size(),
                              span<const slave_layout>(chain.data(), chain.size()), opt);
  out.assign(r->begin(), r->end());  // a complete frame's slaves, else none
  out.resize(chain.size());
  return r;
}

// A 25-bit multi-turn/single-turn slave with alignment, nE only and a 5-bit CRC (0x25), and an
// 18-bit slave without status bits, a 7-bit CRC (0x97) with a start value, not inverted.
const slave_layout mt_layout{12, 13, 2, true, false, crc_from_biss_notation(0x25)};
const slave_layout plain_layout{
    0, 18, 0, false, false, crc_from_biss_notation(0x97, 0x15, crc_output::plain)};
// 64 data bits and a 16-bit CRC: 82 bits, more than one 64-bit read.
const slave_layout wide_layout{24, 40, 0, true, true, crc_from_biss_notation(0x11021, 0x1D0F)};

}  // namespace

TEST_CASE("CRC6 0x43 and CRC4 0x13 match long division on every input up to 16 bits") {
  const ref::model crc6{6, 0x03, 0, false, false, 0x3F};
  const ref::model crc4{4, 0x03, 0, false, false, 0x0F};
  const dynamic_crc dyn6_proto(crc6_43.parameters());
  for (unsigned n = 1; n <= 16; ++n) {
    for (std::uint32_t v = 0; v < (1U << n); ++v) {
      const auto bits = as_ints(bits_of(v, n));
      const std::uint32_t r6 = ref::crc_of_bits(crc6, bits);
      const std::uint32_t r4 = ref::crc_of_bits(crc4, bits);
      CHECK(crc6_biss<crc_table_size::byte>::compute_bits(v, n) == r6);
      CHECK(crc6_biss<crc_table_size::nibble>::compute_bits(v, n) == r6);
      CHECK(crc6_biss<crc_table_size::bitwise>::compute_bits(v, n) == r6);
      CHECK(crc4_biss<crc_table_size::byte>::compute_bits(v, n) == r4);
      CHECK(crc4_biss<crc_table_size::bitwise>::compute_bits(v, n) == r4);
      dynamic_crc d = dyn6_proto;
      CHECK(d.update_bits(v, n).value() == r6);
    }
  }
}

TEST_CASE("CRC6, CRC4 and run-time CRCs match long division on random inputs up to 64 bits") {
  testutil::splitmix64 rng(0xB155);
  const crc_format formats[] = {crc6_43, crc_from_biss_notation(0x13), crc_from_biss_notation(0x25),
                                crc_from_biss_notation(0x97, 0x15, crc_output::plain),
                                crc_from_biss_notation(0x1021 | 0x10000, 0xFFFF)};
  for (int i = 0; i < 4000; ++i) {
    const auto n = static_cast<unsigned>(17U + rng.below(48));
    const std::uint64_t v =
        rng.next() & (n == 64U ? ~std::uint64_t{0} : ((std::uint64_t{1} << n) - 1U));
    for (const crc_format& f : formats) {
      const std::uint32_t want = ref_wire_crc(f, bits_of(v, n));
      CHECK(wire_crc<crc_table_size::byte>(f, v, n, 0, 0) == want);
      CHECK(wire_crc<crc_table_size::bitwise>(f, v, n, 0, 0) == want);
      // split between data and status the way the decoder feeds it
      CHECK(wire_crc(f, v >> 2U, n - 2U, static_cast<std::uint32_t>(v & 3U), 2) == want);
    }
  }
}

TEST_CASE("ABSYS frame: encoder output equals the frame built from the notes, decoder reads it") {
  const std::vector<slave_layout> chain{absys_layout};
  testutil::splitmix64 rng(7);
  for (int i = 0; i < 200; ++i) {
    const slave_bits v{0, rng.next() & 0xFFFFFFFFU, rng.below(2) == 0U, rng.below(4) != 0U};
    const bool cds = rng.below(2) != 0U;
    const auto ack = static_cast<std::size_t>(1U + rng.below(8));
    const std::string want = frame_string(0, ack, cds, chain, {v});
    std::uint32_t words[4] = {};
    line_options line;
    line.ack_bits = ack;
    line.cds = cds;
    const slave_values sv{0, v.st, v.ne, v.nw};
    const auto n = encode_frame(absys_layout, sv, span<std::uint32_t>(words, 4), line);
    REQUIRE(n.ok());
    REQUIRE(*n == want.size());
    CHECK(bits_of_words(words, *n) == want);
    std::vector<slave_data> out;
    const auto r = decode_string<std::uint32_t>(want, chain, out);
    REQUIRE(r.is_complete());
    CHECK(r->start == ack);
    CHECK(r->line_delay == 0);
    CHECK(r->cds == cds);
    CHECK(r.consumed_bits() == want.size());
    CHECK(out[0].single_turn == v.st);
    CHECK(out[0].data == v.st);
    CHECK(out[0].ne == v.ne);
    CHECK(out[0].nw == v.nw);
    CHECK(out[0].crc == ref_wire_crc(crc6_43, want.substr(ack + 2, 34)));
    CHECK(out[0].crc_ok());
  }
}

TEST_CASE("start search at every line delay and Ack length, CDS 0 and 1, 8/16/32-bit words") {
  const std::vector<slave_layout> chain{absys_layout};
  const slave_bits v{0, 0x89ABCDEFU, true, true};
  for (std::size_t idle = 0; idle <= 40; ++idle) {
    for (std::size_t ack = 1; ack <= 24; ++ack) {
      for (int cds = 0; cds < 2; ++cds) {
        // bits after the CRC are not guaranteed: put ones there
        const std::string s = frame_string(idle, ack, cds != 0, chain, {v}, "1011");
        std::vector<slave_data> o8;
        std::vector<slave_data> o16;
        std::vector<slave_data> o32;
        const auto r8 = decode_string<std::uint8_t>(s, chain, o8);
        const auto r16 = decode_string<std::uint16_t>(s, chain, o16);
        const auto r32 = decode_string<std::uint32_t>(s, chain, o32);
        CAPTURE(idle);
        CAPTURE(ack);
        REQUIRE(r8.is_complete());
        REQUIRE(r16.is_complete());
        REQUIRE(r32.is_complete());
        CHECK(r8->start == idle + ack);
        CHECK(r8->line_delay == idle);
        CHECK(r8->ack_bits() == ack);
        CHECK(r16->start == idle + ack);
        CHECK(r32->start == idle + ack);
        CHECK(r8->cds == (cds != 0));
        CHECK(o8[0].single_turn == 0x89ABCDEFU);
        CHECK(o16[0].single_turn == 0x89ABCDEFU);
        CHECK(o32[0].single_turn == 0x89ABCDEFU);
        CHECK(r32.consumed_bits() == s.size() - 4U);
      }
    }
  }
}

TEST_CASE("a line delay of 60 to 80 samples: the Ack at, and past, the end of the first 64") {
  // With max_line_delay above 64 the Ack is searched for past the first 64 samples: at
  // sample 64 itself (a delay of 64), and where sample 64 is still idle (a delay past 64).
  const std::vector<slave_layout> chain{absys_layout};
  const slave_bits v{0, 0x2468ACEU, false, true};
  for (std::size_t idle = 60; idle <= 80; ++idle) {
    for (std::size_t ack = 1; ack <= 3; ++ack) {
      CAPTURE(idle);
      CAPTURE(ack);
      const std::string s = frame_string(idle, ack, true, chain, {v}, "1011");
      std::vector<slave_data> out;
      const auto r = decode_string<std::uint32_t>(s, chain, out, decode_options{128, 256});
      REQUIRE(r.is_complete());
      CHECK(r->line_delay == idle);
      CHECK(r->start == idle + ack);
      CHECK(out[0].single_turn == 0x2468ACEU);
    }
  }
}

namespace {

// Decodes the first n samples of `s` packed in Word, the samples from n on set to `fill`.
template <class Word>
frame_result<max_chain> decode_prefix(const std::string& s, std::size_t n,
                                      const std::vector<slave_layout>& chain,
                                      std::vector<slave_data>& out, const std::string& fill) {
  const std::vector<Word> words = pack<Word>(s.substr(0, n) + fill);
  const auto r = decode_frame(span<const Word>(words.data(), words.size()), n,
                              span<const slave_layout>(chain.data(), chain.size()));
  out.assign(r->begin(), r->end());  // a complete frame's slaves, else none
  out.resize(chain.size());
  return r;
}

template <class Word>
void samples_past_the_count_are_ignored(testutil::splitmix64& rng) {
  const std::vector<std::vector<slave_layout>> chains{{absys_layout}, {plain_layout}};
  for (int round = 0; round < 60; ++round) {
    const auto& chain = chains[static_cast<std::size_t>(rng.below(2))];
    const slave_bits v{0, rng.next() & 0x3FFFFU, rng.below(2) == 0U, rng.below(2) == 0U};
    const std::string s =
        frame_string(static_cast<std::size_t>(rng.below(12)),
                     static_cast<std::size_t>(1U + rng.below(6)), rng.below(2) == 0U, chain, {v});
    std::string noise;
    for (int k = 0; k < 96; ++k) {
      noise.push_back(rng.below(2) == 0U ? '0' : '1');
    }
    for (std::size_t n = 0; n <= s.size() && n <= 64U; ++n) {
      std::vector<slave_data> clean;
      std::vector<slave_data> noisy;
      const auto a = decode_prefix<Word>(s, n, chain, clean, std::string(96, '0'));
      const auto b = decode_prefix<Word>(s, n, chain, noisy, noise);
      CAPTURE(s);
      CAPTURE(n);
      REQUIRE(a.status() == b.status());
      CHECK(a.error() == b.error());
      CHECK(a.consumed_bits() == b.consumed_bits());
      CHECK(a.needed_bits() == b.needed_bits());
      CHECK(a->start == b->start);
      CHECK(a->line_delay == b->line_delay);
      CHECK(a->cds == b->cds);
      CHECK(clean[0].data == noisy[0].data);
      CHECK(clean[0].crc == noisy[0].crc);
      CHECK(clean[0].ne == noisy[0].ne);
      if (n == s.size()) {
        CHECK(b.is_complete());
        CHECK(noisy[0].single_turn == v.st % (std::uint64_t{1} << chain[0].single_turn_bits));
      }
    }
  }
}

}  // namespace

TEST_CASE("samples past the bit count never change the outcome (short captures, any words)") {
  testutil::splitmix64 rng(64);
  samples_past_the_count_are_ignored<std::uint8_t>(rng);
  samples_past_the_count_are_ignored<std::uint16_t>(rng);
  samples_past_the_count_are_ignored<std::uint32_t>(rng);
}

TEST_CASE("LSB-first captures decode the same frame") {
  const std::string s = frame_string(3, 2, true, {absys_layout}, {{0, 0x1234567U, true, false}});
  std::vector<std::uint8_t> words((s.size() + 7U) / 8U, 0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '1') {
      words[i / 8U] = static_cast<std::uint8_t>(words[i / 8U] | (1U << (i % 8U)));
    }
  }
  const auto r = decode_frame(span<const std::uint8_t>(words.data(), words.size()), s.size(),
                              absys_layout, {}, bit_order::lsb_first);
  REQUIRE(r.is_complete());
  const slave_data& d = r->slaves[0];
  CHECK(r->start == 5);
  CHECK(d.single_turn == 0x1234567U);
  CHECK(d.warning());
}

TEST_CASE("no Ack, no Start, truncated: distinct outcomes") {
  const std::vector<slave_layout> chain{absys_layout};
  std::vector<slave_data> out;
  decode_options opt;
  opt.max_line_delay = 16;
  opt.max_ack_bits = 20;
  // only ones: need more input up to the bound, then no_ack
  CHECK(decode_string<std::uint8_t>(std::string(16, '1'), chain, out, opt).is_incomplete());
  CHECK(decode_string<std::uint8_t>(std::string(17, '1'), chain, out, opt).error() ==
        errc::biss_no_ack);
  CHECK(decode_string<std::uint8_t>(std::string(200, '1'), chain, out, opt).error() ==
        errc::biss_no_ack);
  // Ack forever: need more input up to the bound, then no_start
  CHECK(decode_string<std::uint8_t>("111" + std::string(20, '0'), chain, out, opt).is_incomplete());
  CHECK(decode_string<std::uint8_t>("111" + std::string(21, '0'), chain, out, opt).error() ==
        errc::biss_no_start);
  // an Ack of exactly the bound is accepted
  const std::string longest = frame_string(16, 20, false, chain, {{0, 5, true, true}});
  CHECK(decode_string<std::uint8_t>(longest, chain, out, opt).is_complete());
  CHECK(decode_string<std::uint8_t>(frame_string(17, 1, false, chain, {{0, 5, true, true}}), chain,
                                    out, opt)
            .error() == errc::biss_no_ack);
  // every strict prefix of a frame past its Start needs input, with the exact count
  const std::string full = frame_string(2, 3, true, chain, {{0, 0xCAFEF00DU, false, true}});
  for (std::size_t n = 0; n < full.size(); ++n) {
    const auto r = decode_string<std::uint16_t>(full.substr(0, n), chain, out);
    CAPTURE(n);
    REQUIRE(r.is_incomplete());
    if (n > 5U) {
      CHECK(r.needed_bits() == full.size() - n);
    }
  }
  CHECK(decode_string<std::uint16_t>(full, chain, out).is_complete());
}

TEST_CASE("every single-bit flip of data, nE, nW and CRC is a CRC mismatch; CDS flips are data") {
  const std::vector<slave_layout> chain{absys_layout};
  const std::string full = frame_string(1, 2, false, chain, {{0, 0x00F00F0FU, true, true}});
  const std::size_t first = 1 + 2 + 2;  // after idle, Ack, Start, CDS
  std::vector<slave_data> out;
  for (std::size_t i = first; i < full.size(); ++i) {
    std::string bad = full;
    bad[i] = bad[i] == '1' ? '0' : '1';
    const auto r = decode_string<std::uint32_t>(bad, chain, out);
    CAPTURE(i);
    REQUIRE(r.is_failed());
    CHECK(r.error() == errc::crc_mismatch);
    CHECK(r.consumed_bits() == full.size());
    // the evidence: the CRC sent (the frame's last 6 bits) and the one its data calls for
    CHECK(r.received() == std::stoul(bad.substr(bad.size() - 6U), nullptr, 2));
    CHECK(r.expected() == ref_wire_crc(crc6_43, bad.substr(first, 34)));
    CHECK(r.expected() != r.received());
  }
  std::string cds = full;
  cds[4] = '1';
  const auto r = decode_string<std::uint32_t>(cds, chain, out);
  REQUIRE(r.is_complete());
  CHECK(r->cds);
}

TEST_CASE("active nE / nW are device status, not failures") {
  const std::vector<slave_layout> chain{absys_layout};
  std::vector<slave_data> out;
  const auto r = decode_string<std::uint8_t>(
      frame_string(0, 1, false, chain, {{0, 42, false, false}}), chain, out);
  REQUIRE(r.is_complete());
  CHECK(out[0].error());
  CHECK(out[0].warning());
  CHECK(out[0].single_turn == 42);
}

TEST_CASE("chains of 1 to 3 slaves with different layouts") {
  const std::vector<slave_layout> layouts{absys_layout, mt_layout, plain_layout, wide_layout};
  testutil::splitmix64 rng(99);
  for (std::size_t n = 1; n <= 3; ++n) {
    for (int rep = 0; rep < 100; ++rep) {
      std::vector<slave_layout> chain;
      std::vector<slave_bits> vals;
      std::vector<slave_values> svals;
      for (std::size_t k = 0; k < n; ++k) {
        const slave_layout& l = layouts[(k + static_cast<std::size_t>(rep)) % 4U];
        chain.push_back(l);
        const slave_bits b{rng.next() & ((std::uint64_t{1} << l.multi_turn_bits) - 1U),
                           rng.next() & ((std::uint64_t{1} << l.single_turn_bits) - 1U),
                           !l.has_error || rng.below(2) == 0U,
                           !l.has_warning || rng.below(2) == 0U};
        vals.push_back(b);
        svals.push_back({b.mt, b.st, b.ne, b.nw});
      }
      const auto idle = static_cast<std::size_t>(rng.below(10));
      const auto ack = static_cast<std::size_t>(1U + rng.below(10));
      const std::string s = frame_string(idle, ack, rep % 2 == 0, chain, vals);
      std::vector<slave_data> out;
      const auto r = decode_string<std::uint16_t>(s, chain, out);
      CAPTURE(n);
      CAPTURE(rep);
      REQUIRE(r.is_complete());
      CHECK(r.consumed_bits() == s.size());
      CHECK(r->start == idle + ack);
      for (std::size_t k = 0; k < n; ++k) {
        CHECK(out[k].multi_turn == vals[k].mt);
        CHECK(out[k].single_turn == vals[k].st);
        CHECK(out[k].ne == vals[k].ne);
        CHECK(out[k].nw == vals[k].nw);
        CHECK(out[k].crc_ok());
      }
      // the encoder writes the same bits
      std::vector<std::uint16_t> words(20, 0);
      line_options line;
      line.line_delay = idle;
      line.ack_bits = ack;
      line.cds = rep % 2 == 0;
      const auto w = encode_frame(span<const slave_layout>(chain.data(), chain.size()),
                                  span<const slave_values>(svals.data(), svals.size()),
                                  span<std::uint16_t>(words.data(), words.size()), line);
      REQUIRE(w.ok());
      CHECK(*w == s.size());
      const auto packed = pack<std::uint16_t>(s);
      for (std::size_t k = 0; k * 16U < s.size(); ++k) {
        const unsigned used =
            s.size() - k * 16U >= 16U ? 16U : static_cast<unsigned>(s.size() - k * 16U);
        const auto mask = static_cast<std::uint16_t>(0xFFFFU << (16U - used));
        CHECK((words[k] & mask) == (packed[k] & mask));
      }
      // a bad CRC in the last slave fails the frame, its CRCs as the evidence
      const std::uint32_t last_crc = out[n - 1U].crc;
      std::string bad = s;
      bad.back() = bad.back() == '1' ? '0' : '1';
      const auto rb = decode_string<std::uint16_t>(bad, chain, out);
      CHECK(rb.error() == errc::crc_mismatch);
      CHECK(rb.received() == (last_crc ^ 1U));
      CHECK(rb.expected() == last_crc);
    }
  }
}

TEST_CASE("a chain given as an array of N layouts gives a chain_frame<N> equal to the span form") {
  const slave_layout chain[3] = {absys_layout, mt_layout, plain_layout};
  testutil::splitmix64 rng(7);
  for (int rep = 0; rep < 50; ++rep) {
    std::vector<slave_bits> vals;
    for (const slave_layout& l : chain) {
      vals.push_back({rng.next() & ((std::uint64_t{1} << l.multi_turn_bits) - 1U),
                      rng.next() & ((std::uint64_t{1} << l.single_turn_bits) - 1U),
                      !l.has_error || rng.below(2) == 0U, !l.has_warning || rng.below(2) == 0U});
    }
    std::string s = frame_string(static_cast<std::size_t>(rng.below(10)),
                                 static_cast<std::size_t>(1U + rng.below(5)), rep % 2 == 0,
                                 std::vector<slave_layout>(chain, chain + 3), vals);
    if (rep % 3 == 2) {  // a bad CRC somewhere, or a frame cut short
      char& c = s[s.size() - 1U - static_cast<std::size_t>(rng.below(20))];
      c = c == '1' ? '0' : '1';
    } else if (rep % 5 == 4) {
      s.resize(s.size() - 1U - static_cast<std::size_t>(rng.below(30)));
    }
    const std::vector<std::uint32_t> words = pack<std::uint32_t>(s);
    const span<const std::uint32_t> w(words.data(), words.size());
    const frame_result<3> a = decode_frame(w, s.size(), chain);
    const frame_result<max_chain> b = decode_frame(w, s.size(), span<const slave_layout>(chain, 3));
    CAPTURE(rep);
    REQUIRE(a.status() == b.status());
    CHECK(a.error() == b.error());
    if (a.is_complete()) {
      CHECK(a.consumed_bits() == b.consumed_bits());
      CHECK(a->size() == 3U);
      CHECK(a->start == b->start);
      CHECK(a->cds == b->cds);
      for (std::size_t k = 0; k < 3U; ++k) {
        CHECK(a->slaves[k].single_turn == vals[k].st);
        CHECK(a->slaves[k].multi_turn == vals[k].mt);
        CHECK(a->slaves[k].crc == b->slaves[k].crc);
      }
    } else if (a.is_failed()) {
      CHECK(a.expected() == b.expected());
      CHECK(a.received() == b.received());
    } else {
      CHECK(a.needed_bits() == b.needed_bits());
    }
  }
}

TEST_CASE("invalid layouts, chains, buffers and values are refused") {
  std::uint32_t words[4] = {};
  const span<const std::uint32_t> in(words, 4);
  slave_layout bad = absys_layout;
  bad.single_turn_bits = 70;
  CHECK(bad.validate() == errc::biss_layout);
  CHECK(decode_frame(in, 128, bad).error() == errc::biss_layout);
  bad = absys_layout;
  bad.crc.width = 17;
  CHECK(decode_frame(in, 128, bad).error() == errc::biss_layout);
  bad = absys_layout;
  bad.crc.poly = 0x43;  // BiSS notation given where the x^6 term must be left out
  CHECK(decode_frame(in, 128, bad).error() == errc::biss_layout);
  CHECK(decode_frame(in, 128, span<const slave_layout>{}).error() == errc::invalid_argument);
  const slave_layout two[2] = {absys_layout, absys_layout};
  const slave_layout nine[max_chain + 1] = {};
  CHECK(decode_frame(in, 128, span<const slave_layout>(nine, max_chain + 1)).error() ==
        errc::invalid_argument);

  std::uint32_t small[1] = {};
  CHECK(encode_frame(absys_layout, slave_values{}, span<std::uint32_t>(small, 1)).error() ==
        errc::buffer_too_small);
  CHECK(small[0] == 0U);
  slave_values big;
  big.single_turn = std::uint64_t{1} << 32U;
  CHECK(encode_frame(absys_layout, big, span<std::uint32_t>(words, 4)).error() ==
        errc::out_of_range);
  line_options no_ack;
  no_ack.ack_bits = 0;
  CHECK(encode_frame(absys_layout, slave_values{}, span<std::uint32_t>(words, 4), no_ack).error() ==
        errc::invalid_argument);
  CHECK(encoded_bits(span<const slave_layout>(two, 2), line_options{}) == 3U + 80U);
}

namespace {

// Encodes one frame of `layout` with `values` and decodes it back.
frame_result<1> round_trip(const slave_layout& layout, const slave_values& values, slave_data& d) {
  std::uint32_t words[6] = {};
  line_options line;
  line.line_delay = 3;
  line.ack_bits = 2;
  const auto n = encode_frame(layout, values, span<std::uint32_t>(words, 6), line);
  REQUIRE(n.ok());
  const auto r = decode_frame(span<const std::uint32_t>(words, 6), n.value(), layout);
  d = r->slaves[0];
  return r;
}

}  // namespace

TEST_CASE("BiSS-C layouts: no CRC, and 64 data bits with nE and nW") {
  slave_layout plain;
  plain.crc = crc_format{0, 0, 0, false};
  slave_values v;
  v.single_turn = 0x1234;
  slave_data d;
  auto r = round_trip(plain, v, d);
  REQUIRE(r.is_complete());
  CHECK(d.single_turn == 0x1234);
  CHECK(d.crc == 0);
  CHECK(d.crc_computed == 0);

  slave_layout wide;
  wide.multi_turn_bits = 32;
  wide.single_turn_bits = 32;
  v.multi_turn = 0xCAFEF00DU;
  v.single_turn = 0x89ABCDEFU;
  v.ne = false;
  r = round_trip(wide, v, d);
  REQUIRE(r.is_complete());
  CHECK(d.multi_turn == 0xCAFEF00DU);
  CHECK(d.single_turn == 0x89ABCDEFU);
  CHECK(d.error());
  CHECK(d.crc_ok());
}

TEST_CASE("BiSS-C encoder: an invalid layout is refused, and encoded_bits says 0") {
  slave_layout bad;
  bad.single_turn_bits = 0;  // no data bits at all
  const slave_layout chain[1] = {bad};
  CHECK(encoded_bits(span<const slave_layout>(chain, 1), line_options{}) == 0U);
  std::uint32_t words[4] = {};
  CHECK(encode_frame(bad, slave_values{}, span<std::uint32_t>(words, 4)).error() ==
        errc::biss_layout);
}

TEST_CASE("encode_frame and decode_frame: a 64-bit field, whichever part it is, round trips") {
  // 64 data bits in one part: the single-turn, the multi-turn or the alignment (no 64-bit
  // shift on the way in or out)
  struct part_case {
    unsigned mt, st, align;
  };
  const part_case cases[] = {{0, 64, 0}, {64, 0, 0}, {0, 0, 64}};
  for (const part_case& c : cases) {
    CAPTURE(c.mt);
    CAPTURE(c.st);
    slave_layout l;
    l.multi_turn_bits = c.mt;
    l.single_turn_bits = c.st;
    l.alignment_bits = c.align;
    REQUIRE(l.validate() == errc::ok);
    slave_values v;
    v.single_turn = c.st == 64U ? 0xF123456789ABCDEFULL : 0U;
    v.multi_turn = c.mt == 64U ? 0xFEDCBA9876543210ULL : 0U;
    std::uint32_t words[6] = {};
    const auto n = encode_frame(l, v, span<std::uint32_t>(words, 6));
    REQUIRE(n.ok());
    const auto r = decode_frame(span<const std::uint32_t>(words, 6), *n, l);
    REQUIRE(r.is_complete());
    const slave_data& d = r->slaves[0];
    CHECK(d.crc_ok());
    CHECK(d.single_turn == v.single_turn);
    CHECK(d.multi_turn == v.multi_turn);
    CHECK(d.data == (c.st == 64U ? v.single_turn : c.mt == 64U ? v.multi_turn : 0U));
  }
  // the multi-turn value must fit its bits, the 64-bit one any value
  slave_layout l;
  l.multi_turn_bits = 32;
  slave_values v;
  v.multi_turn = std::uint64_t{1} << 32U;
  std::uint32_t words[6] = {};
  CHECK(encode_frame(l, v, span<std::uint32_t>(words, 6)).error() == errc::out_of_range);
}

TEST_CASE("wire CRC: 6-bit CRCs other than the standard one, inverted or not, by long division") {
  // The standard CRC6 (x^6 + x + 1, start 0) has a fast path; another polynomial, another
  // start value, or a CRC sent as computed (not inverted) is checked against the reference.
  const crc_format formats[] = {
      {6, 0x03, 0, true}, {6, 0x03, 0, false}, {6, 0x05, 0, true}, {6, 0x03, 0x01, true}};
  for (const crc_format& f : formats) {
    CAPTURE(f.poly);
    CAPTURE(f.start);
    CAPTURE(f.inverted);
    slave_layout l;
    l.crc = f;
    REQUIRE(l.validate() == errc::ok);
    slave_values v;
    v.single_turn = 0x89ABCDEFU;
    v.nw = false;
    std::uint32_t words[4] = {};
    const auto n = encode_frame(l, v, span<std::uint32_t>(words, 4));
    REQUIRE(n.ok());
    const auto r = decode_frame(span<const std::uint32_t>(words, 4), *n, l);
    REQUIRE(r.is_complete());
    const slave_data& d = r->slaves[0];
    CHECK(d.crc_ok());
    // data (32 bits), nE 1, nW 0, as they go on the wire
    std::string covered;
    for (unsigned k = 32; k-- > 0U;) {
      covered.push_back(((v.single_turn >> k) & 1U) != 0U ? '1' : '0');
    }
    covered += "10";
    CHECK(d.crc == ref_wire_crc(f, covered));
  }
}

namespace {

// encode_frame then decode_frame of a two-slave chain in words of type Word, in `order`: every
// value back, each CRC good.
template <class Word>
void round_trip_chain(const slave_layout (&chain)[2], const slave_values (&values)[2],
                      bit_order order, const line_options& line, const decode_options& opt) {
  Word words[64] = {};
  const auto n =
      encode_frame(span<const slave_layout>(chain, 2), span<const slave_values>(values, 2),
                   span<Word>(words, 64), line, order);
  REQUIRE(n.ok());
  const auto r =
      decode_frame(span<const Word>(words, 64), *n, span<const slave_layout>(chain, 2), opt, order);
  REQUIRE(r.is_complete());
  CHECK(r->line_delay == line.line_delay);
  for (std::size_t i = 0; i < 2; ++i) {
    CAPTURE(i);
    const slave_data& d = r->slaves[i];
    CHECK(d.crc_ok());
    CHECK(d.single_turn == values[i].single_turn);
    CHECK(d.multi_turn == values[i].multi_turn);
    CHECK(d.ne == (chain[i].has_error ? values[i].ne : true));
    CHECK(d.nw == (chain[i].has_warning ? values[i].nw : true));
  }
}

}  // namespace

TEST_CASE("encode_frame and decode_frame: chains without status bits or CRC, any word, order") {
  // fields of width 0 (no nE, nW or CRC), a second slave past the 64-bit window, LSB-first
  // captures, line delays past the window (with the bound raised to allow them)
  slave_layout bare;
  bare.has_error = false;
  bare.has_warning = false;
  bare.crc = crc_format{0, 0, 0, false};  // no CRC
  bare.single_turn_bits = 20;
  slave_layout full;
  full.multi_turn_bits = 12;
  full.single_turn_bits = 20;
  const slave_layout chains[][2] = {{bare, full}, {full, bare}, {bare, bare}};
  const slave_values values[2] = {{0, 0xABCDE, false, true}, {0xFED, 0x12345, true, false}};
  for (const auto& chain : chains) {
    slave_values v[2] = {values[0], values[1]};
    for (std::size_t i = 0; i < 2; ++i) {
      if (chain[i].multi_turn_bits == 0U) {
        v[i].multi_turn = 0;
      }
    }
    for (const bit_order order : {bit_order::msb_first, bit_order::lsb_first}) {
      for (const std::size_t delay : {std::size_t{0}, std::size_t{3}, std::size_t{70}}) {
        CAPTURE(delay);
        line_options line;
        line.line_delay = delay;
        line.ack_bits = 2;
        decode_options opt;
        opt.max_line_delay = 100;
        round_trip_chain<std::uint8_t>(chain, v, order, line, opt);
        round_trip_chain<std::uint16_t>(chain, v, order, line, opt);
        round_trip_chain<std::uint32_t>(chain, v, order, line, opt);
        round_trip_chain<std::uint64_t>(chain, v, order, line, opt);
      }
    }
  }
}

TEST_CASE("encode_frame: each argument check alone; decode_frame: two bad CRCs in a chain") {
  const slave_layout chain[2] = {slave_layout{}, slave_layout{}};
  const slave_values values[2] = {};
  std::uint32_t words[8] = {};
  const span<std::uint32_t> out(words, 8);
  CHECK(encode_frame(span<const slave_layout>(), span<const slave_values>(), out).error() ==
        errc::invalid_argument);
  CHECK(encode_frame(span<const slave_layout>(chain, 2), span<const slave_values>(values, 1), out)
            .error() == errc::invalid_argument);
  slave_layout many[max_chain + 1] = {};
  slave_values many_values[max_chain + 1] = {};
  CHECK(encode_frame(span<const slave_layout>(many, max_chain + 1),
                     span<const slave_values>(many_values, max_chain + 1), out)
            .error() == errc::invalid_argument);
  CHECK(encode_frame(span<const slave_layout>(chain, 2), span<const slave_values>(values, 2), out,
                     line_options{}, bit_order::msb_first, 257)
            .error() == errc::buffer_too_small);
  // both slaves' CRCs wrong (decoded with another polynomial): crc_mismatch, its evidence the
  // first bad slave's (the second found bad changes nothing)
  const auto n =
      encode_frame(span<const slave_layout>(chain, 2), span<const slave_values>(values, 2), out);
  REQUIRE(n.ok());
  slave_layout other[2] = {slave_layout{}, slave_layout{}};
  other[0].crc.poly = 0x05;
  other[1].crc.poly = 0x05;
  const auto r =
      decode_frame(span<const std::uint32_t>(words, 8), *n, span<const slave_layout>(other, 2));
  REQUIRE(r.is_failed());
  CHECK(r.error() == errc::crc_mismatch);
  CHECK(r.expected() != r.received());
}

TEST_CASE("decode_frame: an empty capture, and 64 samples with the Ack but no Start, need more") {
  // no samples, in each bit order and with words of 8 and 64 bits (the window is built three
  // ways): one more sample needed
  const std::uint8_t none8[1] = {0xFF};
  const std::uint64_t none64[1] = {~std::uint64_t{0}};
  for (const bit_order order : {bit_order::msb_first, bit_order::lsb_first}) {
    CAPTURE(static_cast<int>(order));
    const auto a = decode_frame(none8, 0, absys_layout, {}, order);
    CHECK(a.is_incomplete());
    CHECK(a.needed_bits() == 1);
    const auto b = decode_frame(none64, 0, absys_layout, {}, order);
    CHECK(b.is_incomplete());
    CHECK(b.needed_bits() == 1);
  }
  // exactly one window of 64 samples: the line high, the Ack from sample 2 on and no Start
  // yet: nothing past the window to search, one more sample needed (62 zeros are within
  // max_ack_bits)
  const std::uint8_t ack_only[8] = {0xC0, 0, 0, 0, 0, 0, 0, 0};
  const auto c = decode_frame(ack_only, 64, absys_layout);
  CHECK(c.is_incomplete());
  CHECK(c.needed_bits() == 1);
  // the same with a Start in the 65th sample: the search goes on past the window and finds it
  const std::uint8_t start_after[9] = {0xC0, 0, 0, 0, 0, 0, 0, 0, 0x80};
  const auto d = decode_frame(start_after, 65, absys_layout);
  CHECK(d.is_incomplete());
  CHECK(d.needed_bits() > 1);  // the Start found: the frame's fields still to come
}

TEST_CASE("default decode_options: a line delay up to 64 samples, an Ack up to 256") {
  // docs/biss.md §1, decoding a capture: biss_no_ack after only 1s over max_line_delay + 1
  // samples (65 by default), biss_no_start after only 0s over 256 samples after the first 0.
  const std::vector<slave_layout> chain{absys_layout};
  const slave_bits v{0, 0x13579BDU, true, true};
  std::vector<slave_data> out;
  const auto longest_delay =
      decode_string<std::uint32_t>(frame_string(64, 1, false, chain, {v}), chain, out);
  REQUIRE(longest_delay.is_complete());
  CHECK(longest_delay->line_delay == 64);
  CHECK(out[0].single_turn == 0x13579BDU);
  CHECK(decode_string<std::uint32_t>(frame_string(65, 1, false, chain, {v}), chain, out).error() ==
        errc::biss_no_ack);
  CHECK(decode_string<std::uint32_t>(std::string(64, '1'), chain, out).is_incomplete());
  CHECK(decode_string<std::uint32_t>(std::string(65, '1'), chain, out).error() ==
        errc::biss_no_ack);
  const auto longest_ack =
      decode_string<std::uint32_t>(frame_string(2, 256, false, chain, {v}), chain, out);
  REQUIRE(longest_ack.is_complete());
  CHECK(longest_ack->ack_bits() == 256);
  CHECK(out[0].single_turn == 0x13579BDU);
  CHECK(decode_string<std::uint32_t>(frame_string(2, 257, false, chain, {v}), chain, out).error() ==
        errc::biss_no_start);
}

TEST_CASE("64 data bits with nE and nW: the CRC6 covers all 66 bits (long division)") {
  // Data and status together longer than 64 bits: the CRC is fed in two parts. The CRC sent
  // and the CRC computed are checked against the reference, not only against each other.
  const std::vector<slave_layout> chains[] = {{slave_layout{32, 32, 0, true, true, crc6_43}},
                                              {slave_layout{0, 63, 0, true, true, crc6_43}},
                                              {slave_layout{0, 64, 0, true, false, crc6_43}}};
  const slave_bits values[] = {{0xCAFEF00DU, 0x89ABCDEFU, false, true},
                               {0xCAFEF00DU, 0x89ABCDEFU, true, false},
                               {0, 0x7123456789ABCDEFULL, true, true}};
  for (const auto& chain : chains) {
    const slave_layout& l = chain[0];
    for (const slave_bits& given : values) {
      slave_bits v = given;
      if (l.multi_turn_bits == 0U) {
        v.st = (v.mt << 32U) | v.st;
        v.mt = 0;
      }
      v.st &= l.single_turn_bits == 64U ? ~std::uint64_t{0}
                                        : (std::uint64_t{1} << l.single_turn_bits) - 1U;
      CAPTURE(l.single_turn_bits);
      CAPTURE(v.st);
      const std::string s = frame_string(1, 1, false, chain, {v});
      const std::size_t covered = l.data_bits() + l.status_bits();
      const std::uint32_t want = ref_wire_crc(crc6_43, s.substr(4, covered));
      // the decoder: the CRC it computes is the reference's
      std::vector<slave_data> out;
      const auto r = decode_string<std::uint32_t>(s, chain, out);
      REQUIRE(r.is_complete());
      CHECK(out[0].crc == want);
      CHECK(out[0].crc_computed == want);
      // the encoder: the bits it writes are the frame built here
      std::uint32_t words[4] = {};
      line_options line;
      line.line_delay = 1;
      const auto n = encode_frame(l, slave_values{v.mt, v.st, v.ne, v.nw},
                                  span<std::uint32_t>(words, 4), line);
      REQUIRE(n.ok());
      REQUIRE(*n == s.size());
      CHECK(bits_of_words(words, *n) == s);
    }
  }
}

TEST_CASE("decode_frame: a refused chain or layout consumes none of the capture") {
  // decode_failure::consumed is what the caller may drop: an argument error says nothing of
  // the capture, so nothing (0), whatever the samples hold.
  const std::string s = frame_string(2, 1, false, {absys_layout}, {{0, 0x1234U, true, true}});
  const std::vector<std::uint32_t> words = pack<std::uint32_t>(s);
  const span<const std::uint32_t> in(words.data(), words.size());
  const auto empty = decode_frame(in, s.size(), span<const slave_layout>{});
  CHECK(empty.error() == errc::invalid_argument);
  CHECK(empty.consumed_bits() == 0U);
  const slave_layout nine[max_chain + 1] = {};
  const auto long_chain = decode_frame(in, s.size(), span<const slave_layout>(nine, max_chain + 1));
  CHECK(long_chain.error() == errc::invalid_argument);
  CHECK(long_chain.consumed_bits() == 0U);
  slave_layout bad = absys_layout;
  bad.crc.width = 17;
  const auto bad_layout = decode_frame(in, s.size(), bad);
  CHECK(bad_layout.error() == errc::biss_layout);
  CHECK(bad_layout.consumed_bits() == 0U);
  const slave_layout chain[2] = {absys_layout, bad};
  const auto bad_second = decode_frame(in, s.size(), span<const slave_layout>(chain, 2));
  CHECK(bad_second.error() == errc::biss_layout);
  CHECK(bad_second.consumed_bits() == 0U);
}

TEST_CASE("no Ack or no Start yet: one more sample needed, for one slave and for a chain alike") {
  // Before the Ack, or between the Ack and the Start bit, the decoder cannot tell how long the
  // line stays idle or the Ack lasts: at least one more sample, whatever the chain's length
  // (as for one slave: "an empty capture, and 64 samples with the Ack but no Start").
  const std::vector<std::vector<slave_layout>> chains{
      {absys_layout}, {absys_layout, mt_layout}, {absys_layout, mt_layout, plain_layout}};
  const std::string captures[] = {"",
                                  "1",
                                  std::string(10, '1'),
                                  "1110",
                                  "11" + std::string(40, '0'),
                                  std::string(3, '1') + std::string(70, '0')};
  for (const auto& chain : chains) {
    for (const std::string& s : captures) {
      CAPTURE(chain.size());
      CAPTURE(s);
      std::vector<slave_data> out;
      const auto r = decode_string<std::uint8_t>(s, chain, out);
      REQUIRE(r.is_incomplete());
      CHECK(r.needed_bits() == 1U);
    }
  }
}

TEST_CASE("an Ack of max_ack_bits whose Start bit is sample 64, the first past the window") {
  // The Start bit is searched for past the first 64 samples with the Ack's bound left: an Ack
  // of exactly max_ack_bits ending at sample 63 is accepted, one sample longer is refused.
  const std::vector<slave_layout> chain{absys_layout};
  const slave_bits v{0, 0x0F1E2D3CU, true, false};
  for (const std::size_t bound :
       {std::size_t{1}, std::size_t{2}, std::size_t{20}, std::size_t{63}}) {
    decode_options opt;
    opt.max_ack_bits = bound;
    CAPTURE(bound);
    std::vector<slave_data> out;
    const std::string s = frame_string(64 - bound, bound, true, chain, {v});
    const auto r = decode_string<std::uint32_t>(s, chain, out, opt);
    REQUIRE(r.is_complete());
    CHECK(r->start == 64);
    CHECK(r->ack_bits() == bound);
    CHECK(out[0].single_turn == 0x0F1E2D3CU);
    CHECK(r.consumed_bits() == s.size());
    CHECK(decode_string<std::uint32_t>(frame_string(63 - bound, bound + 1, true, chain, {v}), chain,
                                       out, opt)
              .error() == errc::biss_no_start);
  }
}

TEST_CASE("a chain given as a span: the slots past the chain hold value-initialised slave_data") {
  // frame.hpp: chain_frame's slaves past size() are value-initialised, whatever the memory
  // the result is built in held before (here: filled with 0xA5, the result built in place).
  const std::vector<slave_layout> chain{absys_layout, mt_layout};
  const std::string s = frame_string(3, 2, false, chain, {{0, 0x1234U, true, true}, {5, 6, false}});
  const std::vector<std::uint32_t> words = pack<std::uint32_t>(s);
  alignas(frame_result<max_chain>) unsigned char storage[sizeof(frame_result<max_chain>)];
  std::memset(storage, 0xA5, sizeof storage);
  const auto* r = ::new (static_cast<void*>(storage)) frame_result<max_chain>(
      decode_frame(span<const std::uint32_t>(words.data(), words.size()), s.size(),
                   span<const slave_layout>(chain.data(), chain.size())));
  REQUIRE(r->is_complete());
  REQUIRE((*r)->size() == 2U);
  CHECK((*r)->slaves[0].single_turn == 0x1234U);
  CHECK((*r)->slaves[1].multi_turn == 5U);
  for (std::size_t k = 2; k < max_chain; ++k) {
    CAPTURE(k);
    const slave_data& d = (*r)->slaves[k];
    CHECK(d.data == 0U);
    CHECK(d.multi_turn == 0U);
    CHECK(d.single_turn == 0U);
    CHECK(d.ne);
    CHECK(d.nw);
    CHECK(d.crc == 0U);
    CHECK(d.crc_computed == 0U);
  }
}

TEST_CASE(
    "a one-bit data field with nE and nW: each of the eight combinations, in and past the window") {
  // The smallest layout validate() accepts: data, nE and nW one bit each, then the CRC6.
  // Decoded from the first 64 samples, and past them (a line delay of 70).
  const slave_layout tiny{0, 1, 0, true, true, crc6_43};
  REQUIRE(tiny.validate() == errc::ok);
  const std::vector<slave_layout> chain{tiny};
  decode_options opt;
  opt.max_line_delay = 100;
  for (const std::size_t idle : {std::size_t{2}, std::size_t{70}}) {
    for (unsigned bits = 0; bits < 8U; ++bits) {
      const slave_bits v{0, (bits >> 2U) & 1U, ((bits >> 1U) & 1U) != 0U, (bits & 1U) != 0U};
      CAPTURE(idle);
      CAPTURE(bits);
      const std::string s = frame_string(idle, 1, false, chain, {v});
      std::vector<slave_data> out;
      const auto r = decode_string<std::uint16_t>(s, chain, out, opt);
      REQUIRE(r.is_complete());
      CHECK(out[0].single_turn == v.st);
      CHECK(out[0].ne == v.ne);
      CHECK(out[0].nw == v.nw);
      CHECK(out[0].crc == ref_wire_crc(crc6_43, s.substr(idle + 3, 3)));
      CHECK(out[0].crc_ok());
    }
  }
}

TEST_CASE("alignment bits sent as ones are filler: not in the single-turn or multi-turn value") {
  // frame.hpp: alignment bits are low-order filler after the single-turn value; whatever a
  // slave puts there, the position is the multi-turn and single-turn bits alone (the CRC
  // covers the filler as sent). All 64 data bits filler too: no position at all. Line delay
  // 2, Ack 1, Start, CDS 0.
  struct filler_case {
    slave_layout layout;
    std::uint64_t mt, st;
  };
  const filler_case cases[] = {{slave_layout{0, 0, 64, true, true, crc6_43}, 0, 0},
                               {mt_layout, 0xABC, 0x1234},
                               {slave_layout{10, 20, 34, false, true, crc6_43}, 0x3FF, 0xFFFFF}};
  for (const filler_case& c : cases) {
    const slave_layout& l = c.layout;
    CAPTURE(l.alignment_bits);
    REQUIRE(l.validate() == errc::ok);
    std::string covered = bits_of(c.mt, l.multi_turn_bits) + bits_of(c.st, l.single_turn_bits) +
                          std::string(l.alignment_bits, '1');
    covered += std::string(l.status_bits(), '1');
    const std::string s = "11010" + covered + bits_of(ref_wire_crc(l.crc, covered), l.crc.width);
    const std::vector<slave_layout> chain{l};
    std::vector<slave_data> out;
    const auto r = decode_string<std::uint32_t>(s, chain, out);
    REQUIRE(r.is_complete());
    CHECK(out[0].crc_ok());
    CHECK(out[0].multi_turn == c.mt);
    CHECK(out[0].single_turn == c.st);
    const unsigned db = l.data_bits();
    std::uint64_t want_data = 0;
    for (unsigned k = 0; k < db; ++k) {
      want_data = (want_data << 1U) | (covered[k] == '1' ? 1U : 0U);
    }
    CHECK(out[0].data == want_data);
  }
}

TEST_CASE(
    "encode_frame: default slave_values and line_options are position 0, no error, no warning") {
  // slave_values{}: multi-turn and single-turn 0, nE and nW high (inactive); line_options{}:
  // no line delay, an Ack of one sample, CDS 0, no timeout.
  const slave_layout layouts[] = {absys_layout, mt_layout};
  for (const slave_layout& l : layouts) {
    CAPTURE(l.multi_turn_bits);
    const std::string want = frame_string(0, 1, false, {l}, {{0, 0, true, true}});
    std::uint32_t words[4] = {0xFFFFFFFFU, 0xFFFFFFFFU, 0xFFFFFFFFU, 0xFFFFFFFFU};
    const auto n = encode_frame(l, slave_values{}, span<std::uint32_t>(words, 4));
    REQUIRE(n.ok());
    REQUIRE(*n == want.size());
    CHECK(bits_of_words(words, *n) == want);
  }
}

TEST_CASE("a chain of max_chain (eight) slaves: encoded as the notes build it, decoded back") {
  // frame.hpp: chains of up to 8 slaves (IDs 0..7); the longest is accepted by both sides.
  const std::vector<slave_layout> chain(max_chain, absys_layout);
  std::vector<slave_bits> bits;
  std::vector<slave_values> values;
  for (std::size_t k = 0; k < max_chain; ++k) {
    const std::uint64_t st = 0x01020304U * (k + 1U);
    bits.push_back({0, st, k % 2U == 0U, k % 3U != 0U});
    values.push_back({0, st, k % 2U == 0U, k % 3U != 0U});
  }
  const std::string want = frame_string(2, 1, true, chain, bits);
  std::uint32_t words[12] = {};
  line_options line;
  line.line_delay = 2;
  line.cds = true;
  const auto n = encode_frame(span<const slave_layout>(chain.data(), chain.size()),
                              span<const slave_values>(values.data(), values.size()),
                              span<std::uint32_t>(words, 12), line);
  REQUIRE(n.ok());
  REQUIRE(*n == want.size());
  CHECK(bits_of_words(words, *n) == want);
  std::vector<slave_data> out;
  const auto r = decode_string<std::uint32_t>(want, chain, out);
  REQUIRE(r.is_complete());
  CHECK(r->size() == max_chain);
  for (std::size_t k = 0; k < max_chain; ++k) {
    CAPTURE(k);
    CHECK(out[k].single_turn == bits[k].st);
    CHECK(out[k].ne == bits[k].ne);
    CHECK(out[k].nw == bits[k].nw);
    CHECK(out[k].crc_ok());
  }
}

TEST_CASE("encode_frame: a frame that fills the buffer to its last bit is written whole") {
  // ABSYS: Ack 1, Start, CDS, 40 bits: 43 samples; with 21 samples of timeout, or from bit 21,
  // exactly the 64 bits of two 32-bit words. One bit fewer room is buffer_too_small.
  const slave_values v{0, 0x89ABCDEFU, true, false};
  const std::string frame =
      frame_string(0, 1, false, {absys_layout}, {{0, 0x89ABCDEFU, true, false}});
  REQUIRE(frame.size() == 43U);
  line_options timeout;
  timeout.timeout_bits = 21;
  std::uint32_t a[2] = {0xFFFFFFFFU, 0xFFFFFFFFU};
  const auto na = encode_frame(absys_layout, v, a, timeout);
  REQUIRE(na.ok());
  CHECK(*na == 64U);
  CHECK(bits_of_words(a, 64) == frame + std::string(21, '0'));
  std::uint32_t b[2] = {};
  const auto nb = encode_frame(absys_layout, v, b, line_options{}, bit_order::msb_first, 21);
  REQUIRE(nb.ok());
  CHECK(*nb == 43U);
  CHECK(bits_of_words(b, 64) == std::string(21, '0') + frame);
  timeout.timeout_bits = 22;
  CHECK(encode_frame(absys_layout, v, a, timeout).error() == errc::buffer_too_small);
  CHECK(encode_frame(absys_layout, v, b, line_options{}, bit_order::msb_first, 22).error() ==
        errc::buffer_too_small);
}

TEST_CASE("encode_frame: nE alone, nW alone, neither: the bits the notes give, chain form too") {
  // Each layout's status bits are the ones it has, and its CRC6 covers them alone. The chain
  // form into a plain array writes from bit 0 as the other forms do.
  const slave_layout ne_only{0, 24, 0, true, false, crc6_43};
  const slave_layout nw_only{0, 24, 0, false, true, crc6_43};
  const slave_layout neither{0, 24, 0, false, false, crc6_43};
  const std::uint64_t positions[] = {0x123456U, 0xABCDEFU};
  for (const slave_layout& l : {ne_only, nw_only, neither}) {
    for (const std::uint64_t st : positions) {
      for (unsigned flags = 0; flags < 4U; ++flags) {
        const bool ne = (flags & 2U) != 0U;
        const bool nw = (flags & 1U) != 0U;
        CAPTURE(l.has_error);
        CAPTURE(l.has_warning);
        CAPTURE(st);
        CAPTURE(flags);
        const std::string want = frame_string(0, 1, true, {l}, {{0, st, ne, nw}});
        const slave_layout chain[1] = {l};
        const slave_values values[1] = {{0, st, ne, nw}};
        line_options line;
        line.cds = true;
        std::uint32_t words[2] = {0xFFFFFFFFU, 0xFFFFFFFFU};
        const auto n = encode_frame(span<const slave_layout>(chain, 1),
                                    span<const slave_values>(values, 1), words, line);
        REQUIRE(n.ok());
        REQUIRE(*n == want.size());
        CHECK(bits_of_words(words, *n) == want);
      }
    }
  }
}

TEST_CASE("a result that is not complete holds an empty frame: no slaves, nothing found") {
  // result.hpp: value() of a result that is not complete is a value-initialised T; for a
  // chain_frame that is no slave decoded (size() 0, begin() == end()) and no line delay, Start
  // bit or CDS found (0, 0, false). Both a need for more input and a failure.
  const std::vector<slave_layout> chain{absys_layout, mt_layout};
  const std::string captures[] = {
      std::string(10, '1'), std::string(200, '1'),
      frame_string(3, 2, true, chain, {{0, 5, true, true}, {1, 2}}).substr(0, 30)};
  for (const std::string& s : captures) {
    CAPTURE(s.size());
    const std::vector<std::uint32_t> words = pack<std::uint32_t>(s);
    const auto r = decode_frame(span<const std::uint32_t>(words.data(), words.size()), s.size(),
                                span<const slave_layout>(chain.data(), chain.size()));
    REQUIRE(!r.is_complete());
    CHECK(r->size() == 0U);
    CHECK(r->begin() == r->end());
    CHECK(r->line_delay == 0U);
    CHECK(r->start == 0U);
    CHECK(!r->cds);
    CHECK(r->ack_bits() == 0U);
    for (const slave_data& d : r->slaves) {
      CHECK(d.data == 0U);
      CHECK(d.crc == 0U);
      CHECK(d.crc_computed == 0U);
      CHECK(d.multi_turn == 0U);
      CHECK(d.single_turn == 0U);
      CHECK(d.ne);
      CHECK(d.nw);
    }
  }
}
