// motionbus firmware examples — the Modbus RTU server loop the Modbus images share: bytes from
// the board's UART to a server framer as they arrive; a frame the framer hands over is served
// without a second CRC pass (serve_frame) and the reply, if any, written back; a line silence of
// MOTIONBUS_SILENCE_US hands the framer what it holds (idle()), so that a request whose length
// its function code does not give (an unknown function) is answered then, with exception 01.
//
// The silence: Modbus asks for t3.5 (4 ms at 9600 baud). Under emulation the gaps between bytes
// come from the host's scheduling, not the baud rate, so the images wait 50 ms by default: build
// them with -DMOTIONBUS_SILENCE_US=4010 for a real line at 9600 baud. MOTIONBUS_SLAVE is the
// server's address (1 by default).
#ifndef MOTIONBUS_FIRMWARE_MODBUS_SERVE_LOOP_HPP
#define MOTIONBUS_FIRMWARE_MODBUS_SERVE_LOOP_HPP

#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/server.hpp"

#ifndef MOTIONBUS_SILENCE_US
#define MOTIONBUS_SILENCE_US 50000
#endif
#ifndef MOTIONBUS_SLAVE
#define MOTIONBUS_SLAVE 1
#endif

namespace firmware {

inline constexpr std::uint8_t slave = MOTIONBUS_SLAVE;
inline constexpr std::uint32_t silence_us = MOTIONBUS_SILENCE_US;

/// Feeds the UART's bytes to the server framer `rx` forever and hands each frame it gives to
/// `serve(frame)`; a line silence of silence_us hands over what `rx` holds. `each_pass(now_us)`
/// runs once per pass of the loop (a device's clock, say).
template <class Framer, class Serve, class EachPass>
[[noreturn]] void frame_forever(Framer& rx, Serve&& serve, EachPass&& each_pass) {
  std::uint32_t last_byte = board::now_us();
  for (;;) {
    const std::uint32_t now = board::now_us();
    each_pass(now);
    std::uint8_t byte = 0;
    if (board::uart_read(byte)) {
      last_byte = now;
      motionbus::put_each(rx, byte, [&serve](const auto& r) {
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

/// Serves `device` on the UART forever; `each_pass(now_us)` runs once per pass of the loop (a
/// device's clock, say).
template <class Device, class EachPass>
[[noreturn]] void serve_forever(Device& device, EachPass&& each_pass) {
  static motionbus::modbus::rtu_server_framer rx;
  static std::uint8_t reply[motionbus::modbus::max_rtu_size];
  rx = motionbus::modbus::rtu_server_framer({slave});
  frame_forever(
      rx,
      [&device](const motionbus::modbus::rtu_frame& frame) {
        const auto n = motionbus::modbus::serve_frame(
            device, slave, frame, motionbus::mutable_byte_view(reply, sizeof reply));
        if (n.ok() && n.value() > 0U) {  // nothing for broadcasts and other addresses
          board::uart_write(reply, n.value());
        }
      },
      each_pass);
}

}  // namespace firmware

#endif  // MOTIONBUS_FIRMWARE_MODBUS_SERVE_LOOP_HPP
