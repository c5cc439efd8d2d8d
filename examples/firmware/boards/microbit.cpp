// motionbus firmware examples — the BBC micro:bit (nRF51822, Cortex-M0), as QEMU models it
// (-M microbit): startup code, the nRF51 UART polled, TIMER0 as a microsecond clock. No vendor
// SDK: the registers are those of the nRF51 reference manual (UART, TIMER).
#include <cstddef>
#include <cstdint>

#include "../board.hpp"

namespace {

constexpr std::uintptr_t uart0 = 0x40002000U;
constexpr std::uintptr_t timer0 = 0x40008000U;

volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

}  // namespace

// The startup code and vector table are cortex_m_startup.cpp's.

namespace board {

void init() {
  reg(uart0 + 0x524U) = 0x00275000U;  // BAUDRATE: 9600 (QEMU ignores the rate)
  reg(uart0 + 0x500U) = 4U;           // ENABLE
  reg(uart0 + 0x000U) = 1U;           // TASKS_STARTRX
  reg(uart0 + 0x008U) = 1U;           // TASKS_STARTTX
  reg(timer0 + 0x504U) = 0U;          // MODE: timer
  reg(timer0 + 0x508U) = 3U;          // BITMODE: 32 bits
  reg(timer0 + 0x510U) = 4U;          // PRESCALER: 16 MHz / 2^4 = 1 MHz
  reg(timer0 + 0x000U) = 1U;          // TASKS_START
}

bool uart_read(std::uint8_t& byte) {
  if (reg(uart0 + 0x108U) == 0U) {  // EVENTS_RXDRDY
    return false;
  }
  reg(uart0 + 0x108U) = 0U;
  byte = static_cast<std::uint8_t>(reg(uart0 + 0x518U) & 0xFFU);  // RXD
  return true;
}

void uart_write(const std::uint8_t* bytes, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    reg(uart0 + 0x11CU) = 0U;        // EVENTS_TXDRDY
    reg(uart0 + 0x51CU) = bytes[i];  // TXD
    while (reg(uart0 + 0x11CU) == 0U) {
    }
  }
}

void console(const char* text) {
  // Arm semihosting SYS_WRITE0 (0x04): r0 the operation, r1 the string; BKPT 0xAB on M-profile.
  register std::uintptr_t op asm("r0") = 0x04U;
  register const char* arg asm("r1") = text;
  asm volatile("bkpt 0xAB" : "+r"(op) : "r"(arg) : "memory");
}

std::uint32_t now_us() {
  reg(timer0 + 0x040U) = 1U;    // TASKS_CAPTURE[0]
  return reg(timer0 + 0x540U);  // CC[0]
}

}  // namespace board
