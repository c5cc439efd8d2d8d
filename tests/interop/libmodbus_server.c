/* A libmodbus RTU server (a third-party Modbus slave) for the library's client side.
 * Usage: libmodbus_server DEVICE PARITY. Slave 1; 100 coils, inputs and registers; holding
 * register i holds 3*i, input register i holds 1000+i, coil i is on when i is odd. Serves until
 * killed. */
#include <errno.h>
#include <modbus.h>
#include <stdio.h>

int main(int argc, char** argv) {
  if (argc < 3) {
    return 2;
  }
  modbus_t* ctx = modbus_new_rtu(argv[1], 9600, argv[2][0], 8, 1);
  if (ctx == NULL || modbus_set_slave(ctx, 1) != 0 || modbus_connect(ctx) != 0) {
    fprintf(stderr, "cannot open %s\n", argv[1]);
    return 1;
  }
  modbus_mapping_t* map = modbus_mapping_new(100, 100, 100, 100);
  for (int i = 0; i < 100; ++i) {
    map->tab_registers[i] = (uint16_t)(3 * i);
    map->tab_input_registers[i] = (uint16_t)(1000 + i);
    map->tab_bits[i] = (uint8_t)(i % 2);
    map->tab_input_bits[i] = (uint8_t)(i % 3 == 0);
  }
  uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH];
  for (;;) {
    const int rc = modbus_receive(ctx, query);
    if (rc > 0) {
      modbus_reply(ctx, query, rc, map);
    } else if (rc == -1 && errno != EMBBADCRC && errno != ETIMEDOUT && errno != EMBBADDATA) {
      break;
    }
  }
  modbus_mapping_free(map);
  modbus_close(ctx);
  modbus_free(ctx);
  return 0;
}
