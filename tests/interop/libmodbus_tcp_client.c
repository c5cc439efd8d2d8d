/* libmodbus's TCP client (modbus_new_tcp) through `motionbus gateway` to `motionbus serve
 * sm-unit` on a pty (tests/interop/run_gateway_interop.sh). Usage: libmodbus_tcp_client PORT
 * TIMEOUT_MS. Exit 0 when every check holds. */
#include <errno.h>
#include <modbus.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "libmodbus_peer.h"

static double now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1000.0 + (double)t.tv_nsec / 1e6;
}

int main(int argc, char** argv) {
  if (argc < 3) {
    return 2;
  }
  const int timeout_ms = atoi(argv[2]);
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", atoi(argv[1]));
  if (ctx == NULL || modbus_connect(ctx) != 0) {
    fprintf(stderr, "cannot connect to the gateway\n");
    return 1;
  }
  modbus_set_response_timeout(ctx, 3, 0);
  modbus_set_slave(ctx, 1);
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
  const uint16_t two[2] = {6000, 20};
  check("FC10 two settings", modbus_write_registers(ctx, 37, 2, two) == 2);
  check("FC05 warning reset", modbus_write_bit(ctx, 100, 1) == 1);
  uint8_t id[32] = {0};
  check("FC11 answered", modbus_report_slave_id(ctx, sizeof id, id) >= 0);
  modbus_set_slave(ctx, 5);
  const double start = now_ms();
  const int rc = modbus_read_registers(ctx, 36, 1, regs);
  const double took = now_ms() - start;
  check("unit 5 silent: exception 0B (EMBXGTAR)", rc == -1 && errno == EMBXGTAR);
  printf("     0B after %.0f ms (timeout %d ms)\n", took, timeout_ms);
  check("0B within the timeout and its margin",
        took >= timeout_ms * 0.9 && took <= timeout_ms + 500.0);
  /* libmodbus takes 0..247 and 255 (MODBUS_TCP_SLAVE) over TCP: 255 has no path on a line */
  modbus_set_slave(ctx, MODBUS_TCP_SLAVE);
  check("unit 255: exception 0A (EMBXGPATH)",
        modbus_read_registers(ctx, 36, 1, regs) == -1 && errno == EMBXGPATH);
  modbus_close(ctx);
  modbus_free(ctx);
  return failures == 0 ? 0 : 1;
}
