// T-format decode speed against a spec-literal baseline in the same run: the baseline computes
// the CRC G(X) = X^8 + 1 one bit at a time as the spec describes it (spec §6.3.4) and assembles
// every field bit by bit, LSB first (spec §6.3.3, Figure 6); the bit-stream baseline also finds
// the frame start one sample at a time (spec §8.1).
#include <motionbus/tformat.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

// --- the spec-literal baseline ---------------------------------------------------------------
struct naive_response {
  std::uint8_t cf = 0, sf = 0, enid = 0, almc = 0;
  std::uint32_t abs = 0, abm = 0;
  bool ok = false;
};

// CRC register of G(X) = X^8 + 1, one data bit at a time, bits in wire order (LSB first).
std::uint8_t naive_crc(const std::uint8_t* bytes, std::size_t n) {
  unsigned reg = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (unsigned b = 0; b < 8; ++b) {
      const unsigned in = (bytes[i] >> b) & 1U;
      const unsigned feedback = ((reg >> 7U) & 1U) ^ in;
      reg = ((reg << 1U) & 0xFFU) | feedback;  // x^8 + 1: the feedback re-enters at x^0
    }
  }
  // The register holds the CRC with its bits in wire order: reverse to a byte.
  unsigned out = 0;
  for (unsigned b = 0; b < 8; ++b) {
    out |= ((reg >> b) & 1U) << (7U - b);
  }
  return static_cast<std::uint8_t>(out);
}

std::uint32_t naive_field(const std::uint8_t* bytes, std::size_t first, std::size_t count) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < count * 8U; ++k) {
    const unsigned bit = (bytes[first + k / 8U] >> (k % 8U)) & 1U;
    v |= static_cast<std::uint32_t>(bit) << k;
  }
  return v;
}

naive_response naive_decode(const std::uint8_t* f, std::size_t n) {
  naive_response r;
  if (n < 1 || (f[0] & 7U) != 2U) {
    return r;
  }
  const unsigned id = (f[0] >> 3U) & 0xFU;
  const std::size_t size = id == 3 ? 11 : (id == 2 ? 4 : 6);
  if (n < size || naive_crc(f, size - 1) != f[size - 1]) {
    return r;
  }
  r.cf = f[0];
  r.sf = static_cast<std::uint8_t>(naive_field(f, 1, 1));
  if (id == 3) {
    r.abs = naive_field(f, 2, 3);
    r.enid = static_cast<std::uint8_t>(naive_field(f, 5, 1));
    r.abm = naive_field(f, 6, 3);
    r.almc = static_cast<std::uint8_t>(naive_field(f, 9, 1));
  } else if (id == 1) {
    r.abm = naive_field(f, 2, 3);
  } else {
    r.abs = naive_field(f, 2, 3);
  }
  r.ok = true;
  return r;
}

// Bit stream: samples one per byte-array bit, MSB first.
int sample(const std::uint32_t* words, std::size_t i) {
  return static_cast<int>((words[i / 32U] >> (31U - i % 32U)) & 1U);
}

naive_response naive_decode_line(const std::uint32_t* words, std::size_t bits) {
  for (std::size_t i = 0; i + 4 <= bits; ++i) {
    if (sample(words, i) == 0 && (i == 0 || sample(words, i - 1) == 1) &&
        sample(words, i + 1) == 0 && sample(words, i + 2) == 1 && sample(words, i + 3) == 0) {
      std::uint8_t bytes[11] = {};
      std::size_t fields = 1;
      for (std::size_t k = 0; k < fields; ++k) {
        const std::size_t at = i + k * 10U;
        if (at + 10 > bits || sample(words, at) != 0 || sample(words, at + 9) != 1) {
          return {};
        }
        unsigned v = 0;
        for (unsigned b = 0; b < 8; ++b) {
          v |= static_cast<unsigned>(sample(words, at + 1 + b)) << b;
        }
        bytes[k] = static_cast<std::uint8_t>(v);
        if (k == 0) {
          const unsigned id = (v >> 3U) & 0xFU;
          fields = id == 3 ? 11 : (id == 2 ? 4 : 6);
        }
      }
      return naive_decode(bytes, fields);
    }
  }
  return {};
}

// --- inputs ------------------------------------------------------------------------------------
std::vector<std::uint8_t> frame_for(tf::data_id id, std::uint32_t abs) {
  tf::response r;
  r.id = id;
  r.abs = abs & 0x1FFFFU;
  r.abm = 0x1234;
  r.enid = 0x11;
  r.almc = 0x40;
  std::uint8_t out[11] = {};
  const std::size_t n = tf::encode_response(r, out).value();
  return {out, out + n};
}

// 64 distinct frames so that branch predictors do not learn one input.
std::vector<std::vector<std::uint8_t>> frames(tf::data_id id) {
  std::vector<std::vector<std::uint8_t>> out;
  for (std::uint32_t i = 0; i < 64; ++i) {
    out.push_back(frame_for(id, i * 2039U));
  }
  return out;
}

// The 64 frames back to back in one array, each in a 16-byte slot.
std::vector<std::uint8_t> flat(tf::data_id id, std::size_t& size) {
  std::vector<std::uint8_t> out(64U * 16U, 0);
  const auto list = frames(id);
  size = list[0].size();
  for (std::size_t k = 0; k < 64; ++k) {
    std::copy(list[k].begin(), list[k].end(), out.begin() + static_cast<long>(k * 16U));
  }
  return out;
}

template <tf::data_id Id>
void bm_decode(benchmark::State& state) {
  std::size_t size = 0;
  const auto input = flat(Id, size);
  std::size_t i = 0;
  for (auto _ : state) {
    const std::uint8_t* f = input.data() + (i++ & 63U) * 16U;
    auto r = tf::decode_response(mb::byte_view(f, size));
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

template <tf::data_id Id>
void bm_decode_baseline(benchmark::State& state) {
  std::size_t size = 0;
  const auto input = flat(Id, size);
  std::size_t i = 0;
  for (auto _ : state) {
    const std::uint8_t* f = input.data() + (i++ & 63U) * 16U;
    auto r = naive_decode(f, size);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

// ID3 response after 7 idle bits in 32-bit MSB-first words (a typical SPI capture).
std::vector<std::vector<std::uint32_t>> captures() {
  std::vector<std::vector<std::uint32_t>> out;
  for (const auto& f : frames(tf::data_id::read_all)) {
    std::vector<std::uint32_t> words(5, 0xFFFFFFFFU);
    (void)tf::encode_line(mb::byte_view(f.data(), f.size()),
                          mb::span<std::uint32_t>(words.data(), words.size()),
                          mb::bit_order::msb_first, 0, 7);
    out.push_back(words);
  }
  return out;
}

void bm_line(benchmark::State& state) {
  const auto input = captures();
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& w = input[i++ & 63U];
    auto r = tf::decode_response_line(mb::span<const std::uint32_t>(w.data(), w.size()));
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void bm_line_baseline(benchmark::State& state) {
  const auto input = captures();
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& w = input[i++ & 63U];
    auto r = naive_decode_line(w.data(), w.size() * 32U);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

// A byte stream of 64 ID3 responses, each preceded by the echo of its request.
std::vector<std::uint8_t> stream() {
  std::vector<std::uint8_t> s;
  for (const auto& f : frames(tf::data_id::read_all)) {
    s.push_back(0x1A);
    s.insert(s.end(), f.begin(), f.end());
  }
  return s;
}

void bm_receiver(benchmark::State& state) {
  const auto s = stream();
  tf::receiver_options opt;
  opt.check_against_request = false;
  for (auto _ : state) {
    tf::receiver rx(opt);
    std::size_t frames_seen = 0;
    // byte by byte, as a UART interrupt would deliver them
    for (std::size_t i = 0; i < s.size(); ++i) {
      frames_seen += rx.put(s[i]) && rx.result().is_complete() ? 1U : 0U;
    }
    benchmark::DoNotOptimize(frames_seen);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 64);
}

void bm_receiver_baseline(benchmark::State& state) {
  const auto s = stream();
  for (auto _ : state) {
    std::uint8_t buffer[11] = {};
    std::size_t size = 0;
    std::size_t frames_seen = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      buffer[size++] = s[i];
      // spec-literal: try a frame at the buffer start, else drop a byte
      for (;;) {
        if (size == 0) {
          break;
        }
        const unsigned id = (buffer[0] >> 3U) & 0xFU;
        const std::size_t need = id == 3 ? 11 : (id == 2 ? 4 : 6);
        if ((buffer[0] & 7U) != 2U || (size >= need && !naive_decode(buffer, size).ok)) {
          for (std::size_t k = 1; k < size; ++k) {
            buffer[k - 1] = buffer[k];
          }
          --size;
          continue;
        }
        if (size == need) {
          ++frames_seen;
          size = 0;
        }
        break;
      }
    }
    benchmark::DoNotOptimize(frames_seen);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 64);
}

}  // namespace

BENCHMARK_TEMPLATE(bm_decode_baseline, tf::data_id::read_all)->Name("tformat_id3_decode/baseline");
BENCHMARK_TEMPLATE(bm_decode, tf::data_id::read_all)->Name("tformat_id3_decode/motionbus");
BENCHMARK_TEMPLATE(bm_decode_baseline, tf::data_id::read_abs)->Name("tformat_id0_decode/baseline");
BENCHMARK_TEMPLATE(bm_decode, tf::data_id::read_abs)->Name("tformat_id0_decode/motionbus");
BENCHMARK(bm_line_baseline)->Name("tformat_id3_bitstream_decode/baseline");
BENCHMARK(bm_line)->Name("tformat_id3_bitstream_decode/motionbus");
BENCHMARK(bm_receiver_baseline)->Name("tformat_receiver_64_frames_with_echo/baseline");
BENCHMARK(bm_receiver)->Name("tformat_receiver_64_frames_with_echo/motionbus");
