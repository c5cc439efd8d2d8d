/* libmodbus's value helpers (as the host's libmodbus ships them), as text for
 * tests/interop/values_check.py. Reads lines from stdin, answers one line each:
 *   set HEXBITS32        -> "abcd R0 R1 badc R0 R1 cdab R0 R1 dcba R0 R1 float R0 R1": what
 *                           modbus_set_float_abcd/badc/cdab/dcba and modbus_set_float write for
 *                           the float with these bits
 *   get R0 R1            -> "abcd BITS badc BITS cdab BITS dcba BITS float BITS": what
 *                           modbus_get_float_* and modbus_get_float read
 *   set32 HEXBITS        -> "R0 R1": MODBUS_SET_INT32_TO_INT16
 *   get32 R0 R1          -> HEXBITS: MODBUS_GET_INT32_FROM_INT16
 *   set64 HEXBITS        -> "R0 R1 R2 R3": MODBUS_SET_INT64_TO_INT16
 *   get64 R0 R1 R2 R3    -> HEXBITS: MODBUS_GET_INT64_FROM_INT16 */
#include <inttypes.h>
#include <modbus.h>
#include <stdio.h>
#include <string.h>

static float float_of(uint32_t bits) {
  float f;
  memcpy(&f, &bits, sizeof f);
  return f;
}
static uint32_t bits_of(float f) {
  uint32_t bits;
  memcpy(&bits, &f, sizeof bits);
  return bits;
}

int main(void) {
  char line[256];
  while (fgets(line, sizeof line, stdin) != NULL) {
    uint16_t r[4] = {0, 0, 0, 0};
    unsigned a, b, c, d;
    uint64_t x64;
    uint32_t x32;
    if (sscanf(line, "set32 %" SCNx32, &x32) == 1) {
      MODBUS_SET_INT32_TO_INT16(r, 0, x32);
      printf("%04x %04x\n", r[0], r[1]);
    } else if (sscanf(line, "get32 %x %x", &a, &b) == 2) {
      r[0] = (uint16_t)a;
      r[1] = (uint16_t)b;
      printf("%" PRIx32 "\n", (uint32_t)MODBUS_GET_INT32_FROM_INT16(r, 0));
    } else if (sscanf(line, "set64 %" SCNx64, &x64) == 1) {
      MODBUS_SET_INT64_TO_INT16(r, 0, x64);
      printf("%04x %04x %04x %04x\n", r[0], r[1], r[2], r[3]);
    } else if (sscanf(line, "get64 %x %x %x %x", &a, &b, &c, &d) == 4) {
      r[0] = (uint16_t)a;
      r[1] = (uint16_t)b;
      r[2] = (uint16_t)c;
      r[3] = (uint16_t)d;
      printf("%" PRIx64 "\n", (uint64_t)MODBUS_GET_INT64_FROM_INT16(r, 0));
    } else if (sscanf(line, "set %" SCNx32, &x32) == 1) {
      const float f = float_of(x32);
      modbus_set_float_abcd(f, r);
      printf("abcd %04x %04x ", r[0], r[1]);
      modbus_set_float_badc(f, r);
      printf("badc %04x %04x ", r[0], r[1]);
      modbus_set_float_cdab(f, r);
      printf("cdab %04x %04x ", r[0], r[1]);
      modbus_set_float_dcba(f, r);
      printf("dcba %04x %04x ", r[0], r[1]);
      modbus_set_float(f, r);
      printf("float %04x %04x\n", r[0], r[1]);
    } else if (sscanf(line, "get %x %x", &a, &b) == 2) {
      r[0] = (uint16_t)a;
      r[1] = (uint16_t)b;
      printf("abcd %" PRIx32 " badc %" PRIx32 " cdab %" PRIx32 " dcba %" PRIx32 " float %" PRIx32
             "\n",
             bits_of(modbus_get_float_abcd(r)), bits_of(modbus_get_float_badc(r)),
             bits_of(modbus_get_float_cdab(r)), bits_of(modbus_get_float_dcba(r)),
             bits_of(modbus_get_float(r)));
    } else {
      printf("error\n");
    }
    fflush(stdout);
  }
  return 0;
}
