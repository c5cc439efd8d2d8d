// The gateway core (modbus/gateway.hpp) alone in its translation unit (alone_main.cpp says
// why): one connection and one queued request, each step of a transaction a call of its own
// (meter.py, measure_gateway()). The step's bytes as put_bytes() in ops.cpp gives them (size,
// address), its action in meter_out[2], the bytes of the input it took in meter_out[3].

#include <motionbus/modbus/gateway.hpp>

#include <cstdint>

namespace mb = motionbus;
namespace md = motionbus::modbus;

#define METER_OP extern "C" __attribute__((used, noinline))

extern "C" {
extern std::uint32_t meter_out[64];
__attribute__((used, aligned(8))) std::uint8_t meter_gateway_in[300];
__attribute__((used)) std::uint32_t meter_gateway_in_size;
}

namespace {
md::basic_gateway<1, 1> gateway;

mb::byte_view input() {
  return mb::byte_view(meter_gateway_in, meter_gateway_in_size);
}

void put_step(const md::gateway_step& s) {
  meter_out[0] = static_cast<std::uint32_t>(s.bytes.size());
  meter_out[1] = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(s.bytes.data()));
  meter_out[2] = static_cast<std::uint32_t>(s.action);
  meter_out[3] = static_cast<std::uint32_t>(s.consumed);
}
}  // namespace

METER_OP void op_alone_gateway_from_client() {
  put_step(gateway.from_client(0, input()));
}
METER_OP void op_alone_gateway_poll(std::uint32_t now_us) {
  put_step(gateway.poll(now_us));
}
METER_OP void op_alone_gateway_from_line(std::uint32_t now_us) {
  put_step(gateway.from_line(input(), now_us));
}
