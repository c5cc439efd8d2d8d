/* libmodbus (a third-party Modbus master) against the generic Modbus server image
 * (examples/firmware/modbus_server.cpp) on its UART's pty: every function the server serves,
 * and the exceptions for a bad address and a bad quantity.
 * Usage: libmodbus_generic DEVICE. Exit 0 when every check holds. */
#include <errno.h>
#include <modbus.h>
#include <stdio.h>
#include <string.h>

#include "libmodbus_peer.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    return 2;
  }
  modbus_t* ctx = open_master(argv[1]);
  if (ctx == NULL) {
    return 1;
  }
  uint8_t bits[100] = {0};
  uint16_t regs[100] = {0};

  check("FC05 coil 7 on", modbus_write_bit(ctx, 7, 1) == 1);
  const uint8_t coils[10] = {1, 0, 1, 1, 0, 0, 0, 0, 1, 1};
  check("FC0F coils 20..29", modbus_write_bits(ctx, 20, 10, coils) == 10);
  check("FC01 reads coils 0..29", modbus_read_bits(ctx, 0, 30, bits) == 30);
  check("FC01 coil 7 and coils 20..29 as written",
        bits[7] == 1 && bits[6] == 0 && memcmp(bits + 20, coils, 10) == 0);
  check("FC02 discrete inputs 0..8", modbus_read_input_bits(ctx, 0, 9, bits) == 9);
  check("FC02 input i is on when i % 3 == 0",
        bits[0] == 1 && bits[1] == 0 && bits[3] == 1 && bits[8] == 0);
  check("FC06 holding 5", modbus_write_register(ctx, 5, 0x1234) == 1);
  const uint16_t values[4] = {11, 22, 33, 44};
  check("FC10 holding 40..43", modbus_write_registers(ctx, 40, 4, values) == 4);
  check("FC03 reads them back", modbus_read_registers(ctx, 40, 4, regs) == 4 && regs[0] == 11 &&
                                   regs[3] == 44);
  check("FC03 holding 5", modbus_read_registers(ctx, 5, 1, regs) == 1 && regs[0] == 0x1234);
  check("FC04 input registers 10..12", modbus_read_input_registers(ctx, 10, 3, regs) == 3 &&
                                          regs[0] == 1010 && regs[2] == 1012);
  check("FC16 mask write on holding 5", modbus_mask_write_register(ctx, 5, 0x00F2, 0x0025) == 1);
  check("FC16 result (0x1234 & 0xF2) | (0x25 & ~0xF2)",
        modbus_read_registers(ctx, 5, 1, regs) == 1 && regs[0] == ((0x1234 & 0x00F2) | (0x0025 & ~0x00F2)));
  const uint16_t rw[2] = {7, 8};
  check("FC17 write 60..61, read 40..41",
        modbus_write_and_read_registers(ctx, 60, 2, rw, 40, 2, regs) == 2 && regs[0] == 11 &&
            regs[1] == 22);
  check("FC17 wrote them", modbus_read_registers(ctx, 60, 2, regs) == 2 && regs[0] == 7 &&
                               regs[1] == 8);
  uint8_t id[64] = {0};
  const int n = modbus_report_slave_id(ctx, sizeof id, id);
  check("FC11 server id 0x4D, run indicator on, \"motionbus\"",
        n == 11 && id[0] == 0x4D && id[1] == 0xFF && memcmp(id + 2, "motionbus", 9) == 0);
  check("FC03 past address 99: exception 02",
        modbus_read_registers(ctx, 98, 5, regs) == -1 && errno == EMBXILADD);
  check("FC0F past address 99: exception 02",
        modbus_write_bits(ctx, 95, 10, coils) == -1 && errno == EMBXILADD);
  modbus_close(ctx);
  modbus_free(ctx);
  return failures == 0 ? 0 : 1;
}
