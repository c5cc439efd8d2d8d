// A Modbus server's answer to FC10 (write multiple registers) against libmodbus's, on the same
// host, same requests, same run: from a request whose CRC has been checked (motionbus: the
// framer's frame; libmodbus: the request modbus_receive() returned) to the response ADU with
// its CRC, registers written into the device's memory.
//
// libmodbus sends its response from inside modbus_reply() (write() on the context's file
// descriptor). To time the reply path and not a system call, this program defines write():
// for the one descriptor handed to libmodbus (a descriptor no file uses) it takes the bytes
// and returns; every other descriptor goes to the system call. motionbus writes its response
// to a buffer and stops there. Both use a 256-entry CRC table (libmodbus's own tables).
#include <modbus.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <benchmark/benchmark.h>
#include <motionbus/modbus.hpp>

#include <cstdint>
#include <cstring>
#include <vector>

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

constexpr int sink_fd = 1000;  // no file: the descriptor libmodbus writes its responses to
std::uint8_t sink[MODBUS_RTU_MAX_ADU_LENGTH];
std::size_t sink_size = 0;

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
  std::uint8_t adu[mo::max_rtu_size] = {};
  const std::size_t m = mo::encode_rtu(1, mb::byte_view(pdu, k), adu).value();
  return {adu, adu + m};
}

// The device behind motionbus's server: 200 holding registers, written from the request's
// big-endian bytes.
struct holding_registers {
  std::uint16_t regs[200] = {};
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

void fc10_motionbus(benchmark::State& state) {
  const auto request = fc10_request(static_cast<std::uint16_t>(state.range(0)));
  const mo::rtu_frame frame = mo::decode_rtu(mb::byte_view(request.data(), request.size())).value();
  holding_registers device;
  std::uint8_t out[mo::max_rtu_size];
  for (auto _ : state) {
    const auto n = mo::serve_frame(device, 1, frame, out);
    benchmark::DoNotOptimize(n);
    benchmark::DoNotOptimize(out);
    benchmark::ClobberMemory();
  }
  if (mo::serve_frame(device, 1, frame, out).value() != 8U || device.regs[17] != 260U) {
    state.SkipWithError("wrong response");
  }
}

void fc10_libmodbus(benchmark::State& state) {
  const auto request = fc10_request(static_cast<std::uint16_t>(state.range(0)));
  modbus_t* ctx = modbus_new_rtu("/dev/null", 9600, 'E', 8, 1);
  modbus_mapping_t* map = modbus_mapping_new(0, 0, 200, 0);
  if (ctx == nullptr || map == nullptr || modbus_set_slave(ctx, 1) != 0 ||
      modbus_set_socket(ctx, sink_fd) != 0) {
    state.SkipWithError("libmodbus context");
    return;
  }
  for (auto _ : state) {
    const int n = modbus_reply(ctx, request.data(), static_cast<int>(request.size()), map);
    benchmark::DoNotOptimize(n);
    benchmark::ClobberMemory();
  }
  if (sink_size != 8U || map->tab_registers[17] != 260U) {
    state.SkipWithError("wrong response");
  }
  modbus_set_socket(ctx, -1);
  modbus_mapping_free(map);
  modbus_free(ctx);
}

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

BENCHMARK(fc10_libmodbus)->Arg(2)->Arg(123)->Name("modbus_serve_fc10/libmodbus");
BENCHMARK(fc10_motionbus)->Arg(2)->Arg(123)->Name("modbus_serve_fc10/motionbus");
