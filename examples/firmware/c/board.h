/* motionbus firmware examples — the board interface (../board.hpp) for images written in C:
 * the same polled UART and microsecond clock, through C names (board_c.cpp). */
#ifndef MOTIONBUS_FIRMWARE_C_BOARD_H
#define MOTIONBUS_FIRMWARE_C_BOARD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Sets up the UART (and the clock) before the image uses them. */
void board_init(void);
/* A received byte, if one is waiting (never blocks). */
bool board_uart_read(uint8_t* byte);
/* Sends `n` bytes (blocks until the transmitter took them). */
void board_uart_write(const uint8_t* bytes, size_t n);
/* A free-running microsecond clock. */
uint32_t board_now_us(void);

#ifdef __cplusplus
}
#endif

#endif /* MOTIONBUS_FIRMWARE_C_BOARD_H */
