// motionbus firmware examples — the interrupts of QEMU's RISC-V `virt` board in 32 bits (-M
// virt) for the interrupt-driven images (board_irq.hpp): the NS16550A's receive interrupt
// through the PLIC (source 10, machine-mode context of hart 0) and the CLINT's mtimecmp as the
// one-shot, taken in machine mode by one trap handler (so never one inside the other). No vendor
// SDK: the registers are those of the 16550, the RISC-V PLIC and CLINT, and the privileged ISA.
#include <cstddef>
#include <cstdint>

#include "../board.hpp"
#include "../board_irq.hpp"

namespace {

constexpr std::uintptr_t uart0 = 0x10000000U;
constexpr unsigned uart0_source = 10U;                       // the UART's PLIC source on `virt`
constexpr std::uintptr_t plic = 0x0C000000U;                 // priorities at 4 * source
constexpr std::uintptr_t plic_enable = plic + 0x2000U;       // context 0: hart 0, M-mode
constexpr std::uintptr_t plic_threshold = plic + 0x200000U;  // context 0
constexpr std::uintptr_t plic_claim = plic + 0x200004U;      // context 0: claim / complete
constexpr std::uintptr_t mtime = 0x0200BFF8U;                // CLINT: 64-bit, 10 MHz on `virt`
constexpr std::uintptr_t mtimecmp = 0x02004000U;             // CLINT: hart 0
constexpr std::uint32_t ticks_per_us = 10U;
constexpr std::uint32_t mcause_external = 0x8000000BU;  // machine external interrupt
constexpr std::uint32_t mcause_timer = 0x80000007U;     // machine timer interrupt

volatile std::uint8_t& reg8(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint8_t*>(address);
}
volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// Written once by irq_start() before the interrupts are enabled, read by the handler only.
board::byte_handler on_byte_ = nullptr;
board::timer_handler on_timer_ = nullptr;

std::uint64_t read_mtime() {  // the high word read twice: no carry between the two halves
  for (;;) {
    const std::uint32_t high = reg(mtime + 4U);
    const std::uint32_t low = reg(mtime);
    if (reg(mtime + 4U) == high) {
      return (std::uint64_t{high} << 32U) | low;
    }
  }
}

// mtimecmp written so that no intermediate value lies in the past (the privileged ISA's
// sequence): low word to the maximum, then the high word, then the low word.
void write_mtimecmp(std::uint64_t at) {
  reg(mtimecmp) = 0xFFFFFFFFU;
  reg(mtimecmp + 4U) = static_cast<std::uint32_t>(at >> 32U);
  reg(mtimecmp) = static_cast<std::uint32_t>(at);
}

}  // namespace

extern "C" {
// The machine-mode trap handler (mtvec, direct mode): the compiler saves what it uses and
// returns with mret. Only the two interrupts are enabled: anything else stops here.
__attribute__((interrupt("machine"), aligned(4))) void machine_trap() {
  std::uint32_t cause = 0;
  asm volatile("csrr %0, mcause" : "=r"(cause));
  if (cause == mcause_external) {
    const std::uint32_t source = reg(plic_claim);
    if (source == uart0_source) {
      while ((reg8(uart0 + 5U) & 0x01U) != 0U) {  // LSR bit 0: data ready
        on_byte_(reg8(uart0));
      }
    }
    reg(plic_claim) = source;  // complete
  } else if (cause == mcause_timer) {
    write_mtimecmp(~std::uint64_t{0});  // one-shot: MTIP drops
    on_timer_();
  } else {
    for (;;) {
    }
  }
}
}

namespace board {

void irq_start(byte_handler on_byte, timer_handler on_timer) {
  on_byte_ = on_byte;
  on_timer_ = on_timer;
  write_mtimecmp(~std::uint64_t{0});
  reg(plic + 4U * uart0_source) = 1U;  // priority 1 (0 disables the source)
  reg(plic_enable) = 1U << uart0_source;
  reg(plic_threshold) = 0U;
  reg8(uart0 + 2U) = 0x07U;  // FCR: FIFOs enabled and cleared, receive trigger at 1 byte
  reg8(uart0 + 4U) = 0x08U;  // MCR: OUT2 (gates the interrupt line on PC-style 16550s)
  reg8(uart0 + 1U) = 0x01U;  // IER: received data available
  const std::uintptr_t trap = reinterpret_cast<std::uintptr_t>(&machine_trap);
  asm volatile("csrw mtvec, %0" ::"r"(trap));                    // direct mode
  asm volatile("csrs mie, %0" ::"r"((1U << 11U) | (1U << 7U)));  // MEIE, MTIE
  interrupts_on();
}

void timer_arm(std::uint32_t us) {
  // a later compare value drops MTIP at once: an expiry not yet taken is withdrawn
  write_mtimecmp(read_mtime() + std::uint64_t{us > 0U ? us : 1U} * ticks_per_us);
}

void interrupts_off() {
  asm volatile("csrci mstatus, 8" ::: "memory");
}  // MIE

void interrupts_on() {
  asm volatile("csrsi mstatus, 8" ::: "memory");
}

// wfi wakes on an interrupt pending and enabled in mie, whatever mstatus.MIE says.
void wait_for_interrupt() {
  asm volatile("wfi" ::: "memory");
}

}  // namespace board
