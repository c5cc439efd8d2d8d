// motionbus firmware examples — Arm MPS2 with the AN386 image (Cortex-M4), as QEMU models it
// (-M mps2-an386): startup code, the CMSDK APB UART0 polled, SysTick as a microsecond clock. No
// vendor SDK: the registers are those of the board's documentation (Arm MPS2 AN386, CMSDK APB
// UART).
#include <cstddef>
#include <cstdint>

#include "../board.hpp"

namespace {

constexpr std::uintptr_t uart0 = 0x40004000U;
constexpr std::uint32_t core_clock_hz = 25000000U;  // the AN386 image's system clock

volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

volatile std::uint32_t milliseconds = 0;

}  // namespace

// The startup code and vector table are cortex_m_startup.cpp's; this board takes SysTick.
extern "C" void systick_handler() {
  milliseconds = milliseconds + 1U;
}

namespace board {

void init() {
  reg(uart0 + 0x10U) = core_clock_hz / 9600U;     // BAUDDIV (QEMU ignores the rate)
  reg(uart0 + 0x08U) = 0x3U;                      // CTRL: TX and RX enabled
  reg(0xE000E014U) = core_clock_hz / 1000U - 1U;  // SysTick reload: 1 ms
  reg(0xE000E018U) = 0U;
  reg(0xE000E010U) = 0x7U;  // processor clock, interrupt, enabled
}

bool uart_read(std::uint8_t& byte) {
  if ((reg(uart0 + 0x04U) & 0x2U) == 0U) {  // STATE bit 1: RX buffer full
    return false;
  }
  byte = static_cast<std::uint8_t>(reg(uart0) & 0xFFU);
  return true;
}

void uart_write(const std::uint8_t* bytes, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    while ((reg(uart0 + 0x04U) & 0x1U) != 0U) {  // STATE bit 0: TX buffer full
    }
    reg(uart0) = bytes[i];
  }
}

void console(const char* text) {
  // Arm semihosting SYS_WRITE0 (0x04): r0 the operation, r1 the string; BKPT 0xAB on M-profile.
  register std::uintptr_t op asm("r0") = 0x04U;
  register const char* arg asm("r1") = text;
  asm volatile("bkpt 0xAB" : "+r"(op) : "r"(arg) : "memory");
}

std::uint32_t now_us() {
  // the milliseconds counted by the SysTick interrupt, plus the microseconds of the current one
  // from the counter (it counts down from the reload value); read again if a tick came between
  for (;;) {
    const std::uint32_t ms = milliseconds;
    const std::uint32_t left = reg(0xE000E018U);
    if (ms == milliseconds) {
      const std::uint32_t reload = reg(0xE000E014U);
      return ms * 1000U + (reload - left) / (core_clock_hz / 1000000U);
    }
  }
}

}  // namespace board
