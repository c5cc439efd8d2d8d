// motionbus firmware examples — the interrupts of the boards that have them, for the
// interrupt-driven images (modbus_server_irq.cpp, tformat_master_irq.cpp): the UART's receive
// interrupt and a one-shot timer, beside board.hpp's polled UART and clock (uart_write() and
// now_us() are still board.hpp's). Implemented by boards/mps2_an386_irq.cpp (CMSDK UART0 receive
// interrupt and CMSDK TIMER0, through the NVIC), boards/riscv_virt_irq.cpp (NS16550A through the
// PLIC, the CLINT's mtimecmp) and boards/microbit_irq.cpp (nRF51 UART and TIMER0's CC[1]).
//
// The two handlers run at one interrupt priority: neither ever interrupts the other, which is
// what the library's put()/idle() contract asks (none of a framer's calls while another runs).
// The main loop shares nothing with them but what the image guards itself (see the images).
#ifndef MOTIONBUS_FIRMWARE_BOARD_IRQ_HPP
#define MOTIONBUS_FIRMWARE_BOARD_IRQ_HPP

#include <cstdint>

namespace board {

/// Called in the UART receive interrupt, once for each byte received, in order.
using byte_handler = void (*)(std::uint8_t byte);
/// Called in the timer's interrupt when the one-shot armed by timer_arm() expires.
using timer_handler = void (*)();

/// After init(): routes the UART's receive interrupt to `on_byte` and the one-shot timer's to
/// `on_timer`, and enables both (and the processor's interrupts). uart_read() is not to be used
/// afterwards: the bytes go to `on_byte`.
void irq_start(byte_handler on_byte, timer_handler on_timer);
/// (Re)arms the one-shot timer to expire `us` microseconds from now (at least 1); an earlier
/// arming that has not expired yet is cancelled, and an expiry already pending is withdrawn.
/// Called from the two handlers (or with interrupts off).
void timer_arm(std::uint32_t us);
/// Masks the processor's interrupts (a critical section of the main loop begins).
void interrupts_off();
/// Unmasks them (the critical section ends; what became pending meanwhile is taken now).
void interrupts_on();
/// With interrupts off: sleeps until an interrupt is pending (at once if one is), and returns
/// with interrupts still off; interrupts_on() then takes it. Checking a condition and then
/// sleeping with interrupts off loses no wake-up: an interrupt after the check wakes the sleep.
void wait_for_interrupt();

}  // namespace board

#endif  // MOTIONBUS_FIRMWARE_BOARD_IRQ_HPP
