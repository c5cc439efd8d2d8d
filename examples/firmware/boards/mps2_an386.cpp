// motionbus firmware examples — Arm MPS2 with the AN386 image (Cortex-M4), as QEMU models it
// (-M mps2-an386): startup code, the CMSDK APB UART0 polled, the FPGA I/O block's COUNTER as a
// microsecond clock. No vendor SDK: the registers are those of the board's documentation (Arm
// MPS2 AN386: CMSDK APB UART, FPGA system control and I/O).
#include <cstddef>
#include <cstdint>

#include "../board.hpp"

namespace {

constexpr std::uintptr_t uart0 = 0x40004000U;
constexpr std::uintptr_t fpgaio = 0x40028000U;      // FPGA system control and I/O
constexpr std::uint32_t core_clock_hz = 25000000U;  // the AN386 image's system clock

volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

}  // namespace

// The startup code and vector table are cortex_m_startup.cpp's; this board takes no interrupt.

namespace board {

void init() {
  reg(uart0 + 0x10U) = core_clock_hz / 9600U;           // BAUDDIV (QEMU ignores the rate)
  reg(uart0 + 0x08U) = 0x3U;                            // CTRL: TX and RX enabled
  reg(fpgaio + 0x1CU) = core_clock_hz / 1000000U - 1U;  // PRESCALE: COUNTER counts microseconds
  reg(fpgaio + 0x18U) = 0U;                             // COUNTER
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
  // Not SysTick milliseconds plus its counter: QEMU holds SysTick's counter at 0 until its
  // interrupt is delivered, late when the host is loaded, and drops the ticks missed, so that
  // clock stood still and then jumped (two reset requests 3 ms apart read 55 us apart: issue 27).
  // COUNTER is computed from the emulated clock at each read.
  return reg(fpgaio + 0x18U);
}

}  // namespace board
