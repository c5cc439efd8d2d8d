// motionbus firmware examples — the interrupts of the Arm MPS2 AN386 board (QEMU -M mps2-an386)
// for the interrupt-driven images (board_irq.hpp): the CMSDK APB UART0's receive interrupt (IRQ
// 0) and the CMSDK APB TIMER0 (IRQ 8) as the one-shot, both through the NVIC at one priority.
// No vendor SDK: the registers are those of the board's documentation (Arm MPS2 AN386: CMSDK APB
// UART and timer) and of the Armv7-M NVIC.
#include <cstddef>
#include <cstdint>

#include "../board.hpp"
#include "../board_irq.hpp"

namespace {

constexpr std::uintptr_t uart0 = 0x40004000U;
constexpr std::uintptr_t timer0 = 0x40000000U;
constexpr std::uint32_t ticks_per_us = 25U;  // TIMER0 counts the 25 MHz system clock
constexpr unsigned uart0_rx_irq = 0U;
constexpr unsigned timer0_irq = 8U;
constexpr std::uintptr_t nvic_iser = 0xE000E100U;  // set-enable
constexpr std::uintptr_t nvic_icpr = 0xE000E280U;  // clear-pending

volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// Written once by irq_start() before the interrupts are enabled, read by the handlers only.
board::byte_handler on_byte_ = nullptr;
board::timer_handler on_timer_ = nullptr;

// A write that clears an interrupt reaches the peripheral before the handler returns (else the
// processor may take the interrupt once more on return: Arm's advice for Cortex-M4).
inline void data_barrier() {
  asm volatile("dsb" ::: "memory");
}

}  // namespace

extern "C" {
void default_handler();  // cortex_m_startup.cpp's

void uart0_rx_handler() {
  // INTCLEAR before each read: a byte that arrives after the read raises the interrupt again.
  while ((reg(uart0 + 0x04U) & 0x2U) != 0U) {  // STATE bit 1: RX buffer full
    reg(uart0 + 0x0CU) = 0x2U;                 // INTCLEAR: RX
    on_byte_(static_cast<std::uint8_t>(reg(uart0) & 0xFFU));
  }
  data_barrier();
}

void timer0_handler() {
  reg(timer0 + 0x00U) = 0U;  // CTRL: stopped (one-shot)
  reg(timer0 + 0x0CU) = 1U;  // INTCLEAR
  data_barrier();
  on_timer_();
}

// The external interrupts' vectors, placed by the linker script right after the 16 of
// cortex_m_startup.cpp (section .vectors.irq): IRQ 0 (UART0 RX) and IRQ 8 (TIMER0).
__attribute__((section(".vectors.irq"), used)) void* const irq_vectors[16] = {
    reinterpret_cast<void*>(&uart0_rx_handler),  // 0: UART0 RX
    reinterpret_cast<void*>(&default_handler),   // 1: UART0 TX
    reinterpret_cast<void*>(&default_handler),   // 2
    reinterpret_cast<void*>(&default_handler),   // 3
    reinterpret_cast<void*>(&default_handler),   // 4
    reinterpret_cast<void*>(&default_handler),   // 5
    reinterpret_cast<void*>(&default_handler),   // 6
    reinterpret_cast<void*>(&default_handler),   // 7
    reinterpret_cast<void*>(&timer0_handler),    // 8: TIMER0
    reinterpret_cast<void*>(&default_handler),   // 9
    reinterpret_cast<void*>(&default_handler),   // 10
    reinterpret_cast<void*>(&default_handler),   // 11
    reinterpret_cast<void*>(&default_handler),   // 12
    reinterpret_cast<void*>(&default_handler),   // 13
    reinterpret_cast<void*>(&default_handler),   // 14
    reinterpret_cast<void*>(&default_handler),   // 15
};
}

namespace board {

void irq_start(byte_handler on_byte, timer_handler on_timer) {
  on_byte_ = on_byte;
  on_timer_ = on_timer;
  reg(timer0 + 0x00U) = 0U;                                    // CTRL: stopped
  reg(timer0 + 0x0CU) = 1U;                                    // INTCLEAR
  reg(uart0 + 0x0CU) = 0xFU;                                   // INTCLEAR: all
  reg(uart0 + 0x08U) = 0x3U | 0x8U;                            // CTRL: TX, RX, RX interrupt
  reg(nvic_icpr) = (1U << uart0_rx_irq) | (1U << timer0_irq);  // priorities: both 0
  reg(nvic_iser) = (1U << uart0_rx_irq) | (1U << timer0_irq);
  data_barrier();
  interrupts_on();
}

void timer_arm(std::uint32_t us) {
  const std::uint32_t ticks = (us > 0U ? us : 1U) * ticks_per_us;
  reg(timer0 + 0x00U) = 0U;  // CTRL: stopped
  reg(timer0 + 0x0CU) = 1U;  // INTCLEAR: an expiry not yet taken is withdrawn...
  data_barrier();
  reg(nvic_icpr) = 1U << timer0_irq;  // ...here too: the NVIC latched it as pending
  reg(timer0 + 0x08U) = ticks;        // RELOAD
  reg(timer0 + 0x04U) = ticks;        // VALUE: counts down to 0, then interrupts
  reg(timer0 + 0x00U) = 0x9U;         // CTRL: enabled, interrupt enabled
}

void interrupts_off() {
  asm volatile("cpsid i" ::: "memory");
}

void interrupts_on() {
  asm volatile("cpsie i" ::: "memory");
}

void wait_for_interrupt() {
  asm volatile("dsb\n wfi" ::: "memory");
}

}  // namespace board
