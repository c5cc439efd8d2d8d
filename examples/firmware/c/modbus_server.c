/* motionbus firmware example in C — the generic Modbus RTU server of ../modbus_server.cpp
 * written against the C API (motionbus/c.h): slave 1, 100 coils, 100 discrete inputs, 100
 * holding and 100 input registers at addresses 0..99; functions 01-06, 0F, 10, 11, 16 and 17.
 * The device is a callback table; the library frames, checks, dispatches and answers
 * (exceptions included). The loop is that of ../modbus_serve_loop.hpp: bytes from the UART to
 * the server framer as they arrive, a frame served and its reply written back, and a line
 * silence of MOTIONBUS_SILENCE_US (50 ms under emulation; t3.5 on a real line) handing the
 * framer what it holds. */
#include <motionbus/c.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "board.h"

#ifndef MOTIONBUS_SILENCE_US
#define MOTIONBUS_SILENCE_US 50000
#endif
#ifndef MOTIONBUS_SLAVE
#define MOTIONBUS_SLAVE 1
#endif

#define POINTS 100U

/* The data: coils and holding registers as written; discrete input i is on when i % 3 == 0,
 * input register i reads 1000 + i. */
typedef struct device {
  uint8_t coils[(POINTS + 7U) / 8U];
  uint16_t holding[POINTS];
} device;

static device dev;
static mb_modbus_server_framer rx;
static uint8_t reply[MB_MODBUS_MAX_ADU_SIZE];

static bool fits(uint16_t address, uint16_t quantity) {
  return (uint32_t)address + quantity <= POINTS;
}

static bool coil(const device* d, unsigned a) {
  return ((d->coils[a / 8U] >> (a % 8U)) & 1U) != 0U;
}

static void set_coil(device* d, unsigned a, bool on) {
  const uint8_t bit = (uint8_t)(1U << (a % 8U));
  d->coils[a / 8U] = (uint8_t)(on ? (d->coils[a / 8U] | bit) : (d->coils[a / 8U] & ~bit));
}

/* FC01 and FC02: the packed bits arrive cleared. */
static uint8_t read_coils(uint16_t address, uint16_t quantity, uint8_t* packed, void* context) {
  const device* d = (const device*)context;
  uint16_t i;
  if (!fits(address, quantity)) {
    return 0x02;
  }
  for (i = 0; i < quantity; ++i) {
    if (coil(d, (unsigned)address + i)) {
      packed[i / 8U] = (uint8_t)(packed[i / 8U] | (1U << (i % 8U)));
    }
  }
  return 0;
}

static uint8_t read_discrete_inputs(uint16_t address, uint16_t quantity, uint8_t* packed,
                                    void* context) {
  uint16_t i;
  (void)context;
  if (!fits(address, quantity)) {
    return 0x02;
  }
  for (i = 0; i < quantity; ++i) {
    if (((unsigned)address + i) % 3U == 0U) {
      packed[i / 8U] = (uint8_t)(packed[i / 8U] | (1U << (i % 8U)));
    }
  }
  return 0;
}

static uint8_t read_holding_registers(uint16_t address, uint16_t quantity, uint16_t* out,
                                      void* context) {
  const device* d = (const device*)context;
  uint16_t i;
  if (!fits(address, quantity)) {
    return 0x02;
  }
  for (i = 0; i < quantity; ++i) {
    out[i] = d->holding[address + i];
  }
  return 0;
}

static uint8_t read_input_registers(uint16_t address, uint16_t quantity, uint16_t* out,
                                    void* context) {
  uint16_t i;
  (void)context;
  if (!fits(address, quantity)) {
    return 0x02;
  }
  for (i = 0; i < quantity; ++i) {
    out[i] = (uint16_t)(1000U + address + i);
  }
  return 0;
}

static uint8_t write_single_coil(uint16_t address, bool on, void* context) {
  if (!fits(address, 1)) {
    return 0x02;
  }
  set_coil((device*)context, address, on);
  return 0;
}

static uint8_t write_multiple_coils(uint16_t address, uint16_t quantity, const uint8_t* packed,
                                    void* context) {
  uint16_t i;
  if (!fits(address, quantity)) {
    return 0x02;
  }
  for (i = 0; i < quantity; ++i) {
    set_coil((device*)context, (unsigned)address + i, ((packed[i / 8U] >> (i % 8U)) & 1U) != 0U);
  }
  return 0;
}

static uint8_t write_single_register(uint16_t address, uint16_t value, void* context) {
  if (!fits(address, 1)) {
    return 0x02;
  }
  ((device*)context)->holding[address] = value;
  return 0;
}

static uint8_t write_multiple_registers(uint16_t address, uint16_t quantity,
                                        const uint16_t* values, void* context) {
  device* d = (device*)context;
  uint16_t i;
  if (!fits(address, quantity)) {
    return 0x02;
  }
  for (i = 0; i < quantity; ++i) {
    d->holding[address + i] = values[i];
  }
  return 0;
}

/* FC11: the byte count, then server ID 0x4D ('M'), run indicator 0xFF (on), "motionbus". */
static uint8_t report_server_id(uint8_t* out, size_t capacity, size_t* size, void* context) {
  static const char id[] = "\x4D\xFFmotionbus";
  const size_t n = sizeof id - 1U;
  size_t i;
  (void)context;
  if (capacity < n + 1U) {
    return 0x04;
  }
  out[0] = (uint8_t)n;
  for (i = 0; i < n; ++i) {
    out[1U + i] = (uint8_t)id[i];
  }
  *size = 1U + n;
  return 0;
}

static const mb_modbus_callbacks callbacks = {
    read_coils,        read_discrete_inputs,  read_holding_registers, read_input_registers,
    write_single_coil, write_single_register, write_multiple_coils,   write_multiple_registers,
    report_server_id,  &dev};

/* A frame the framer handed over: served, the reply (if any) written back. */
static void serve(const mb_modbus_frame* frame) {
  size_t n = 0;
  if (mb_modbus_serve_frame(&callbacks, MOTIONBUS_SLAVE, frame, reply, sizeof reply, &n) == MB_OK &&
      n > 0U) { /* nothing for broadcasts and other addresses */
    board_uart_write(reply, n);
  }
}

int main(void) {
  mb_modbus_framer_options options = {MOTIONBUS_SLAVE, 0, false};
  uint32_t last_byte;
  board_init();
  mb_modbus_server_framer_init(&rx, &options);
  last_byte = board_now_us();
  for (;;) {
    const uint32_t now = board_now_us();
    uint8_t byte = 0;
    mb_modbus_frame frame;
    if (board_uart_read(&byte)) {
      last_byte = now;
      if (mb_modbus_server_framer_put(&rx, byte)) {
        /* what the byte settled, then every frame the rescan of the bytes held finds */
        mb_result r = mb_modbus_server_framer_result(&rx, &frame);
        for (;;) {
          if (r.status == MB_COMPLETE) {
            serve(&frame);
          }
          r = mb_modbus_server_framer_feed(&rx, NULL, 0, &frame);
          if (r.status == MB_INCOMPLETE) {
            break;
          }
        }
      }
    } else if (mb_modbus_server_framer_pending(&rx) > 0U &&
               now - last_byte >= (uint32_t)MOTIONBUS_SILENCE_US) {
      if (mb_modbus_server_framer_idle(&rx, &frame).status == MB_COMPLETE) {
        serve(&frame);
      }
    }
  }
}
