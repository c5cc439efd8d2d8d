// Modbus speed against a baseline in the same run: the baseline computes CRC-16 bit by bit as
// Modbus over Serial Line §6.2.2 describes it (shift, XOR 0xA001) and reads fields byte by byte.
#include <motionbus/modbus.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

std::uint16_t naive_crc16(const std::uint8_t* p, std::size_t n) {
  std::uint16_t crc = 0xFFFF;
  for (std::size_t i = 0; i < n; ++i) {
    crc = static_cast<std::uint16_t>(crc ^ p[i]);
    for (int b = 0; b < 8; ++b) {
      crc = (crc & 1U) != 0U ? static_cast<std::uint16_t>((crc >> 1U) ^ 0xA001U)
                             : static_cast<std::uint16_t>(crc >> 1U);
    }
  }
  return crc;
}

// A 125-register FC03 response ADU from slave 1, and its request.
std::vector<std::uint8_t> fc03_response() {
  std::uint16_t regs[125];
  for (std::uint16_t i = 0; i < 125; ++i) {
    regs[i] = static_cast<std::uint16_t>(i * 517U);
  }
  std::uint8_t pdu[253] = {};
  const std::size_t n = mo::encode_read_registers_response(0x03, regs, pdu).value();
  std::uint8_t adu[256] = {};
  const std::size_t k = mo::encode_rtu(1, mb::byte_view(pdu, n), adu).value();
  return {adu, adu + k};
}

const std::uint8_t fc03_request_pdu[] = {0x03, 0x00, 0x00, 0x00, 0x7D};

void bm_fc03_decode(benchmark::State& state) {
  const auto adu = fc03_response();
  for (auto _ : state) {
    benchmark::DoNotOptimize(adu.data());
    const auto f = mo::decode_rtu(mb::byte_view(adu.data(), adu.size()));
    const auto r = mo::decode_response_for(fc03_request_pdu, f->pdu);
    const mb::byte_view data = r->data;  // the result's accessor checks: once, not per register
    std::uint32_t sum = 0;
    for (std::size_t i = 0; i < 125; ++i) {
      sum += mo::register_at(data, i);
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

template <mb::crc_table_size Table>
void bm_fc03_decode_sliced(benchmark::State& state) {
  const auto adu = fc03_response();
  for (auto _ : state) {
    benchmark::DoNotOptimize(adu.data());
    const auto f = mo::decode_rtu<Table>(mb::byte_view(adu.data(), adu.size()));
    const auto r = mo::decode_response_for(fc03_request_pdu, f->pdu);
    const mb::byte_view data = r->data;  // the result's accessor checks: once, not per register
    std::uint32_t sum = 0;
    for (std::size_t i = 0; i < 125; ++i) {
      sum += mo::register_at(data, i);
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void bm_fc03_decode_baseline(benchmark::State& state) {
  const auto adu = fc03_response();
  for (auto _ : state) {
    benchmark::DoNotOptimize(adu.data());
    const std::size_t n = adu.size();
    std::uint32_t sum = 0;
    const std::uint16_t crc = static_cast<std::uint16_t>(adu[n - 2] | (adu[n - 1] << 8));
    if (naive_crc16(adu.data(), n - 2) == crc && adu[1] == 0x03 && adu[2] == 250) {
      for (std::size_t i = 0; i < 125; ++i) {
        sum += static_cast<std::uint32_t>((adu[3 + 2 * i] << 8) | adu[4 + 2 * i]);
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void bm_fc10_encode(benchmark::State& state) {
  std::uint16_t regs[123];
  for (std::uint16_t i = 0; i < 123; ++i) {
    regs[i] = static_cast<std::uint16_t>(i * 31U);
  }
  std::uint8_t pdu[253];
  std::uint8_t adu[256];
  for (auto _ : state) {
    benchmark::DoNotOptimize(regs);
    const std::size_t n = mo::encode_write_multiple_registers(0, regs, pdu).value();
    const std::size_t k = mo::encode_rtu(1, mb::byte_view(pdu, n), adu).value();
    benchmark::DoNotOptimize(k);
    benchmark::DoNotOptimize(adu);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void bm_fc10_encode_baseline(benchmark::State& state) {
  std::uint16_t regs[123];
  for (std::uint16_t i = 0; i < 123; ++i) {
    regs[i] = static_cast<std::uint16_t>(i * 31U);
  }
  std::uint8_t adu[256];
  for (auto _ : state) {
    benchmark::DoNotOptimize(regs);
    std::size_t k = 0;
    adu[k++] = 1;
    adu[k++] = 0x10;
    adu[k++] = 0;
    adu[k++] = 0;
    adu[k++] = 0;
    adu[k++] = 123;
    adu[k++] = 246;
    for (std::size_t i = 0; i < 123; ++i) {
      adu[k++] = static_cast<std::uint8_t>(regs[i] >> 8);
      adu[k++] = static_cast<std::uint8_t>(regs[i] & 0xFF);
    }
    const std::uint16_t crc = naive_crc16(adu, k);
    adu[k++] = static_cast<std::uint8_t>(crc & 0xFF);
    adu[k++] = static_cast<std::uint8_t>(crc >> 8);
    benchmark::DoNotOptimize(k);
    benchmark::DoNotOptimize(adu);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

// 64 request ADUs of mixed functions back to back (a busy RS-485 segment as a server sees it).
std::vector<std::uint8_t> request_stream() {
  std::vector<std::uint8_t> s;
  std::uint8_t pdu[253];
  std::uint8_t adu[256];
  const std::uint16_t regs[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  for (int i = 0; i < 64; ++i) {
    std::size_t n = 0;
    switch (i % 3) {
      case 0:
        n = mo::encode_read(mo::function_code::read_holding_registers, 0, 10, pdu).value();
        break;
      case 1: n = mo::encode_write_multiple_registers(0, regs, pdu).value(); break;
      default: n = mo::encode_write_single_register(5, 0x1234, pdu).value(); break;
    }
    const std::size_t k =
        mo::encode_rtu(static_cast<std::uint8_t>(1 + i % 2), mb::byte_view(pdu, n), adu).value();
    s.insert(s.end(), adu, adu + k);
  }
  return s;
}

void bm_framer(benchmark::State& state) {
  const auto s = request_stream();
  for (auto _ : state) {
    mo::rtu_framer rx(mo::framer_role::server, {1});
    std::size_t frames = 0;
    mb::byte_view in(s.data(), s.size());
    for (;;) {
      const auto r = rx.feed(in);
      if (r.is_incomplete()) {
        break;
      }
      in = in.subspan(r.consumed());
      frames += r.is_complete() ? 1U : 0U;
    }
    benchmark::DoNotOptimize(frames);
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}

// Baseline framer: same length rules, bitwise CRC, a byte at a time into a buffer.
void bm_framer_baseline(benchmark::State& state) {
  const auto s = request_stream();
  for (auto _ : state) {
    std::uint8_t buffer[256];
    std::size_t size = 0;
    std::size_t frames = 0;
    for (std::uint8_t byte : s) {
      buffer[size++] = byte;
      const std::size_t need = mo::predict_request_size(mb::byte_view(buffer, size));
      if (need == 0 || need == mo::unknown_length || size < need) {
        continue;
      }
      const std::uint16_t crc =
          static_cast<std::uint16_t>(buffer[need - 2] | (buffer[need - 1] << 8));
      if (naive_crc16(buffer, need - 2) == crc && buffer[0] == 1) {
        ++frames;
      }
      size = 0;
    }
    benchmark::DoNotOptimize(frames);
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}

}  // namespace

BENCHMARK(bm_fc03_decode_baseline)->Name("modbus_fc03_125_registers_decode/baseline");
BENCHMARK(bm_fc03_decode)->Name("modbus_fc03_125_registers_decode/motionbus");
BENCHMARK_TEMPLATE(bm_fc03_decode_sliced, mb::crc_table_size::slice4)
    ->Name("modbus_fc03_125_registers_decode/motionbus_slice4");
BENCHMARK_TEMPLATE(bm_fc03_decode_sliced, mb::crc_table_size::slice8)
    ->Name("modbus_fc03_125_registers_decode/motionbus_slice8");
BENCHMARK(bm_fc10_encode_baseline)->Name("modbus_fc10_123_registers_encode/baseline");
BENCHMARK(bm_fc10_encode)->Name("modbus_fc10_123_registers_encode/motionbus");
BENCHMARK(bm_framer_baseline)->Name("modbus_rtu_framer_64_requests/baseline");
BENCHMARK(bm_framer)->Name("modbus_rtu_framer_64_requests/motionbus");
