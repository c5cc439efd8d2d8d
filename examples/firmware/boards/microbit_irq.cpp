// motionbus firmware examples — the interrupts of the BBC micro:bit (nRF51822, Cortex-M0; QEMU
// -M microbit) for the interrupt-driven images (board_irq.hpp): the UART's RXDRDY interrupt
// (IRQ 2) and TIMER0's compare channel 1 (IRQ 8; channel 0 is now_us()'s capture) as the
// one-shot, both through the NVIC at one priority. No vendor SDK: the registers are those of the
// nRF51 reference manual (UART, TIMER) and of the Armv6-M NVIC.
#include <cstddef>
#include <cstdint>

#include "../board.hpp"
#include "../board_irq.hpp"

namespace {

constexpr std::uintptr_t uart0 = 0x40002000U;
constexpr std::uintptr_t timer0 = 0x40008000U;  // 1 MHz, 32 bits (board::init())
constexpr unsigned uart0_irq = 2U;
constexpr unsigned timer0_irq = 8U;
constexpr std::uint32_t compare1 = 1U << 17U;  // INTEN: COMPARE[1]
constexpr std::uintptr_t nvic_iser = 0xE000E100U;
constexpr std::uintptr_t nvic_icpr = 0xE000E280U;

volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// Written once by irq_start() before the interrupts are enabled, read by the handlers only.
board::byte_handler on_byte_ = nullptr;
board::timer_handler on_timer_ = nullptr;

inline void data_barrier() {
  asm volatile("dsb" ::: "memory");
}

}  // namespace

extern "C" {
void default_handler();  // cortex_m_startup.cpp's

void uart0_handler() {
  // the event cleared before each read: the read sets it again while bytes remain
  while (reg(uart0 + 0x108U) != 0U) {  // EVENTS_RXDRDY
    reg(uart0 + 0x108U) = 0U;
    on_byte_(static_cast<std::uint8_t>(reg(uart0 + 0x518U) & 0xFFU));  // RXD
  }
  data_barrier();
}

void timer0_handler() {
  reg(timer0 + 0x308U) = compare1;  // INTENCLR: one-shot
  reg(timer0 + 0x144U) = 0U;        // EVENTS_COMPARE[1]
  data_barrier();
  on_timer_();
}

// The external interrupts' vectors, placed by the linker script right after the 16 of
// cortex_m_startup.cpp (section .vectors.irq): IRQ 2 (UART0) and IRQ 8 (TIMER0).
__attribute__((section(".vectors.irq"), used)) void* const irq_vectors[16] = {
    reinterpret_cast<void*>(&default_handler),  // 0: POWER_CLOCK
    reinterpret_cast<void*>(&default_handler),  // 1: RADIO
    reinterpret_cast<void*>(&uart0_handler),    // 2: UART0
    reinterpret_cast<void*>(&default_handler),  // 3
    reinterpret_cast<void*>(&default_handler),  // 4
    reinterpret_cast<void*>(&default_handler),  // 5
    reinterpret_cast<void*>(&default_handler),  // 6
    reinterpret_cast<void*>(&default_handler),  // 7
    reinterpret_cast<void*>(&timer0_handler),   // 8: TIMER0
    reinterpret_cast<void*>(&default_handler),  // 9
    reinterpret_cast<void*>(&default_handler),  // 10
    reinterpret_cast<void*>(&default_handler),  // 11
    reinterpret_cast<void*>(&default_handler),  // 12
    reinterpret_cast<void*>(&default_handler),  // 13
    reinterpret_cast<void*>(&default_handler),  // 14
    reinterpret_cast<void*>(&default_handler),  // 15
};
}

namespace board {

void irq_start(byte_handler on_byte, timer_handler on_timer) {
  on_byte_ = on_byte;
  on_timer_ = on_timer;
  reg(timer0 + 0x308U) = compare1;                          // INTENCLR
  reg(timer0 + 0x144U) = 0U;                                // EVENTS_COMPARE[1]
  reg(uart0 + 0x304U) = 1U << 2U;                           // INTENSET: RXDRDY
  reg(nvic_icpr) = (1U << uart0_irq) | (1U << timer0_irq);  // priorities: both 0
  reg(nvic_iser) = (1U << uart0_irq) | (1U << timer0_irq);
  data_barrier();
  interrupts_on();
}

void timer_arm(std::uint32_t us) {
  reg(timer0 + 0x308U) = compare1;  // INTENCLR: an expiry not yet taken is withdrawn...
  reg(timer0 + 0x144U) = 0U;        // EVENTS_COMPARE[1]
  data_barrier();
  reg(nvic_icpr) = 1U << timer0_irq;  // ...here too: the NVIC latched it as pending
  reg(timer0 + 0x544U) = now_us() + (us > 0U ? us : 1U);  // CC[1]
  reg(timer0 + 0x304U) = compare1;                        // INTENSET
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
