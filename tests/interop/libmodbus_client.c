/* libmodbus (a third-party Modbus master) against `motionbus serve sm-unit` on a pty.
 * Usage: libmodbus_client DEVICE. Exit 0 when every check holds. */
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
  uint16_t regs[16] = {0};
  check("FC04 instantaneous data", modbus_read_input_registers(ctx, 100, 9, regs) == 9);
  check("frequency is 50 Hz", regs[7] == 50);
  check("FC06 setting 36", modbus_write_register(ctx, 36, 650) == 1);
  check("FC03 reads it back", modbus_read_registers(ctx, 36, 1, regs) == 1 && regs[0] == 650);
  check("FC06 beyond the limit: exception 03",
        modbus_write_register(ctx, 37, 15001) == -1 && errno == EMBXILVAL);
  check("FC03 one address of a block: exception 02",
        modbus_read_registers(ctx, 300, 1, regs) == -1 && errno == EMBXILADD);
  check("FC03 product code block", modbus_read_registers(ctx, 300, 2, regs) == 2);
  check("FC16 not supported: exception 01",
        modbus_mask_write_register(ctx, 36, 0xFFFF, 0) == -1 && errno == EMBXILFUN);
  uint8_t id[32] = {0};
  const int n = modbus_report_slave_id(ctx, sizeof id, id);
  /* The SM unit answers FC11 with two bytes and no byte count; libmodbus expects a count and
   * takes the first byte (0x01) for it: it still returns without error. */
  check("FC11 answered", n >= 0);
  /* Log out: write the password ("password", NUL padded) to 100..107 (SM unit §10). */
  const uint16_t password[8] = {0x7061, 0x7373, 0x776F, 0x7264, 0, 0, 0, 0};
  check("FC10 logout with the password", modbus_write_registers(ctx, 100, 8, password) == 8);
  check("FC04 login status: logged out",
        modbus_read_input_registers(ctx, 300, 1, regs) == 1 && regs[0] == 0x0000);
  check("FC06 while logged out: exception 04 (login error)",
        modbus_write_register(ctx, 36, 700) == -1 && errno == EMBXSFAIL);
  modbus_close(ctx);
  modbus_free(ctx);
  return failures == 0 ? 0 : 1;
}
