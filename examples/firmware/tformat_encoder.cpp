// motionbus firmware example — a Tamagawa TS5700N8500 T-format encoder on a UART: the encoder
// emulator (devices/ts5700n8500_emulator.hpp) answering each request. A request ends when the
// encoder-side decoder has all its fields (the length follows from the CF), or when the line
// is silent: a request cut short is answered then (ID3 data, as the specification's Table 6
// says), a wrong sync code never.
//
// The silence: 1 ms or less on a real line at 2.5 Mbps; 500 ms under emulation, where the gaps
// between bytes come from the host's scheduling (MOTIONBUS_SILENCE_US): QEMU hands the UART a
// request's bytes one main-loop turn apart, measured up to 266 ms apart on a loaded host.
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "motionbus/devices/ts5700n8500_emulator.hpp"
#include "motionbus/tformat/codec.hpp"

#ifndef MOTIONBUS_SILENCE_US
#define MOTIONBUS_SILENCE_US 500000  // not 50 ms: a loaded host split requests (issue 27)
#endif

namespace mb = motionbus;
namespace tf = motionbus::tformat;
namespace ts = motionbus::devices::ts5700n8500;

namespace {

constexpr std::uint32_t silence_us = MOTIONBUS_SILENCE_US;

ts::emulator encoder;
std::uint8_t request[tf::max_request_size];
std::size_t held = 0;

void answer(std::uint32_t now) {
  const ts::reply r = encoder.respond(mb::byte_view(request, held), now);
  held = 0;
  board::uart_write(r.bytes, r.size);  // size 0: silence (a wrong sync code)
}

}  // namespace

int main() {
  board::init();
  // A fixed shaft: single-turn 123456 of 2^17, turn 77, so that the host knows every field.
  encoder.set_position(123456, 77);
  std::uint32_t last_byte = board::now_us();
  for (;;) {
    const std::uint32_t now = board::now_us();
    std::uint8_t byte = 0;
    if (board::uart_read(byte)) {
      last_byte = now;
      request[held++] = byte;
      const auto q = tf::decode_request(mb::byte_view(request, held));
      if (!q.is_incomplete() || held == tf::max_request_size) {
        answer(now);
      }
    } else if (held > 0U && now - last_byte >= silence_us) {
      answer(now);
    }
  }
}
