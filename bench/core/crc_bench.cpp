// CRC throughput: every named CRC at every table size over a 256-byte buffer, and the BiSS
// CRC6 over a 34-bit sensor word. Baseline in the same run: the bitwise form (no table).
#include <motionbus/core/crc.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

namespace mb = motionbus;

namespace {

std::vector<std::uint8_t> make_buffer(std::size_t n) {
  std::vector<std::uint8_t> data(n);
  std::uint32_t x = 0x12345678U;
  for (auto& b : data) {
    x = x * 1664525U + 1013904223U;
    b = static_cast<std::uint8_t>(x >> 24U);
  }
  return data;
}

template <class Crc>
void bm_bytes(benchmark::State& state) {
  const auto data = make_buffer(static_cast<std::size_t>(state.range(0)));
  const mb::byte_view view(data.data(), data.size());
  for (auto _ : state) {
    benchmark::DoNotOptimize(data.data());
    auto v = Crc::compute(view);
    benchmark::DoNotOptimize(v);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
}

template <mb::crc_table_size Table>
void bm_biss_word(benchmark::State& state) {
  std::uint64_t word = (std::uint64_t{0x89ABCDEFU} << 2U) | 3U;
  for (auto _ : state) {
    benchmark::DoNotOptimize(word);
    auto v = mb::crc6_biss<Table>::compute_bits(word, 34);
    benchmark::DoNotOptimize(v);
    ++word;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

constexpr auto byte_t = mb::crc_table_size::byte;
constexpr auto nibble_t = mb::crc_table_size::nibble;
constexpr auto bitwise_t = mb::crc_table_size::bitwise;

}  // namespace

BENCHMARK_TEMPLATE(bm_bytes, mb::crc16_modbus<bitwise_t>)->Name("crc16_modbus/bitwise")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc16_modbus<nibble_t>)->Name("crc16_modbus/nibble")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc16_modbus<byte_t>)->Name("crc16_modbus/byte")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc16_modbus<mb::crc_table_size::slice4>)
    ->Name("crc16_modbus/slice4")
    ->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc16_modbus<mb::crc_table_size::slice8>)
    ->Name("crc16_modbus/slice8")
    ->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc8_tformat<bitwise_t>)->Name("crc8_tformat/bitwise")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc8_tformat<nibble_t>)->Name("crc8_tformat/nibble")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc8_tformat<byte_t>)->Name("crc8_tformat/byte")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc6_biss<bitwise_t>)->Name("crc6_biss/bitwise")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc6_biss<nibble_t>)->Name("crc6_biss/nibble")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc6_biss<byte_t>)->Name("crc6_biss/byte")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc4_biss<bitwise_t>)->Name("crc4_biss/bitwise")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc4_biss<nibble_t>)->Name("crc4_biss/nibble")->Arg(256);
BENCHMARK_TEMPLATE(bm_bytes, mb::crc4_biss<byte_t>)->Name("crc4_biss/byte")->Arg(256);
BENCHMARK_TEMPLATE(bm_biss_word, bitwise_t)->Name("crc6_biss_34bit_word/bitwise");
BENCHMARK_TEMPLATE(bm_biss_word, nibble_t)->Name("crc6_biss_34bit_word/nibble");
BENCHMARK_TEMPLATE(bm_biss_word, byte_t)->Name("crc6_biss_34bit_word/byte");
