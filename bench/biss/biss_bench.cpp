// BiSS-C sensor data decode from raw captures, against a naive decoder in the same run: the
// start found one sample at a time, every field assembled bit by bit, the CRC6 computed bit by
// bit (shift register of x^6 + x + 1).
#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "motionbus/biss.hpp"

namespace mb = motionbus;
namespace bs = motionbus::biss;

namespace {

// --- the naive baseline ----------------------------------------------------------------------
struct naive_slave {
  std::uint64_t data = 0;
  bool ne = false, nw = false, ok = false;
};

inline unsigned sample(const std::uint32_t* w, std::size_t i) {
  return (w[i / 32U] >> (31U - i % 32U)) & 1U;
}

// One slave of `data_bits` + nE + nW + CRC6 0x43 (inverted) from position `pos`.
naive_slave naive_slave_at(const std::uint32_t* w, std::size_t& pos, unsigned data_bits) {
  naive_slave s;
  unsigned reg = 0;
  for (unsigned k = 0; k < data_bits + 2U; ++k) {
    const unsigned b = sample(w, pos++);
    if (k < data_bits) {
      s.data = (s.data << 1U) | b;
    } else if (k == data_bits) {
      s.ne = b != 0U;
    } else {
      s.nw = b != 0U;
    }
    const unsigned fb = ((reg >> 5U) & 1U) ^ b;
    reg = (reg << 1U) & 0x3FU;
    if (fb != 0U) {
      reg ^= 0x03U;
    }
  }
  unsigned crc = 0;
  for (unsigned k = 0; k < 6U; ++k) {
    crc = (crc << 1U) | sample(w, pos++);
  }
  s.ok = crc == (reg ^ 0x3FU);
  return s;
}

bool naive_decode(const std::uint32_t* w, std::size_t bits, naive_slave* out, std::size_t n) {
  std::size_t pos = 0;
  while (pos < bits && sample(w, pos) == 1U) {  // idle
    ++pos;
  }
  while (pos < bits && sample(w, pos) == 0U) {  // Ack
    ++pos;
  }
  if (pos + 2U + n * 40U > bits) {
    return false;
  }
  pos += 2U;  // Start, CDS
  bool ok = true;
  for (std::size_t k = 0; k < n; ++k) {
    out[k] = naive_slave_at(w, pos, 32);
    ok = ok && out[k].ok;
  }
  return ok;
}

// --- inputs ------------------------------------------------------------------------------------

// 64 captures of `slaves` ABSYS frames, each with 1..8 idle samples and a 1..4-sample Ack,
// in 32-bit MSB-first words (two words for one slave: a 64-bit capture), one after the other
// in one buffer: capture i starts at word i * words.
std::vector<std::uint32_t> captures(std::size_t slaves, std::size_t words) {
  std::vector<std::uint32_t> out;
  std::vector<bs::slave_layout> chain(slaves, bs::absys_layout);
  for (unsigned i = 0; i < 64U; ++i) {
    std::vector<std::uint32_t> w(words, 0);
    std::vector<bs::slave_values> v(slaves);
    for (std::size_t k = 0; k < slaves; ++k) {
      v[k].single_turn = (0x9E3779B9U * (i + 1U) + static_cast<std::uint32_t>(k)) & 0xFFFFFFFFU;
      v[k].ne = (i % 7U) != 0U;
    }
    bs::line_options line;
    line.line_delay = 1U + i % 8U;
    line.ack_bits = 1U + i % 4U;
    line.cds = (i & 1U) != 0U;
    (void)bs::encode_frame(mb::span<const bs::slave_layout>(chain.data(), chain.size()),
                           mb::span<const bs::slave_values>(v.data(), v.size()),
                           mb::span<std::uint32_t>(w.data(), w.size()), line);
    out.insert(out.end(), w.begin(), w.end());
  }
  return out;
}

// What a drive takes from each frame, made observable the same way for both decoders: valid
// or not, the position, nE, nW.
inline void publish(bool ok, std::uint64_t position, bool ne, bool nw) {
  benchmark::DoNotOptimize(ok);
  benchmark::DoNotOptimize(position);
  benchmark::DoNotOptimize(ne);
  benchmark::DoNotOptimize(nw);
}

template <mb::crc_table_size Table>
void bm_absys(benchmark::State& state) {
  const auto input = captures(1, 2);
  std::size_t i = 0;
  for (auto _ : state) {
    const std::uint32_t* w = input.data() + (i++ & 63U) * 2U;
    const auto r =
        bs::decode_frame<Table>(mb::span<const std::uint32_t>(w, 2), 64, bs::absys_layout);
    const bs::slave_data& d = r->slaves[0];
    publish(r.is_complete(), d.single_turn, d.ne, d.nw);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void bm_absys_baseline(benchmark::State& state) {
  const auto input = captures(1, 2);
  std::size_t i = 0;
  naive_slave d;
  for (auto _ : state) {
    const std::uint32_t* w = input.data() + (i++ & 63U) * 2U;
    const bool ok = naive_decode(w, 64, &d, 1);
    publish(ok, d.data, d.ne, d.nw);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void bm_chain(benchmark::State& state) {
  const auto input = captures(3, 5);
  const bs::slave_layout chain[3] = {bs::absys_layout, bs::absys_layout, bs::absys_layout};
  std::size_t i = 0;
  for (auto _ : state) {
    const std::uint32_t* w = input.data() + (i++ & 63U) * 5U;
    const auto r = bs::decode_frame(mb::span<const std::uint32_t>(w, 5), 160, chain);
    for (const auto& s : r.value()) {
      publish(r.is_complete(), s.single_turn, s.ne, s.nw);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void bm_chain_baseline(benchmark::State& state) {
  const auto input = captures(3, 5);
  naive_slave d[3];
  std::size_t i = 0;
  for (auto _ : state) {
    const std::uint32_t* w = input.data() + (i++ & 63U) * 5U;
    const bool ok = naive_decode(w, 160, d, 3);
    for (const auto& s : d) {
      publish(ok, s.data, s.ne, s.nw);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

}  // namespace

BENCHMARK(bm_absys_baseline)->Name("biss_absys_64bit_capture_decode/baseline");
BENCHMARK_TEMPLATE(bm_absys, mb::crc_table_size::slice8)
    ->Name("biss_absys_64bit_capture_decode/motionbus_crc_slice8");
BENCHMARK_TEMPLATE(bm_absys, mb::crc_table_size::byte)
    ->Name("biss_absys_64bit_capture_decode/motionbus_crc256");
BENCHMARK_TEMPLATE(bm_absys, mb::crc_table_size::nibble)
    ->Name("biss_absys_64bit_capture_decode/motionbus_crc16");
BENCHMARK_TEMPLATE(bm_absys, mb::crc_table_size::bitwise)
    ->Name("biss_absys_64bit_capture_decode/motionbus_crc_bitwise");
BENCHMARK(bm_chain_baseline)->Name("biss_chain3_decode/baseline");
BENCHMARK(bm_chain)->Name("biss_chain3_decode/motionbus");
