// motionbus firmware examples — the board interface (board.hpp) under C names (board.h), so
// that an image written in C runs on the same board support as the C++ images.
#include "board.h"

#include <cstddef>
#include <cstdint>

#include "../board.hpp"

extern "C" {

void board_init(void) {
  board::init();
}

bool board_uart_read(std::uint8_t* byte) {
  return board::uart_read(*byte);
}

void board_uart_write(const std::uint8_t* bytes, std::size_t n) {
  board::uart_write(bytes, n);
}

std::uint32_t board_now_us(void) {
  return board::now_us();
}

}  // extern "C"
