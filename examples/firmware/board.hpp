// motionbus firmware examples — the board interface each image is written against: a polled
// UART and a microsecond clock. A port to a new board replaces boards/<board>.cpp (its startup
// code, UART driver and clock) and the linker script; the images do not change.
#ifndef MOTIONBUS_FIRMWARE_BOARD_HPP
#define MOTIONBUS_FIRMWARE_BOARD_HPP

#include <cstddef>
#include <cstdint>

namespace board {

/// Sets up the UART (and the clock) before main() uses them.
void init();
/// A received byte, if one is waiting (never blocks).
bool uart_read(std::uint8_t& byte);
/// Sends `n` bytes (blocks until the transmitter took them).
void uart_write(const std::uint8_t* bytes, std::size_t n);
/// A free-running microsecond clock (wraps after about 71 minutes).
std::uint32_t now_us();
/// Writes text to the debugger's console (semihosting: QEMU's standard output with
/// -semihosting), for images whose UART talks to a peer.
void console(const char* text);

}  // namespace board

#endif  // MOTIONBUS_FIRMWARE_BOARD_HPP
