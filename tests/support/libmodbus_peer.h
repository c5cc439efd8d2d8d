/* What the libmodbus peers of the tests share (tests/interop/libmodbus_client.c,
 * tests/firmware/libmodbus_generic.c): the checks' tally and the master's port, 9600 8E1,
 * slave 1, a one-second response timeout (or Modbus TCP to a gateway). */
#ifndef MOTIONBUS_TESTS_LIBMODBUS_PEER_H
#define MOTIONBUS_TESTS_LIBMODBUS_PEER_H

#include <modbus.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

static void check(const char* name, int condition) {
  printf("%s %s\n", condition ? "ok  " : "FAIL", name);
  if (!condition) {
    ++failures;
  }
}

/* The master on `device`, or NULL (said on stderr); `tcp:PORT` is a Modbus TCP client of
 * 127.0.0.1:PORT instead (a gateway in front of the device), with a three-second timeout. */
static modbus_t* open_master(const char* device) {
  const int tcp = strncmp(device, "tcp:", 4) == 0;
  modbus_t* ctx =
      tcp ? modbus_new_tcp("127.0.0.1", atoi(device + 4)) : modbus_new_rtu(device, 9600, 'E', 8, 1);
  if (ctx == NULL || modbus_connect(ctx) != 0) {
    fprintf(stderr, "cannot open %s\n", device);
    if (ctx != NULL) {
      modbus_free(ctx);
    }
    return NULL;
  }
  modbus_set_response_timeout(ctx, tcp ? 3 : 1, 0);
  modbus_set_slave(ctx, 1);
  return ctx;
}

#endif
