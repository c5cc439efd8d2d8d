// The shape of T-format in servo-drive firmware: every control cycle, send ID0 and decode the
// answer in the UART receive interrupt. No heap, no exceptions; the "UART" here is the
// encoder model, so the loop runs on a host too.
#include <motionbus/devices/ts5700n8500_emulator.hpp>
#include <motionbus/tformat.hpp>

#include <cstdint>
#include <cstdio>

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

// --- what the firmware provides ---------------------------------------------------------------
motionbus::devices::ts5700n8500::emulator simulated_encoder;  // stands in for the RS-485 line
std::uint8_t rx_fifo[16];
std::size_t rx_fifo_size = 0;

void uart_send(const std::uint8_t* data, std::size_t size, std::uint32_t now_us) {
  const motionbus::devices::ts5700n8500::reply r =
      simulated_encoder.respond(mb::byte_view(data, size), now_us);
  for (std::size_t i = 0; i < r.size; ++i) {
    rx_fifo[rx_fifo_size++] = r.bytes[i];
  }
}

}  // namespace

int main() {
  tf::receiver rx;  // lives as long as the firmware
  std::uint8_t request[1] = {};
  (void)tf::encode_request(tf::data_id::read_abs, request);  // built once: 0x02
  std::uint32_t position = 0;
  int good = 0;
  for (std::uint32_t cycle = 0; cycle < 8; ++cycle) {
    const std::uint32_t now_us = cycle * 62;  // a 16 kHz control loop
    simulated_encoder.rotate(1000);
    uart_send(request, sizeof request, now_us);
    rx.sent(request);
    // receive interrupt: bytes arrive one by one
    for (std::size_t i = 0; i < rx_fifo_size; ++i) {
      if (rx.put(rx_fifo[i]) && rx.result().is_complete()) {
        position = rx.result()->abs;
        ++good;
      }
    }
    rx_fifo_size = 0;
    std::printf("cycle %u: position %u\n", static_cast<unsigned>(cycle),
                static_cast<unsigned>(position));
  }
  return good == 8 ? 0 : 1;
}
