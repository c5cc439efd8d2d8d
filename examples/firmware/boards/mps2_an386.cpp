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

extern "C" {
extern std::uint32_t __data_load;
extern std::uint32_t __data_start;
extern std::uint32_t __data_end;
extern std::uint32_t __bss_start;
extern std::uint32_t __bss_end;
extern std::uint32_t __stack_top;
extern void (*__init_array_start)();
extern void (*__init_array_end)();
// The image's main(), called by its assembler name: C++ does not let a program call main.
int image_main() __asm__("main");

[[noreturn]] void reset_handler() {
  for (std::uint32_t *d = &__data_start, *s = &__data_load; d < &__data_end;) {
    *d++ = *s++;
  }
  for (std::uint32_t* b = &__bss_start; b < &__bss_end;) {
    *b++ = 0;
  }
  for (void (**f)() = &__init_array_start; f < &__init_array_end; ++f) {
    (*f)();
  }
  (void)image_main();
  for (;;) {
  }
}

void default_handler() {
  for (;;) {
  }
}

void systick_handler() {
  milliseconds = milliseconds + 1U;
}

// The Cortex-M vector table: initial stack pointer, then the exception handlers.
__attribute__((section(".vectors"), used)) void* const vectors[16] = {
    &__stack_top,
    reinterpret_cast<void*>(&reset_handler),
    reinterpret_cast<void*>(&default_handler),  // NMI
    reinterpret_cast<void*>(&default_handler),  // HardFault
    reinterpret_cast<void*>(&default_handler),  // MemManage
    reinterpret_cast<void*>(&default_handler),  // BusFault
    reinterpret_cast<void*>(&default_handler),  // UsageFault
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    reinterpret_cast<void*>(&default_handler),  // SVCall
    reinterpret_cast<void*>(&default_handler),  // DebugMonitor
    nullptr,
    reinterpret_cast<void*>(&default_handler),  // PendSV
    reinterpret_cast<void*>(&systick_handler),  // SysTick
};
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
