// motionbus against libmodbus on the same host, same inputs, same run, both with 512 bytes of
// CRC table (motionbus's default 256 x 16-bit table; libmodbus's two 256 x 8-bit tables):
// - a server's answer to FC03 (read holding registers) and FC10 (write multiple registers) at
//   2 and 123 registers, from a request whose CRC has been checked (motionbus: the framer's
//   frame; libmodbus: the request modbus_receive() returned) to the response ADU with its CRC,
//   the registers read from or written into the device's memory;
// - the CRC-16: libmodbus's own is internal (static in modbus-rtu.c), reached only through its
//   send path, so the peers are compared on the work that path does, building an RTU ADU
//   from an address, a function code and the rest of the PDU (a copy and the CRC over 8 and
//   254 bytes, libmodbus's longest raw request); and the CRC alone over 8 and 255 bytes
//   against the two-table loop the Modbus serial-line specification gives (Modbus over Serial
//   Line V1.02 §6.2.2; libmodbus's crc16() is that loop), written here and so compiled with
//   this program's flags.
//
// The program is built twice, at -O2 and at -O3 (bench/CMakeLists.txt); the level is in every
// benchmark's name. libmodbus is Debian 12's shared library (its own build flags) in both.
//
// libmodbus sends its response from inside modbus_reply() (write() on the context's file
// descriptor). To time the reply path and not a system call, this program defines write():
// for the one descriptor handed to libmodbus (a descriptor no file uses) it takes the bytes
// and returns; every other descriptor goes to the system call. motionbus writes its response
// to a buffer and stops there.
#include <modbus.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <benchmark/benchmark.h>
#include <motionbus/modbus.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#ifndef MOTIONBUS_BENCH_OPT
#define MOTIONBUS_BENCH_OPT "O3"
#endif

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

constexpr int sink_fd = 1000;  // no file: the descriptor libmodbus writes its responses to
std::uint8_t sink[MODBUS_RTU_MAX_ADU_LENGTH];
std::size_t sink_size = 0;

std::string name(const char* what, const char* peer) {
  return std::string(what) + "/" + peer + "/" MOTIONBUS_BENCH_OPT;
}

std::vector<std::uint8_t> make_bytes(std::size_t n) {
  std::vector<std::uint8_t> data(n);
  std::uint32_t x = 0x12345678U;
  for (auto& b : data) {
    x = x * 1664525U + 1013904223U;
    b = static_cast<std::uint8_t>(x >> 24U);
  }
  return data;
}

std::vector<std::uint8_t> rtu_request(mb::byte_view pdu) {
  std::uint8_t adu[mo::max_rtu_size] = {};
  const std::size_t m = mo::encode_rtu(1, pdu, adu).value();
  return {adu, adu + m};
}

// The request ADU of FC10 writing `n` registers from address 16 to slave 1.
std::vector<std::uint8_t> fc10_request(std::uint16_t n) {
  std::vector<std::uint16_t> values(n);
  for (std::uint16_t i = 0; i < n; ++i) {
    values[i] = static_cast<std::uint16_t>(i * 257U + 3U);
  }
  std::uint8_t pdu[mo::max_pdu_size] = {};
  const std::size_t k =
      mo::encode_write_multiple_registers(16, mb::span<const std::uint16_t>(values.data(), n), pdu)
          .value();
  return rtu_request(mb::byte_view(pdu, k));
}

// The request ADU of FC03 reading `n` registers from address 16 of slave 1.
std::vector<std::uint8_t> fc03_request(std::uint16_t n) {
  std::uint8_t pdu[mo::max_pdu_size] = {};
  const std::size_t k = mo::encode_read(0x03, 16, n, pdu).value();
  return rtu_request(mb::byte_view(pdu, k));
}

constexpr std::uint16_t register_value(std::size_t i) {
  return static_cast<std::uint16_t>(i * 0x0101U + 0x1234U);
}

// The device behind motionbus's server: 200 holding registers in host order, as libmodbus's
// mapping holds them; read as registers (the server writes their big-endian bytes), written
// from the request's big-endian bytes.
struct holding_registers {
  std::uint16_t regs[200] = {};
  holding_registers() {
    for (std::size_t i = 0; i < 200; ++i) {
      regs[i] = register_value(i);
    }
  }
  std::uint8_t read_registers(std::uint8_t /*function*/, std::uint16_t address,
                              mb::span<std::uint16_t> out) {
    if (address + out.size() > 200U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = regs[address + i];
    }
    return 0;
  }
  std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity,
                                  mb::byte_view data) {
    if (address + quantity > 200U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      regs[address + i] = mo::register_at(data, i);
    }
    return 0;
  }
};

// The response both peers must give to a read of `n` registers from address 16.
bool fc03_response_ok(mb::byte_view adu, std::size_t n) {
  const auto frame = mo::decode_rtu(adu);
  if (!frame || frame.value().slave != 1 || frame.value().pdu.size() != 2 + 2 * n ||
      frame.value().pdu[0] != 0x03 || frame.value().pdu[1] != 2 * n) {
    return false;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (mo::register_at(frame.value().pdu.subspan(2), i) != register_value(16 + i)) {
      return false;
    }
  }
  return true;
}

void serve_motionbus(benchmark::State& state, std::vector<std::uint8_t> request, bool read) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const mo::rtu_frame frame = mo::decode_rtu(mb::byte_view(request.data(), request.size())).value();
  holding_registers device;
  std::uint8_t out[mo::max_rtu_size];
  for (auto _ : state) {
    const auto size = mo::serve_frame(device, 1, frame, out);
    benchmark::DoNotOptimize(size);
    benchmark::DoNotOptimize(out);
    benchmark::ClobberMemory();
  }
  const auto size = mo::serve_frame(device, 1, frame, out);
  const bool ok = read ? size && fc03_response_ok(mb::byte_view(out, size.value()), n)
                       : size && size.value() == 8U && device.regs[17] == 260U;
  if (!ok) {
    state.SkipWithError("wrong response");
  }
}

void serve_libmodbus(benchmark::State& state, const std::vector<std::uint8_t>& request, bool read) {
  const auto n = static_cast<std::size_t>(state.range(0));
  modbus_t* ctx = modbus_new_rtu("/dev/null", 9600, 'E', 8, 1);
  modbus_mapping_t* map = modbus_mapping_new(0, 0, 200, 0);
  if (ctx == nullptr || map == nullptr || modbus_set_slave(ctx, 1) != 0 ||
      modbus_set_socket(ctx, sink_fd) != 0) {
    state.SkipWithError("libmodbus context");
    return;
  }
  for (std::size_t i = 0; i < 200; ++i) {
    map->tab_registers[i] = register_value(i);
  }
  for (auto _ : state) {
    const int r = modbus_reply(ctx, request.data(), static_cast<int>(request.size()), map);
    benchmark::DoNotOptimize(r);
    benchmark::ClobberMemory();
  }
  const bool ok = read ? fc03_response_ok(mb::byte_view(sink, sink_size), n)
                       : sink_size == 8U && map->tab_registers[17] == 260U;
  if (!ok) {
    state.SkipWithError("wrong response");
  }
  modbus_set_socket(ctx, -1);
  modbus_mapping_free(map);
  modbus_free(ctx);
}

void fc10_motionbus(benchmark::State& state) {
  serve_motionbus(state, fc10_request(static_cast<std::uint16_t>(state.range(0))), false);
}
void fc10_libmodbus(benchmark::State& state) {
  serve_libmodbus(state, fc10_request(static_cast<std::uint16_t>(state.range(0))), false);
}
void fc03_motionbus(benchmark::State& state) {
  serve_motionbus(state, fc03_request(static_cast<std::uint16_t>(state.range(0))), true);
}
void fc03_libmodbus(benchmark::State& state) {
  serve_libmodbus(state, fc03_request(static_cast<std::uint16_t>(state.range(0))), true);
}

// An RTU ADU built from `n` raw bytes (address, function code, the rest of the PDU): libmodbus's
// modbus_send_raw_request() against motionbus's encode_rtu(); the CRC runs over `n` bytes.
void adu_libmodbus(benchmark::State& state) {
  const auto raw = make_bytes(static_cast<std::size_t>(state.range(0)));
  modbus_t* ctx = modbus_new_rtu("/dev/null", 9600, 'E', 8, 1);
  if (ctx == nullptr || modbus_set_socket(ctx, sink_fd) != 0) {
    state.SkipWithError("libmodbus context");
    return;
  }
  for (auto _ : state) {
    const int r = modbus_send_raw_request(ctx, raw.data(), static_cast<int>(raw.size()));
    benchmark::DoNotOptimize(r);
    benchmark::ClobberMemory();
  }
  const bool ok = sink_size == raw.size() + 2U &&
                  mb::load_le16(mb::byte_view(sink, sink_size), raw.size()) ==
                      mb::crc16_modbus<>::compute(mb::byte_view(raw.data(), raw.size()));
  if (!ok) {
    state.SkipWithError("wrong ADU");
  }
  modbus_set_socket(ctx, -1);
  modbus_free(ctx);
}

void adu_motionbus(benchmark::State& state) {
  const auto raw = make_bytes(static_cast<std::size_t>(state.range(0)));
  const mb::byte_view pdu(raw.data() + 1, raw.size() - 1U);
  std::uint8_t out[mo::max_rtu_size];
  for (auto _ : state) {
    benchmark::DoNotOptimize(raw.data());
    const auto n = mo::encode_rtu(raw[0] % 248U, pdu, out);
    benchmark::DoNotOptimize(n);
    benchmark::DoNotOptimize(out);
    benchmark::ClobberMemory();
  }
  const auto n = mo::encode_rtu(raw[0] % 248U, pdu, out);
  if (!n || n.value() != raw.size() + 2U ||
      mb::load_le16(mb::byte_view(out, n.value()), raw.size()) !=
          mb::crc16_modbus<>::compute(mb::byte_view(raw.data(), raw.size())) ||
      raw[0] >= 248U) {
    state.SkipWithError("wrong ADU");
  }
}

// The two-table CRC of the Modbus serial-line specification (§6.2.2): one table holds the high
// byte, the other the low byte of the CRC-16 (reflected 0xA001) of each index, and each step
// looks both up at (low byte of the CRC) XOR (the data byte). Tables computed here from the
// polynomial.
struct two_tables {
  std::array<std::uint8_t, 256> hi{};
  std::array<std::uint8_t, 256> lo{};
};

constexpr two_tables make_two_tables() {
  two_tables t;
  for (unsigned i = 0; i < 256U; ++i) {
    unsigned c = i;
    for (int k = 0; k < 8; ++k) {
      c = (c & 1U) != 0U ? (c >> 1U) ^ 0xA001U : c >> 1U;
    }
    // The spec's loop keeps the CRC as two bytes, "hi" the one sent first (the register's
    // low byte): the next hi is the table entry's low byte XOR the old lo, the next lo the
    // entry's high byte.
    t.hi[i] = static_cast<std::uint8_t>(c & 0xFFU);
    t.lo[i] = static_cast<std::uint8_t>(c >> 8U);
  }
  return t;
}

constexpr two_tables spec_tables = make_two_tables();

std::uint16_t crc16_two_tables(const std::uint8_t* data, std::size_t n) {
  std::uint8_t first = 0xFF;   // sent first: the register's low byte
  std::uint8_t second = 0xFF;  // the register's high byte
  while (n-- != 0U) {
    const unsigned i = first ^ *data++;
    first = static_cast<std::uint8_t>(second ^ spec_tables.hi[i]);
    second = spec_tables.lo[i];
  }
  return static_cast<std::uint16_t>(second << 8U | first);
}

void crc_two_tables(benchmark::State& state) {
  const auto data = make_bytes(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    benchmark::DoNotOptimize(data.data());
    auto v = crc16_two_tables(data.data(), data.size());
    benchmark::DoNotOptimize(v);
  }
  if (crc16_two_tables(data.data(), data.size()) !=
      mb::crc16_modbus<mb::crc_table_size::bitwise>::compute(
          mb::byte_view(data.data(), data.size()))) {
    state.SkipWithError("wrong CRC");
  }
}

void crc_motionbus(benchmark::State& state) {
  const auto data = make_bytes(static_cast<std::size_t>(state.range(0)));
  const mb::byte_view view(data.data(), data.size());
  for (auto _ : state) {
    benchmark::DoNotOptimize(data.data());
    auto v = mb::crc16_modbus<mb::crc_table_size::byte>::compute(view);
    benchmark::DoNotOptimize(v);
  }
  if (mb::crc16_modbus<mb::crc_table_size::byte>::compute(view) !=
      mb::crc16_modbus<mb::crc_table_size::bitwise>::compute(view)) {
    state.SkipWithError("wrong CRC");
  }
}

// Registered at start-up: the names carry the optimisation level this copy was built at.
const bool registered = [] {
  benchmark::RegisterBenchmark(name("modbus_crc16", "spec_two_tables").c_str(), crc_two_tables)
      ->Arg(8)
      ->Arg(255);
  benchmark::RegisterBenchmark(name("modbus_crc16", "motionbus").c_str(), crc_motionbus)
      ->Arg(8)
      ->Arg(255);
  benchmark::RegisterBenchmark(name("modbus_rtu_adu", "libmodbus").c_str(), adu_libmodbus)
      ->Arg(8)
      ->Arg(254);
  benchmark::RegisterBenchmark(name("modbus_rtu_adu", "motionbus").c_str(), adu_motionbus)
      ->Arg(8)
      ->Arg(254);
  benchmark::RegisterBenchmark(name("modbus_serve_fc03", "libmodbus").c_str(), fc03_libmodbus)
      ->Arg(2)
      ->Arg(123);
  benchmark::RegisterBenchmark(name("modbus_serve_fc03", "motionbus").c_str(), fc03_motionbus)
      ->Arg(2)
      ->Arg(123);
  benchmark::RegisterBenchmark(name("modbus_serve_fc10", "libmodbus").c_str(), fc10_libmodbus)
      ->Arg(2)
      ->Arg(123);
  benchmark::RegisterBenchmark(name("modbus_serve_fc10", "motionbus").c_str(), fc10_motionbus)
      ->Arg(2)
      ->Arg(123);
  return true;
}();

}  // namespace

// libmodbus's send path ends here for the sink descriptor (see the top of the file).
extern "C" ssize_t write(int fd, const void* data, size_t size) {
  if (fd == sink_fd) {
    sink_size = size < sizeof sink ? size : sizeof sink;
    std::memcpy(sink, data, sink_size);
    return static_cast<ssize_t>(size);
  }
  return static_cast<ssize_t>(syscall(SYS_write, fd, data, size));
}
