// motionbus firmware examples — QEMU's RISC-V `virt` board in 32 bits (-M virt, standing for an
// FPGA soft-core): startup code, the NS16550A UART polled, the CLINT's mtime (10 MHz) as the
// clock. No vendor SDK: the registers are those of the 16550 and of the RISC-V CLINT.
#include <cstddef>
#include <cstdint>

#include "../board.hpp"

namespace {

constexpr std::uintptr_t uart0 = 0x10000000U;
constexpr std::uintptr_t mtime = 0x0200BFF8U;  // CLINT: 64-bit time, 10 MHz on `virt`

volatile std::uint8_t& reg8(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint8_t*>(address);
}

}  // namespace

extern "C" {
extern std::uint32_t __bss_start;
extern std::uint32_t __bss_end;
extern void (*__init_array_start)();
extern void (*__init_array_end)();
// The image's main(), called by its assembler name: C++ does not let a program call main.
int image_main() __asm__("main");

// Everything is loaded into RAM by QEMU (-kernel): only .bss is cleared here.
[[noreturn]] void reset_c() {
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

__attribute__((naked, section(".text.start"))) void _start() {
  asm volatile(
      "la sp, __stack_top\n"
      "call reset_c\n"
      "1: j 1b\n");
}
}

namespace board {

void init() {
  reg8(uart0 + 1U) = 0x00U;  // IER: no interrupts
  reg8(uart0 + 2U) = 0x07U;  // FCR: FIFOs enabled and cleared
  reg8(uart0 + 3U) = 0x03U;  // LCR: 8 data bits (QEMU ignores rate and parity)
}

bool uart_read(std::uint8_t& byte) {
  if ((reg8(uart0 + 5U) & 0x01U) == 0U) {  // LSR bit 0: data ready
    return false;
  }
  byte = reg8(uart0);
  return true;
}

void uart_write(const std::uint8_t* bytes, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    while ((reg8(uart0 + 5U) & 0x20U) == 0U) {  // LSR bit 5: transmitter holding register empty
    }
    reg8(uart0) = bytes[i];
  }
}

void console(const char* text) {
  // RISC-V semihosting SYS_WRITE0 (0x04): a0 the operation, a1 the string, and the three
  // instructions that mark a semihosting call (uncompressed, in this order).
  register std::uintptr_t op asm("a0") = 0x04U;
  register const char* arg asm("a1") = text;
  asm volatile(
      ".option push\n"
      ".option norvc\n"
      "slli x0, x0, 0x1f\n"
      "ebreak\n"
      "srai x0, x0, 7\n"
      ".option pop\n"
      : "+r"(op)
      : "r"(arg)
      : "memory");
}

std::uint32_t now_us() {
  // mtime / 10 modulo 2^32, so that the clock wraps after 2^32 us as board.hpp says and a
  // difference across the wrap is right. (The low word alone divided by 10 went back from
  // 429496729 to 0 every 429.5 s: a difference across that step read as a silence of an hour,
  // and a frame being received then was cut.) Without a 64-bit division: with mtime = high *
  // 2^32 + low, 2^32 = 10 * 429496729 + 6 and low = 10 * q + r, mtime / 10 is high *
  // 429496729 + q + (6 * high + r) / 10 (exact in 32 bits for 9700 years of high words).
  const volatile std::uint32_t* const t = reinterpret_cast<volatile std::uint32_t*>(mtime);
  std::uint32_t high = 0;
  std::uint32_t low = 0;
  do {  // the high word read again: no carry between the two halves
    high = t[1];
    low = t[0];
  } while (t[1] != high);
  return high * 429496729U + low / 10U + (6U * high + low % 10U) / 10U;
}

}  // namespace board
