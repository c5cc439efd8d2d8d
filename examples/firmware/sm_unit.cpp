// motionbus firmware example — a Tsubaki SM unit on a UART: the SM unit emulator
// (devices/sm_unit_emulator.hpp) behind the Modbus RTU server dispatch, slave 1, 9600 8E1 on
// real hardware. Bytes go to the server framer as they arrive; a frame the framer hands over
// is served without a second CRC pass (serve_frame); a line silence hands the framer what it
// holds (idle()): a request whose length its function code does not give (an unknown function)
// is answered then, with exception 01.
//
// The silence: Modbus asks for t3.5 (4 ms at 9600 baud). Under emulation the gaps between
// bytes come from the host's scheduling, not the baud rate, so this image waits `silence_us`
// (50 ms by default) before it takes the line as idle: build it with -DMOTIONBUS_SILENCE_US=4010
// for a real line at 9600 baud.
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "motionbus/devices/sm_unit_emulator.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/server.hpp"

#ifndef MOTIONBUS_SILENCE_US
#define MOTIONBUS_SILENCE_US 50000
#endif
#ifndef MOTIONBUS_SLAVE
#define MOTIONBUS_SLAVE 1
#endif

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

constexpr std::uint8_t slave = MOTIONBUS_SLAVE;
constexpr std::uint32_t silence_us = MOTIONBUS_SILENCE_US;

mo::rtu_server_framer rx;
mb::devices::sm_unit::emulator unit;
std::uint8_t reply[mo::max_rtu_size];

void serve(const mo::rtu_frame& frame) {
  const auto n = mo::serve_frame(unit, slave, frame, mb::mutable_byte_view(reply, sizeof reply));
  if (n.ok() && n.value() > 0U) {  // nothing for broadcasts and other addresses
    board::uart_write(reply, n.value());
  }
}

}  // namespace

int main() {
  board::init();
  rx = mo::rtu_server_framer({mo::framer_role::server, slave});
  std::uint32_t last_byte = board::now_us();
  for (;;) {
    const std::uint32_t now = board::now_us();
    unit.set_time_ms(now / 1000U);
    std::uint8_t byte = 0;
    if (board::uart_read(byte)) {
      last_byte = now;
      mb::feed_all(rx, mb::byte_view(&byte, 1), [](const auto& r) {
        if (r.is_complete()) {
          serve(r.value());
        }
        return true;
      });
    } else if (rx.pending() > 0U && now - last_byte >= silence_us) {
      const auto r = rx.idle();
      if (r.is_complete()) {
        serve(r.value());
      }
    }
  }
}
