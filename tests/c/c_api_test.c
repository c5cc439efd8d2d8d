/* The C API from C (gcc -std=c99 -Wall -Wextra -Werror -pedantic): every function of
 * motionbus/c.h on real frames, against published check values, frames worked out by hand from
 * the specifications, and independent computations written here (CRCs bit by bit, XOR sums). */
#include <motionbus/c.h>

#include <stdio.h>
#include <string.h>

static int failures = 0;
static int checks = 0;

#define CHECK(cond)                                                \
  do {                                                             \
    ++checks;                                                      \
    if (!(cond)) {                                                 \
      ++failures;                                                  \
      fprintf(stderr, "%s:%d: FAIL %s\n", __FILE__, __LINE__, #cond); \
    }                                                              \
  } while (0)

static const uint8_t check_input[9] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

/* --- independent references ----------------------------------------------------------------- */

/* CRC-16/MODBUS bit by bit (reflected 0xA001, init 0xFFFF). */
static uint16_t ref_crc16(const uint8_t* p, size_t n) {
  uint16_t c = 0xFFFF;
  size_t i;
  int b;
  for (i = 0; i < n; ++i) {
    c ^= p[i];
    for (b = 0; b < 8; ++b) {
      c = (uint16_t)((c & 1U) ? (c >> 1) ^ 0xA001U : c >> 1);
    }
  }
  return c;
}

/* An MSB-first CRC of `width` bits, polynomial `poly` (without x^width), start 0, inverted. */
static unsigned ref_crc_msb(uint64_t bits, unsigned count, unsigned width, unsigned poly) {
  unsigned reg = 0;
  unsigned i;
  const unsigned top = 1U << (width - 1U);
  const unsigned mask = (1U << width) - 1U;
  for (i = 0; i < count; ++i) {
    const unsigned in = (unsigned)((bits >> (count - 1U - i)) & 1U);
    const unsigned fb = ((reg & top) != 0U) ^ in;
    reg = (reg << 1) & mask;
    if (fb) {
      reg ^= poly;
    }
  }
  return (~reg) & mask;
}

static uint8_t xor_of(const uint8_t* p, size_t n) {
  uint8_t x = 0;
  size_t i;
  for (i = 0; i < n; ++i) {
    x = (uint8_t)(x ^ p[i]);
  }
  return x;
}

/* An RTU ADU with the reference CRC. */
static size_t make_adu(uint8_t slave, const uint8_t* pdu, size_t n, uint8_t* out) {
  uint16_t c;
  out[0] = slave;
  memcpy(out + 1, pdu, n);
  c = ref_crc16(out, n + 1U);
  out[n + 1U] = (uint8_t)(c & 0xFFU);
  out[n + 2U] = (uint8_t)(c >> 8);
  return n + 3U;
}

/* --- errors and CRCs ------------------------------------------------------------------------- */
static void test_errors_and_crcs(void) {
  const uint8_t frame[6] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03};
  CHECK(strcmp(mb_errc_name(MB_OK), "ok") == 0);
  CHECK(strcmp(mb_errc_name(MB_CRC_MISMATCH), "crc_mismatch") == 0);
  CHECK(strcmp(mb_errc_name(MB_TFORMAT_PARITY), "parity") == 0);
  CHECK(strcmp(mb_errc_name(MB_MODBUS_QUANTITY), "illegal_quantity") == 0);
  CHECK(strcmp(mb_errc_name(MB_BISS_NO_ACK), "no_ack") == 0);
  CHECK(strcmp(mb_errc_name(MB_BISS_EDS), "invalid_eds") == 0);
  CHECK(strcmp(mb_errc_name(200), "unknown") == 0);
  CHECK(strcmp(mb_errc_name(-1), "unknown") == 0);

  /* published check values (CRC catalogue), and the references */
  CHECK(mb_crc16_modbus(check_input, 9) == 0x4B37);
  CHECK(mb_crc16_modbus(frame, 6) == 0x8776); /* Modbus over Serial Line, Appendix B example */
  CHECK(mb_crc16_modbus(frame, 6) == ref_crc16(frame, 6));
  CHECK(mb_crc16_modbus(NULL, 0) == 0xFFFF);
  CHECK(mb_crc8_tformat(check_input, 9) == 0x31);
  CHECK(mb_crc8_tformat(check_input, 9) == xor_of(check_input, 9));
  {
    /* "123456789" as 72 bits does not fit one call: the bytes' CRC6 check value 0x2E comes
     * from the C++ suite; here the bit-field form against the reference, any length */
    uint64_t v = 0x0123456789ABCDEFULL;
    unsigned n;
    for (n = 1; n <= 64; ++n) {
      const uint64_t bits = n == 64 ? v : (v & ((1ULL << n) - 1U));
      CHECK(mb_crc6_biss(bits, n) == ref_crc_msb(bits, n, 6, 0x03));
      CHECK(mb_crc4_biss(bits, n) == ref_crc_msb(bits, n, 4, 0x03));
    }
    CHECK(mb_crc6_biss(v, 100) == mb_crc6_biss(v, 64)); /* clamped to 64 bits */
  }
}

/* --- T-format -------------------------------------------------------------------------------- */
static void test_tformat_codec(void) {
  uint8_t out[8];
  size_t n = 99;
  mb_tformat_response r;
  mb_tformat_request q;
  mb_result res;
  mb_tformat_options opt = mb_tformat_default_options();
  /* an ID3 response: ABS 0x01ABCD, ENID 0x11, ABM 0x4321, ALMC 0 (spec §6.3, Figure 3) */
  uint8_t id3[11] = {0x1A, 0x00, 0xCD, 0xAB, 0x01, 0x11, 0x21, 0x43, 0x00, 0x00, 0x00};
  id3[10] = xor_of(id3, 10);

  CHECK(opt.single_turn_bits == 17 && opt.multi_turn_bits == 16 && opt.check_unused_bits &&
        !opt.resolution_from_enid);

  /* requests: CF = sync 010, the Data ID, its parity (spec §6.3.1) */
  CHECK(mb_tformat_encode_request(MB_TFORMAT_ID3, 0, 0, out, sizeof out, &n) == MB_OK);
  CHECK(n == 1 && out[0] == 0x1A);
  CHECK(mb_tformat_encode_request(MB_TFORMAT_ID0, 0, 0, out, sizeof out, &n) == MB_OK);
  CHECK(n == 1 && out[0] == 0x02);
  CHECK(mb_tformat_encode_request(MB_TFORMAT_ID7, 0, 0, out, sizeof out, &n) == MB_OK);
  CHECK(n == 1 && out[0] == 0xBA);
  CHECK(mb_tformat_encode_request(MB_TFORMAT_IDD, 5, 0, out, sizeof out, &n) == MB_OK);
  CHECK(n == 3 && out[0] == 0xEA && out[1] == 0x05 && out[2] == (0xEA ^ 0x05));
  CHECK(mb_tformat_encode_request(MB_TFORMAT_ID6, 3, 0x55, out, sizeof out, &n) == MB_OK);
  CHECK(n == 4 && out[0] == 0x32 && out[1] == 0x03 && out[2] == 0x55 && out[3] == 0x64);
  CHECK(mb_tformat_encode_request(0x4, 0, 0, out, sizeof out, &n) == MB_TFORMAT_UNKNOWN_DATA_ID);
  CHECK(n == 0);
  CHECK(mb_tformat_encode_request(MB_TFORMAT_IDD, 128, 0, out, sizeof out, &n) ==
        MB_OUT_OF_RANGE);
  CHECK(mb_tformat_encode_request(MB_TFORMAT_ID6, 3, 1, out, 3, &n) == MB_BUFFER_TOO_SMALL);
  CHECK(mb_tformat_encode_request(MB_TFORMAT_ID3, 0, 0, out, sizeof out, NULL) == MB_OK);

  /* the ID3 response */
  res = mb_tformat_decode_response(id3, sizeof id3, NULL, &r);
  CHECK(res.status == MB_COMPLETE && res.error == MB_OK && res.count == 11);
  CHECK(r.id == MB_TFORMAT_ID3 && r.cf == 0x1A && r.sf == 0 && r.abs == 0x01ABCD &&
        r.enid == 0x11 && r.abm == 0x4321 && r.almc == 0 && r.crc == id3[10]);
  /* fewer bytes: incomplete, the rest needed */
  res = mb_tformat_decode_response(id3, 4, NULL, &r);
  CHECK(res.status == MB_INCOMPLETE && res.count == 7);
  res = mb_tformat_decode_response(NULL, 0, NULL, &r);
  CHECK(res.status == MB_INCOMPLETE && res.count >= 1);
  /* a bad CRC: failed, evidence = computed and received */
  id3[10] ^= 0xFF;
  res = mb_tformat_decode_response(id3, sizeof id3, NULL, &r);
  CHECK(res.status == MB_FAILED && res.error == MB_CRC_MISMATCH && res.count == 1);
  CHECK(res.expected == (uint32_t)(id3[10] ^ 0xFF) && res.received == id3[10]);
  id3[10] ^= 0xFF;
  /* a bad parity, a bad sync code */
  {
    const uint8_t parity[1] = {0x1A | 0x80};
    const uint8_t sync[1] = {0x1B};
    res = mb_tformat_decode_response(parity, 1, NULL, &r);
    CHECK(res.status == MB_FAILED && res.error == MB_TFORMAT_PARITY);
    res = mb_tformat_decode_response(sync, 1, NULL, &r);
    CHECK(res.status == MB_FAILED && res.error == MB_TFORMAT_SYNC_CODE);
  }
  /* ABS above 17 bits: out of range by default, accepted with 23 bits or unchecked */
  {
    uint8_t wide[11] = {0x1A, 0x00, 0xFF, 0xFF, 0x7F, 0x17, 0x01, 0x00, 0x00, 0x00, 0x00};
    wide[10] = xor_of(wide, 10);
    res = mb_tformat_decode_response(wide, 11, NULL, &r);
    CHECK(res.status == MB_FAILED && res.error == MB_OUT_OF_RANGE);
    opt.single_turn_bits = 23;
    res = mb_tformat_decode_response(wide, 11, &opt, &r);
    CHECK(res.status == MB_COMPLETE && r.abs == 0x7FFFFF && r.abm == 1);
    opt = mb_tformat_default_options();
    opt.resolution_from_enid = 1; /* ENID 0x17: 23 bits */
    res = mb_tformat_decode_response(wide, 11, &opt, &r);
    CHECK(res.status == MB_COMPLETE && r.abs == 0x7FFFFF);
    opt = mb_tformat_default_options();
    opt.check_unused_bits = 0;
    res = mb_tformat_decode_response(wide, 11, &opt, NULL);
    CHECK(res.status == MB_COMPLETE);
    opt = mb_tformat_default_options();
  }
  /* checked against the request */
  {
    const uint8_t id3_request[1] = {0x1A};
    const uint8_t id0_request[1] = {0x02};
    res = mb_tformat_decode_response_for(id3_request, 1, id3, 11, NULL, &r);
    CHECK(res.status == MB_COMPLETE && r.abs == 0x01ABCD);
    res = mb_tformat_decode_response_for(id0_request, 1, id3, 11, NULL, &r);
    CHECK(res.status == MB_FAILED && res.error == MB_TFORMAT_CF_MISMATCH &&
          res.expected == 0x02 && res.received == 0x1A);
    res = mb_tformat_decode_response_for(NULL, 0, id3, 11, NULL, &r);
    CHECK(res.status == MB_FAILED && res.error == MB_INVALID_ARGUMENT);
  }
  /* the encoder's side: requests decoded, responses encoded and decoded back */
  {
    const uint8_t eeprom_write[4] = {0x32, 0x03, 0x55, 0x64};
    uint8_t bad[4] = {0x32, 0x03, 0x55, 0x65};
    uint8_t built[11];
    mb_tformat_response v;
    res = mb_tformat_decode_request(eeprom_write, 4, &q);
    CHECK(res.status == MB_COMPLETE && res.count == 4 && q.id == MB_TFORMAT_ID6 &&
          q.cf == 0x32 && q.address == 3 && q.edf == 0x55 && q.crc == 0x64);
    res = mb_tformat_decode_request(eeprom_write, 2, &q);
    CHECK(res.status == MB_INCOMPLETE && res.count == 2);
    res = mb_tformat_decode_request(bad, 4, &q);
    CHECK(res.status == MB_FAILED && res.error == MB_CRC_MISMATCH && res.count == 4 &&
          res.expected == 0x64 && res.received == 0x65);
    memset(&v, 0, sizeof v);
    v.id = MB_TFORMAT_ID3;
    v.abs = 0x01ABCD;
    v.enid = 0x11;
    v.abm = 0x4321;
    CHECK(mb_tformat_encode_response(&v, built, sizeof built, &n) == MB_OK);
    CHECK(n == 11 && memcmp(built, id3, 11) == 0);
    v.sf = 0x01; /* reserved SF bit */
    CHECK(mb_tformat_encode_response(&v, built, sizeof built, &n) == MB_RESERVED_BITS);
    CHECK(mb_tformat_encode_response(NULL, built, sizeof built, &n) == MB_INVALID_ARGUMENT);
    memset(&v, 0, sizeof v);
    v.id = MB_TFORMAT_IDD;
    v.address = 9;
    v.edf = 0xA5;
    CHECK(mb_tformat_encode_response(&v, built, sizeof built, &n) == MB_OK);
    CHECK(n == 4 && built[0] == 0xEA && built[1] == 9 && built[2] == 0xA5 &&
          built[3] == (0xEA ^ 9 ^ 0xA5));
    res = mb_tformat_decode_response(built, n, NULL, &r);
    CHECK(res.status == MB_COMPLETE && r.id == MB_TFORMAT_IDD && r.address == 9 &&
          r.edf == 0xA5 && !r.busy);
  }
}

static void test_tformat_receiver(void) {
  static mb_tformat_receiver rx; /* caller-owned storage, in .bss */
  mb_tformat_receiver_options o = mb_tformat_receiver_default_options();
  mb_tformat_response r;
  mb_result res;
  const uint8_t request[1] = {0x1A};
  uint8_t id3[11] = {0x1A, 0x00, 0xCD, 0xAB, 0x01, 0x11, 0x21, 0x43, 0x00, 0x00, 0x00};
  uint8_t line[32];
  size_t i, n, settled = 0;
  id3[10] = xor_of(id3, 10);

  CHECK(sizeof rx == MB_TFORMAT_RECEIVER_SIZE ||
        sizeof rx % MB_STORAGE_ALIGN == 0); /* the union rounds up to its alignment */
  CHECK(!o.echo_expected && o.check_against_request && o.decode.single_turn_bits == 17);

  /* byte by byte: settled at the last byte of the response */
  mb_tformat_receiver_init(&rx, NULL);
  mb_tformat_receiver_sent(&rx, request, 1);
  for (i = 0; i < 11; ++i) {
    if (mb_tformat_receiver_put(&rx, id3[i])) {
      ++settled;
      CHECK(i == 10);
    }
  }
  CHECK(settled == 1);
  res = mb_tformat_receiver_result(&rx, &r);
  CHECK(res.status == MB_COMPLETE && r.abs == 0x01ABCD && r.abm == 0x4321);
  CHECK(mb_tformat_receiver_pending(&rx) == 0);

  /* half duplex: the echo of the request skipped, garbage dropped, the response found */
  o.echo_expected = 1;
  mb_tformat_receiver_init(&rx, &o);
  mb_tformat_receiver_sent(&rx, request, 1);
  n = 0;
  line[n++] = 0x1A; /* the echo */
  memcpy(line + n, id3, 11);
  n += 11;
  res = mb_tformat_receiver_feed(&rx, line, n, &r);
  CHECK(res.status == MB_COMPLETE && res.count == 12 && r.abm == 0x4321);
  CHECK(mb_tformat_receiver_echoes_skipped(&rx) == 1);
  CHECK(!mb_tformat_receiver_echo_missed(&rx));
  res = mb_tformat_receiver_feed(&rx, NULL, 0, &r);
  CHECK(res.status == MB_INCOMPLETE);

  /* a response without the echo expected: delivered, and said so */
  mb_tformat_receiver_sent(&rx, request, 1);
  res = mb_tformat_receiver_feed(&rx, id3, 11, &r);
  CHECK(res.status == MB_COMPLETE && r.abs == 0x01ABCD);
  CHECK(mb_tformat_receiver_echo_missed(&rx));

  /* garbage, then a corrupted frame, then a good one: the failure, then the frame */
  mb_tformat_receiver_init(&rx, NULL);
  mb_tformat_receiver_sent(&rx, request, 1);
  n = 0;
  line[n++] = 0xFF; /* no CF */
  memcpy(line + n, id3, 11);
  line[n + 10] ^= 0x01; /* bad CRC */
  n += 11;
  memcpy(line + n, id3, 11);
  n += 11;
  res = mb_tformat_receiver_feed(&rx, line, n, &r);
  CHECK(res.status == MB_FAILED && res.error == MB_CRC_MISMATCH);
  i = res.count;
  res = mb_tformat_receiver_feed(&rx, line + i, n - i, &r);
  CHECK(res.status == MB_COMPLETE && r.abs == 0x01ABCD);
  CHECK(mb_tformat_receiver_dropped(&rx) >= 2);

  /* a frame cut short by the line's silence */
  mb_tformat_receiver_sent(&rx, request, 1);
  for (i = 0; i < 5; ++i) {
    CHECK(!mb_tformat_receiver_put(&rx, id3[i]));
  }
  CHECK(mb_tformat_receiver_pending(&rx) == 5);
  res = mb_tformat_receiver_idle(&rx);
  CHECK(res.status == MB_FAILED && res.error == MB_TRUNCATED && res.count == 5);
  res = mb_tformat_receiver_idle(&rx);
  CHECK(res.status == MB_INCOMPLETE);

  /* the response to another request: a CF mismatch, reported by put() */
  {
    const uint8_t id0_request[1] = {0x02};
    mb_tformat_receiver_sent(&rx, id0_request, 1);
    settled = 0;
    for (i = 0; i < 11; ++i) {
      settled += mb_tformat_receiver_put(&rx, id3[i]) ? 1U : 0U;
    }
    CHECK(settled == 1);
    res = mb_tformat_receiver_result(&rx, NULL);
    CHECK(res.status == MB_FAILED && res.error == MB_TFORMAT_CF_MISMATCH);
    /* unchecked: delivered */
    o = mb_tformat_receiver_default_options();
    o.check_against_request = 0;
    o.decode.single_turn_bits = 20;
    mb_tformat_receiver_init(&rx, &o);
    mb_tformat_receiver_sent(&rx, id0_request, 1);
    res = mb_tformat_receiver_feed(&rx, id3, 11, &r);
    CHECK(res.status == MB_COMPLETE && r.id == MB_TFORMAT_ID3);
  }
}

/* --- Modbus: the server ------------------------------------------------------------------------
 * The device of the firmware images: 100 coils, discrete input i on when i % 3 == 0, 100 holding
 * registers, input register i = 1000 + i. */
typedef struct device {
  uint8_t coils[13];
  uint16_t holding[100];
  unsigned calls;
} device;

static int fits(uint16_t address, uint16_t quantity) {
  return (unsigned)address + quantity <= 100U;
}
static uint8_t read_coils(uint16_t address, uint16_t quantity, uint8_t* packed, void* context) {
  device* d = (device*)context;
  uint16_t i;
  ++d->calls;
  if (!fits(address, quantity)) {
    return 2;
  }
  for (i = 0; i < quantity; ++i) {
    const unsigned a = (unsigned)address + i;
    if ((d->coils[a / 8] >> (a % 8)) & 1U) {
      packed[i / 8] = (uint8_t)(packed[i / 8] | (1U << (i % 8)));
    }
  }
  return 0;
}
static uint8_t read_discrete(uint16_t address, uint16_t quantity, uint8_t* packed, void* context) {
  uint16_t i;
  ++((device*)context)->calls;
  if (!fits(address, quantity)) {
    return 2;
  }
  for (i = 0; i < quantity; ++i) {
    if (((unsigned)address + i) % 3U == 0U) {
      packed[i / 8] = (uint8_t)(packed[i / 8] | (1U << (i % 8)));
    }
  }
  return 0;
}
static uint8_t read_holding(uint16_t address, uint16_t quantity, uint16_t* out, void* context) {
  device* d = (device*)context;
  ++d->calls;
  if (!fits(address, quantity)) {
    return 2;
  }
  memcpy(out, d->holding + address, quantity * sizeof *out);
  return 0;
}
static uint8_t read_input(uint16_t address, uint16_t quantity, uint16_t* out, void* context) {
  uint16_t i;
  ++((device*)context)->calls;
  if (!fits(address, quantity)) {
    return 2;
  }
  for (i = 0; i < quantity; ++i) {
    out[i] = (uint16_t)(1000U + address + i);
  }
  return 0;
}
static void set_coil(device* d, unsigned a, int on) {
  const uint8_t bit = (uint8_t)(1U << (a % 8));
  d->coils[a / 8] = (uint8_t)(on ? (d->coils[a / 8] | bit) : (d->coils[a / 8] & ~bit));
}
static uint8_t write_coil(uint16_t address, bool on, void* context) {
  ++((device*)context)->calls;
  if (!fits(address, 1)) {
    return 2;
  }
  set_coil((device*)context, address, on);
  return 0;
}
static uint8_t write_register(uint16_t address, uint16_t value, void* context) {
  ++((device*)context)->calls;
  if (!fits(address, 1)) {
    return 2;
  }
  ((device*)context)->holding[address] = value;
  return 0;
}
static uint8_t write_coils(uint16_t address, uint16_t quantity, const uint8_t* packed,
                           void* context) {
  uint16_t i;
  ++((device*)context)->calls;
  if (!fits(address, quantity)) {
    return 2;
  }
  for (i = 0; i < quantity; ++i) {
    set_coil((device*)context, (unsigned)address + i, (packed[i / 8] >> (i % 8)) & 1U);
  }
  return 0;
}
static uint8_t write_registers(uint16_t address, uint16_t quantity, const uint16_t* values,
                               void* context) {
  device* d = (device*)context;
  ++d->calls;
  if (!fits(address, quantity)) {
    return 2;
  }
  memcpy(d->holding + address, values, quantity * sizeof *values);
  return 0;
}
static uint8_t report_id(uint8_t* out, size_t capacity, size_t* size, void* context) {
  static const char id[] = "\x4D\xFFmotionbus";
  (void)context;
  if (capacity < sizeof id) {
    return 4;
  }
  out[0] = (uint8_t)(sizeof id - 1U);
  memcpy(out + 1, id, sizeof id - 1U);
  *size = sizeof id;
  return 0;
}

/* Serves request PDU `pdu` to slave 1 through the framer, byte by byte; the response PDU (its
 * address and CRC checked) in `response`, its size returned (0: no response). */
static size_t serve(mb_modbus_server_framer* fr, const mb_modbus_callbacks* cb, uint8_t to,
                    const uint8_t* pdu, size_t n, uint8_t* response) {
  uint8_t adu[MB_MODBUS_MAX_ADU_SIZE];
  uint8_t out[MB_MODBUS_MAX_ADU_SIZE];
  const size_t size = make_adu(to, pdu, n, adu);
  size_t i, written = 0, frames = 0;
  mb_modbus_frame f;
  for (i = 0; i < size; ++i) {
    if (mb_modbus_server_framer_put(fr, adu[i])) {
      const mb_result r = mb_modbus_server_framer_result(fr, &f);
      CHECK(r.status == MB_COMPLETE && i == size - 1U);
      if (r.status == MB_COMPLETE) {
        ++frames;
        CHECK(mb_modbus_serve_frame(cb, 1, &f, out, sizeof out, &written) == MB_OK);
      }
    }
  }
  if (frames == 0) { /* no length rule: the silence ends it */
    const mb_result r = mb_modbus_server_framer_idle(fr, &f);
    if (r.status == MB_COMPLETE) {
      CHECK(mb_modbus_serve_frame(cb, 1, &f, out, sizeof out, &written) == MB_OK);
    }
  }
  if (written == 0) {
    return 0;
  }
  CHECK(written >= 5 && out[0] == 1 && ref_crc16(out, written) == 0);
  memcpy(response, out + 1, written - 3U);
  return written - 3U;
}

static void test_modbus_server(void) {
  static mb_modbus_server_framer fr;
  static device dev;
  mb_modbus_callbacks cb;
  mb_modbus_framer_options fo;
  uint8_t rsp[MB_MODBUS_MAX_PDU_SIZE];
  size_t n;
  memset(&cb, 0, sizeof cb);
  cb.read_coils = read_coils;
  cb.read_discrete_inputs = read_discrete;
  cb.read_holding_registers = read_holding;
  cb.read_input_registers = read_input;
  cb.write_single_coil = write_coil;
  cb.write_single_register = write_register;
  cb.write_multiple_coils = write_coils;
  cb.write_multiple_registers = write_registers;
  cb.report_server_id = report_id;
  cb.context = &dev;
  fo.address = 1;
  fo.last_address = 0;
  fo.length_only = 0;
  mb_modbus_server_framer_init(&fr, &fo);

  { /* FC06 then FC03: 36 := 700 read back */
    const uint8_t w[5] = {0x06, 0x00, 36, 0x02, 0xBC};
    const uint8_t r[5] = {0x03, 0x00, 36, 0x00, 0x01};
    n = serve(&fr, &cb, 1, w, 5, rsp);
    CHECK(n == 5 && memcmp(rsp, w, 5) == 0);
    n = serve(&fr, &cb, 1, r, 5, rsp);
    CHECK(n == 4 && rsp[0] == 0x03 && rsp[1] == 2 && rsp[2] == 0x02 && rsp[3] == 0xBC);
  }
  { /* FC04: input registers 1000 + i */
    const uint8_t r[5] = {0x04, 0x00, 10, 0x00, 0x02};
    n = serve(&fr, &cb, 1, r, 5, rsp);
    CHECK(n == 6 && rsp[1] == 4 && rsp[2] == 0x03 && rsp[3] == 0xF2 && rsp[4] == 0x03 &&
          rsp[5] == 0xF3);
  }
  { /* FC05 on coil 3, FC0F coils 8..17, FC01 reads them; FC02 discrete inputs */
    const uint8_t c5[5] = {0x05, 0x00, 3, 0xFF, 0x00};
    const uint8_t c15[8] = {0x0F, 0x00, 8, 0x00, 10, 2, 0xA5, 0x02};
    const uint8_t r1[5] = {0x01, 0x00, 0, 0x00, 18};
    const uint8_t r2[5] = {0x02, 0x00, 0, 0x00, 10};
    n = serve(&fr, &cb, 1, c5, 5, rsp);
    CHECK(n == 5 && memcmp(rsp, c5, 5) == 0);
    n = serve(&fr, &cb, 1, c15, 8, rsp);
    CHECK(n == 5 && rsp[0] == 0x0F && rsp[2] == 8 && rsp[4] == 10);
    n = serve(&fr, &cb, 1, r1, 5, rsp);
    CHECK(n == 5 && rsp[1] == 3 && rsp[2] == 0x08 && rsp[3] == 0xA5 && rsp[4] == 0x02);
    n = serve(&fr, &cb, 1, r2, 5, rsp);
    /* inputs 0, 3, 6, 9 on: 0b01001001, 0b10 */
    CHECK(n == 4 && rsp[1] == 2 && rsp[2] == 0x49 && rsp[3] == 0x02);
  }
  { /* FC10, FC16 (mask write), FC17 (write then read) */
    const uint8_t w16[10] = {0x10, 0x00, 50, 0x00, 2, 4, 0x12, 0x34, 0x56, 0x78};
    const uint8_t m[7] = {0x16, 0x00, 50, 0x00, 0xF2, 0x00, 0x25};
    const uint8_t rw[15] = {0x17, 0x00, 50, 0x00, 2, 0x00, 60, 0x00, 2, 4, 0xAB, 0xCD, 0xEF, 0x01};
    n = serve(&fr, &cb, 1, w16, 10, rsp);
    CHECK(n == 5 && rsp[0] == 0x10 && rsp[4] == 2);
    CHECK(dev.holding[50] == 0x1234 && dev.holding[51] == 0x5678);
    n = serve(&fr, &cb, 1, m, 7, rsp);
    CHECK(n == 7 && memcmp(rsp, m, 7) == 0);
    /* Modbus App. Protocol §6.16: (0x1234 AND 0xF2) OR (0x25 AND NOT 0xF2) = 0x0035 */
    CHECK(dev.holding[50] == 0x0035);
    n = serve(&fr, &cb, 1, rw, 14, rsp);
    CHECK(n == 6 && rsp[0] == 0x17 && rsp[1] == 4 && rsp[2] == 0x00 && rsp[3] == 0x35 &&
          rsp[4] == 0x56 && rsp[5] == 0x78);
    CHECK(dev.holding[60] == 0xABCD && dev.holding[61] == 0xEF01);
  }
  { /* FC11 */
    const uint8_t q[1] = {0x11};
    n = serve(&fr, &cb, 1, q, 1, rsp);
    CHECK(n == 13 && rsp[0] == 0x11 && rsp[1] == 11 && rsp[2] == 0x4D && rsp[3] == 0xFF &&
          memcmp(rsp + 4, "motionbus", 9) == 0);
  }
  { /* exceptions: 02 from the device, 03 from the request's limits (no callback), 01 for an
       unknown function after the silence, 01 for a NULL callback */
    const uint8_t beyond[5] = {0x03, 0x00, 99, 0x00, 2};
    const uint8_t too_many[5] = {0x03, 0x00, 0, 0x00, 126};
    const uint8_t unknown[5] = {0x42, 0x00, 0x00, 0x00, 0x00};
    const uint8_t fc05[5] = {0x05, 0x00, 1, 0xFF, 0x00};
    unsigned before;
    n = serve(&fr, &cb, 1, beyond, 5, rsp);
    CHECK(n == 2 && rsp[0] == 0x83 && rsp[1] == 0x02);
    before = dev.calls;
    n = serve(&fr, &cb, 1, too_many, 5, rsp);
    CHECK(n == 2 && rsp[0] == 0x83 && rsp[1] == 0x03 && dev.calls == before);
    n = serve(&fr, &cb, 1, unknown, 5, rsp);
    CHECK(n == 2 && rsp[0] == 0xC2 && rsp[1] == 0x01);
    cb.write_single_coil = NULL;
    n = serve(&fr, &cb, 1, fc05, 5, rsp);
    CHECK(n == 2 && rsp[0] == 0x85 && rsp[1] == 0x01);
    cb.write_single_coil = write_coil;
  }
  { /* FC16 with only the multiple-register writer; FC17 without it: 01 */
    const uint8_t m[7] = {0x16, 0x00, 70, 0xFF, 0xFF, 0x00, 0x00};
    const uint8_t rw[14] = {0x17, 0x00, 50, 0x00, 1, 0x00, 60, 0x00, 1, 2, 0x11, 0x22, 0, 0};
    dev.holding[70] = 0x4242;
    cb.write_single_register = NULL;
    n = serve(&fr, &cb, 1, m, 7, rsp);
    CHECK(n == 7 && dev.holding[70] == 0x4242);
    cb.write_single_register = write_register;
    cb.write_multiple_registers = NULL;
    n = serve(&fr, &cb, 1, rw, 12, rsp);
    CHECK(n == 2 && rsp[0] == 0x97 && rsp[1] == 0x01);
    cb.write_multiple_registers = write_registers;
  }
  { /* a broadcast: executed, not answered; another slave: neither */
    const uint8_t w[5] = {0x06, 0x00, 40, 0x01, 0x02};
    const uint8_t w2[5] = {0x06, 0x00, 41, 0x01, 0x02};
    n = serve(&fr, &cb, 0, w, 5, rsp);
    CHECK(n == 0 && dev.holding[40] == 0x0102);
    n = serve(&fr, &cb, 5, w2, 5, rsp);
    CHECK(n == 0 && dev.holding[41] == 0);
    CHECK(mb_modbus_server_framer_skipped(&fr) == 1);
  }
  { /* garbage before a request: held until the silence, which finds the frame behind it; a
       bad CRC: dropped at the silence; then a request framed by its length (feed) */
    uint8_t line[64];
    const uint8_t r[5] = {0x03, 0x00, 36, 0x00, 0x01};
    size_t m = 0;
    mb_modbus_frame f;
    mb_result res;
    line[m++] = 0xFF;
    line[m++] = 0x13;
    line[m++] = 0x37;
    m += make_adu(1, r, 5, line + m);
    res = mb_modbus_server_framer_feed(&fr, line, m, &f);
    CHECK(res.status == MB_INCOMPLETE && mb_modbus_server_framer_pending(&fr) == m);
    res = mb_modbus_server_framer_idle(&fr, &f);
    CHECK(res.status == MB_COMPLETE && f.slave == 1 && f.pdu_size == 5 &&
          memcmp(f.pdu, r, 5) == 0);
    CHECK(mb_modbus_server_framer_pending(&fr) == 0 && mb_modbus_server_framer_dropped(&fr) >= 3);
    m = make_adu(1, r, 5, line);
    line[m - 1] ^= 0x5A;
    res = mb_modbus_server_framer_feed(&fr, line, m, &f);
    if (res.status == MB_FAILED) { /* the length rule's frame, its CRC wrong */
      CHECK(res.error == MB_CRC_MISMATCH);
      res = mb_modbus_server_framer_feed(&fr, line + res.count, m - res.count, &f);
    }
    CHECK(res.status == MB_INCOMPLETE);
    res = mb_modbus_server_framer_idle(&fr, &f);
    CHECK(res.status != MB_COMPLETE && mb_modbus_server_framer_pending(&fr) == 0);
    m = make_adu(1, r, 5, line);
    res = mb_modbus_server_framer_feed(&fr, line, m, &f);
    CHECK(res.status == MB_COMPLETE && res.count == m && f.pdu_size == 5);
  }
  { /* serve_pdu (TCP) and argument checks */
    const uint8_t r[5] = {0x03, 0x00, 36, 0x00, 0x01};
    uint8_t small[8];
    mb_modbus_frame f;
    CHECK(mb_modbus_serve_pdu(&cb, r, 5, rsp, sizeof rsp, &n) == MB_OK);
    CHECK(n == 4 && rsp[0] == 0x03 && rsp[3] == 0xBC);
    CHECK(mb_modbus_serve_pdu(&cb, NULL, 0, rsp, sizeof rsp, &n) == MB_OK && n == 0);
    CHECK(mb_modbus_serve_pdu(&cb, r, 5, small, sizeof small, &n) == MB_BUFFER_TOO_SMALL);
    CHECK(mb_modbus_serve_pdu(NULL, r, 5, rsp, sizeof rsp, &n) == MB_INVALID_ARGUMENT);
    f.slave = 1;
    f.pdu = r;
    f.pdu_size = 5;
    f.crc = 0;
    CHECK(mb_modbus_serve_frame(&cb, 1, &f, small, sizeof small, &n) == MB_BUFFER_TOO_SMALL);
    CHECK(mb_modbus_serve_frame(&cb, 1, NULL, rsp, sizeof rsp, &n) == MB_INVALID_ARGUMENT);
  }
  { /* a framer for units 1..4, frames ending by length alone */
    const uint8_t r[5] = {0x03, 0x00, 36, 0x00, 0x01};
    uint8_t adu[16];
    const size_t m = make_adu(3, r, 5, adu);
    mb_modbus_frame f;
    mb_result res;
    fo.last_address = 4;
    fo.length_only = 1;
    mb_modbus_server_framer_init(&fr, &fo);
    res = mb_modbus_server_framer_feed(&fr, adu, m, &f);
    CHECK(res.status == MB_COMPLETE && res.count == m && f.slave == 3 && f.pdu_size == 5);
    mb_modbus_server_framer_init(&fr, NULL); /* defaults: address 0 */
    CHECK(mb_modbus_server_framer_pending(&fr) == 0);
  }
}

/* --- Modbus: RTU and the client ----------------------------------------------------------------- */
static void test_modbus_client(void) {
  uint8_t pdu[MB_MODBUS_MAX_PDU_SIZE];
  uint8_t adu[MB_MODBUS_MAX_ADU_SIZE];
  size_t n = 0, m = 0;
  mb_modbus_frame f;
  mb_modbus_response r;
  mb_result res;
  /* the classic request: slave 1, read 10 holding registers from 0: 01 03 00 00 00 0A C5 CD */
  const uint8_t classic[8] = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};

  CHECK(mb_modbus_encode_read(0x03, 0, 10, pdu, sizeof pdu, &n) == MB_OK && n == 5);
  CHECK(mb_modbus_encode_rtu(1, pdu, n, adu, sizeof adu, &m) == MB_OK);
  CHECK(m == 8 && memcmp(adu, classic, 8) == 0);
  CHECK(mb_modbus_encode_rtu(248, pdu, n, adu, sizeof adu, &m) == MB_MODBUS_SLAVE_ADDRESS);
  CHECK(mb_modbus_encode_rtu(1, pdu, 0, adu, sizeof adu, &m) == MB_MODBUS_PDU_LENGTH);
  CHECK(mb_modbus_encode_rtu(1, pdu, n, adu, 7, &m) == MB_BUFFER_TOO_SMALL && m == 0);
  res = mb_modbus_decode_rtu(classic, 8, &f);
  CHECK(res.status == MB_COMPLETE && res.count == 8 && f.slave == 1 && f.pdu_size == 5 &&
        f.pdu == classic + 1 && f.crc == 0xCDC5);
  {
    uint8_t bad[8];
    memcpy(bad, classic, 8);
    bad[7] = 0x00;
    res = mb_modbus_decode_rtu(bad, 8, &f);
    CHECK(res.status == MB_FAILED && res.error == MB_CRC_MISMATCH && res.expected == 0xCDC5 &&
          res.received == 0x00C5);
    res = mb_modbus_decode_rtu(bad, 3, &f);
    CHECK(res.status == MB_FAILED && res.error == MB_MODBUS_PDU_LENGTH);
  }
  CHECK(mb_modbus_encode_read(0x05, 0, 1, pdu, sizeof pdu, &n) == MB_INVALID_ARGUMENT);
  CHECK(mb_modbus_encode_read(0x03, 0, 126, pdu, sizeof pdu, &n) == MB_MODBUS_QUANTITY);
  CHECK(mb_modbus_encode_read(0x01, 0xFFFF, 2, pdu, sizeof pdu, &n) == MB_MODBUS_ADDRESS_OVERFLOW);

  { /* a read of 2 registers and its response */
    uint8_t q[5];
    size_t qn;
    const uint8_t answer[6] = {0x03, 4, 0x12, 0x34, 0xAB, 0xCD};
    const uint8_t exception[2] = {0x83, 0x02};
    const uint8_t short_count[6] = {0x03, 2, 0x12, 0x34, 0xAB, 0xCD};
    CHECK(mb_modbus_encode_read(0x03, 100, 2, q, sizeof q, &qn) == MB_OK);
    CHECK(q[0] == 0x03 && q[1] == 0 && q[2] == 100 && q[3] == 0 && q[4] == 2);
    res = mb_modbus_decode_response_for(q, qn, answer, 6, &r);
    CHECK(res.status == MB_COMPLETE && r.function == 0x03 && !r.exception && r.byte_count == 4 &&
          r.quantity == 2 && r.data == answer + 2 && r.data_size == 4);
    CHECK(mb_modbus_register_at(r.data, 0) == 0x1234 && mb_modbus_register_at(r.data, 1) == 0xABCD);
    res = mb_modbus_decode_response_for(q, qn, exception, 2, &r);
    CHECK(res.status == MB_COMPLETE && r.exception && r.exception_code == 2 && r.function == 3);
    res = mb_modbus_decode_response_for(q, qn, short_count, 6, &r);
    CHECK(res.status == MB_FAILED && res.error == MB_MODBUS_BYTE_COUNT);
    res = mb_modbus_decode_response_for(NULL, 0, answer, 6, &r);
    CHECK(res.status == MB_FAILED && res.error == MB_INVALID_ARGUMENT);
    res = mb_modbus_decode_response_unpaired(answer, 6, &r);
    CHECK(res.status == MB_COMPLETE && r.byte_count == 4 && r.quantity == 2);
  }
  { /* writes: FC05, FC06, FC0F, FC10, FC16, FC17, and their echoes */
    const uint8_t packed[2] = {0xCD, 0x01};
    const uint16_t values[2] = {0x000A, 0x0102};
    uint8_t q[32];
    size_t qn;
    CHECK(mb_modbus_encode_write_single_coil(172, true, q, sizeof q, &qn) == MB_OK);
    CHECK(qn == 5 && q[0] == 0x05 && q[1] == 0 && q[2] == 0xAC && q[3] == 0xFF && q[4] == 0);
    res = mb_modbus_decode_response_for(q, qn, q, qn, &r);
    CHECK(res.status == MB_COMPLETE && r.address == 172 && r.value == 0xFF00);
    CHECK(mb_modbus_encode_write_single_register(1, 3, q, sizeof q, &qn) == MB_OK);
    CHECK(qn == 5 && q[0] == 0x06 && q[2] == 1 && q[4] == 3);
    CHECK(mb_modbus_encode_write_multiple_coils(19, 10, packed, 2, q, sizeof q, &qn) == MB_OK);
    /* Modbus App. Protocol §6.11's example: 0F 00 13 00 0A 02 CD 01 */
    CHECK(qn == 8 && q[0] == 0x0F && q[2] == 0x13 && q[4] == 0x0A && q[5] == 2 && q[6] == 0xCD &&
          q[7] == 0x01);
    CHECK(mb_modbus_encode_write_multiple_coils(19, 10, packed, 1, q, sizeof q, &qn) ==
          MB_MODBUS_BYTE_COUNT);
    CHECK(mb_modbus_encode_write_multiple_registers(1, values, 2, q, sizeof q, &qn) == MB_OK);
    /* §6.12's example: 10 00 01 00 02 04 00 0A 01 02 */
    CHECK(qn == 10 && q[0] == 0x10 && q[2] == 1 && q[4] == 2 && q[5] == 4 && q[7] == 0x0A &&
          q[8] == 1 && q[9] == 2);
    {
      const uint8_t echo[5] = {0x10, 0x00, 0x01, 0x00, 0x02};
      const uint8_t wrong[5] = {0x10, 0x00, 0x02, 0x00, 0x02};
      res = mb_modbus_decode_response_for(q, qn, echo, 5, &r);
      CHECK(res.status == MB_COMPLETE && r.address == 1 && r.quantity == 2);
      res = mb_modbus_decode_response_for(q, qn, wrong, 5, &r);
      CHECK(res.status == MB_FAILED && res.error == MB_MODBUS_MISMATCH);
    }
    CHECK(mb_modbus_encode_write_multiple_registers(1, NULL, 0, q, sizeof q, &qn) ==
          MB_MODBUS_QUANTITY);
    CHECK(mb_modbus_encode_mask_write_register(4, 0xF2, 0x25, q, sizeof q, &qn) == MB_OK);
    /* §6.16's example: 16 00 04 00 F2 00 25 */
    CHECK(qn == 7 && q[0] == 0x16 && q[2] == 4 && q[4] == 0xF2 && q[6] == 0x25);
    res = mb_modbus_decode_response_for(q, qn, q, qn, &r);
    CHECK(res.status == MB_COMPLETE && r.and_mask == 0xF2 && r.or_mask == 0x25);
    CHECK(mb_modbus_encode_read_write_multiple_registers(3, 6, 14, values, 2, q, sizeof q, &qn) ==
          MB_OK);
    CHECK(qn == 14 && q[0] == 0x17 && q[2] == 3 && q[4] == 6 && q[6] == 14 && q[8] == 2 &&
          q[9] == 4 && q[11] == 0x0A);
    CHECK(mb_modbus_encode_read_write_multiple_registers(3, 0, 14, values, 2, q, sizeof q, &qn) ==
          MB_MODBUS_QUANTITY);
    CHECK(mb_modbus_encode_read_write_multiple_registers(3, 6, 14, NULL, 0, q, sizeof q, &qn) ==
          MB_MODBUS_QUANTITY);
    CHECK(mb_modbus_encode_raw(0x11, NULL, 0, q, sizeof q, &qn) == MB_OK && qn == 1 &&
          q[0] == 0x11);
    CHECK(mb_modbus_encode_raw(0x91, NULL, 0, q, sizeof q, &qn) == MB_INVALID_ARGUMENT);
    {
      const uint8_t fc11[5] = {0x11, 3, 0x4D, 0xFF, 0x01};
      res = mb_modbus_decode_response_for(q, 1, fc11, 5, &r);
      CHECK(res.status == MB_COMPLETE && r.byte_count == 3 && r.data_size == 3 &&
            r.data[0] == 0x4D);
    }
  }
  { /* packed bits */
    const uint8_t packed[2] = {0xCD, 0x01};
    CHECK(mb_modbus_bit_at(packed, 0) && !mb_modbus_bit_at(packed, 1) &&
          mb_modbus_bit_at(packed, 2) && mb_modbus_bit_at(packed, 8) &&
          !mb_modbus_bit_at(packed, 9));
  }
}

/* --- BiSS-C --------------------------------------------------------------------------------------- */

/* Writes `n` bits of `v`, MSB first, into MSB-first 32-bit words from bit `*at`. */
static void put_bits(uint32_t* words, size_t* at, uint64_t v, unsigned n) {
  unsigned i;
  for (i = 0; i < n; ++i) {
    const unsigned bit = (unsigned)((v >> (n - 1U - i)) & 1U);
    if (bit) {
      words[*at / 32U] |= 1UL << (31U - (unsigned)(*at % 32U));
    } else {
      words[*at / 32U] &= ~(1UL << (31U - (unsigned)(*at % 32U)));
    }
    ++*at;
  }
}

static void test_biss_frames(void) {
  const mb_biss_layout absys = mb_biss_absys_layout();
  uint32_t words[4] = {0xFFFFFFFFUL, 0xFFFFFFFFUL, 0xFFFFFFFFUL, 0xFFFFFFFFUL};
  size_t at = 0, bits = 0;
  mb_biss_frame f;
  mb_result res;
  const uint32_t position = 0x12345678UL;
  const unsigned crc = ref_crc_msb(((uint64_t)position << 2) | 0x2U, 34, 6, 0x03);

  CHECK(absys.single_turn_bits == 32 && absys.multi_turn_bits == 0 && absys.has_error &&
        absys.has_warning && absys.crc_width == 6 && absys.crc_poly == 0x03 &&
        absys.crc_inverted);
  /* a capture built here (BiSS-C: line delay 1s, Ack 0s, Start 1, CDS, data, nE, nW, CRC6) */
  put_bits(words, &at, 0x3, 2);  /* line delay: 2 idle bits */
  put_bits(words, &at, 0x0, 3);  /* Ack: 3 bits */
  put_bits(words, &at, 0x3, 2);  /* Start, CDS = 1 */
  put_bits(words, &at, position, 32);
  put_bits(words, &at, 0x2, 2);  /* nE = 1 (no error), nW = 0 (warning) */
  put_bits(words, &at, crc, 6);
  put_bits(words, &at, 0x0, 4);  /* the slave's timeout */
  res = mb_biss_decode_frame(words, 4, at, &absys, 1, 0, 0, false, &f);
  CHECK(res.status == MB_COMPLETE && res.count == at - 4U);
  CHECK(f.line_delay == 2 && f.start == 5 && f.cds && f.count == 1);
  CHECK(f.slaves[0].single_turn == position && f.slaves[0].data == position &&
        f.slaves[0].ne && !f.slaves[0].nw && f.slaves[0].crc == crc &&
        f.slaves[0].crc_computed == crc);
  /* the slave side gives the same 47 samples (nothing written after them) */
  {
    uint32_t built[4] = {0, 0, 0, 0};
    mb_biss_slave_values v;
    v.multi_turn = 0;
    v.single_turn = position;
    v.ne = true;
    v.nw = false;
    CHECK(mb_biss_encode_frame(&absys, &v, 2, 3, true, built, 4, &bits) == MB_OK);
    CHECK(bits == at - 4U);
    CHECK(built[0] == words[0] && (built[1] & 0xFFFE0000UL) == (words[1] & 0xFFFE0000UL) &&
          (built[1] & 0x0001FFFFUL) == 0);
    v.single_turn = 0x100000000ULL;
    CHECK(mb_biss_encode_frame(&absys, &v, 2, 3, true, built, 4, &bits) == MB_OUT_OF_RANGE);
    v.single_turn = 0;
    CHECK(mb_biss_encode_frame(&absys, &v, 2, 3, true, built, 1, &bits) == MB_BUFFER_TOO_SMALL);
    CHECK(mb_biss_encode_frame(NULL, &v, 2, 3, true, built, 4, &bits) == MB_INVALID_ARGUMENT);
  }
  /* a bad CRC: failed with the evidence */
  words[1] ^= 1UL << (31U - (unsigned)((at - 5U) % 32U));
  res = mb_biss_decode_frame(words, 4, at, &absys, 1, 0, 0, false, &f);
  CHECK(res.status == MB_FAILED && res.error == MB_CRC_MISMATCH && res.expected == crc &&
        res.received != crc);
  /* cut short: need more bits */
  res = mb_biss_decode_frame(words, 4, 20, &absys, 1, 0, 0, false, &f);
  CHECK(res.status == MB_INCOMPLETE && res.count >= 1);
  /* only idle: no Ack within the bound given */
  {
    const uint32_t idle[2] = {0xFFFFFFFFUL, 0xFFFFFFFFUL};
    res = mb_biss_decode_frame(idle, 2, 64, &absys, 1, 16, 0, false, &f);
    CHECK(res.status == MB_FAILED && res.error == MB_BISS_NO_ACK);
  }
  /* layouts: invalid, an empty or too long chain */
  {
    mb_biss_layout bad = absys;
    bad.crc_width = 17;
    res = mb_biss_decode_frame(words, 4, at, &bad, 1, 0, 0, false, &f);
    CHECK(res.status == MB_FAILED && res.error == MB_BISS_LAYOUT);
    res = mb_biss_decode_frame(words, 4, at, &absys, 0, 0, 0, false, &f);
    CHECK(res.status == MB_FAILED && res.error == MB_INVALID_ARGUMENT);
    res = mb_biss_decode_frame(words, 4, at, &absys, 9, 0, 0, false, &f);
    CHECK(res.status == MB_FAILED && res.error == MB_INVALID_ARGUMENT);
  }
  /* a chain of two (12-bit multi-turn + 13-bit single-turn, then ABSYS), LSB-first words */
  {
    mb_biss_layout chain[2];
    uint32_t msb[4] = {0xFFFFFFFFUL, 0xFFFFFFFFUL, 0xFFFFFFFFUL, 0xFFFFFFFFUL};
    uint32_t lsb[4];
    size_t k, i;
    const uint64_t d1 = ((uint64_t)0xABC << 13) | 0x1234;
    chain[0] = absys;
    chain[0].multi_turn_bits = 12;
    chain[0].single_turn_bits = 13;
    chain[1] = absys;
    at = 0;
    put_bits(msb, &at, 0x1, 1);
    put_bits(msb, &at, 0x0, 1);
    put_bits(msb, &at, 0x2, 2); /* Start, CDS = 0 */
    put_bits(msb, &at, d1, 25);
    put_bits(msb, &at, 0x3, 2);
    put_bits(msb, &at, ref_crc_msb((d1 << 2) | 3U, 27, 6, 0x03), 6);
    put_bits(msb, &at, position, 32);
    put_bits(msb, &at, 0x1, 2); /* nE = 0: error */
    put_bits(msb, &at, ref_crc_msb(((uint64_t)position << 2) | 1U, 34, 6, 0x03), 6);
    for (k = 0; k < 4; ++k) { /* the same samples, first in the least significant bit */
      lsb[k] = 0;
      for (i = 0; i < 32; ++i) {
        if ((msb[k] >> (31U - i)) & 1U) {
          lsb[k] |= 1UL << i;
        }
      }
    }
    res = mb_biss_decode_frame(msb, 4, at, chain, 2, 0, 0, false, &f);
    CHECK(res.status == MB_COMPLETE && f.count == 2 && !f.cds && f.line_delay == 1);
    CHECK(f.slaves[0].multi_turn == 0xABC && f.slaves[0].single_turn == 0x1234 &&
          f.slaves[0].ne && f.slaves[0].nw);
    CHECK(f.slaves[1].single_turn == position && !f.slaves[1].ne);
    CHECK(mb_biss_decode_frame(msb, 4, at, chain, 2, 0, 0, false, NULL).status == MB_COMPLETE);
    res = mb_biss_decode_frame(lsb, 4, at, chain, 2, 0, 0, true, &f);
    CHECK(res.status == MB_COMPLETE && f.slaves[0].multi_turn == 0xABC &&
          f.slaves[1].single_turn == position);
  }
}

/* A slave for the control master, written from the protocol's description (biss/control.hpp,
 * docs/biss.md §3): after the master's S, it answers 0 for the header but for the R and W
 * echoes; then per byte S = 1 (after `waits` wait states), the data bits, ~CRC4, P = 0. */
typedef struct slave {
  uint8_t registers[128];
  unsigned slot; /* 0: waiting for S; header slots 1..18; then per byte: 0 S, 1-8, 9-12, 13 P */
  unsigned header;
  int in_byte;
  unsigned byte_slot;
  uint8_t address;
  uint8_t value;
  unsigned waits;
  unsigned waited;
  int write;
} slave;

static bool slave_step(slave* s, bool cdm) {
  if (!s->in_byte) {
    if (s->slot == 0) {
      if (!cdm) {
        return false;
      }
      s->slot = 1;
      s->header = 1;
      return false;
    }
    s->header = (s->header << 1) | (cdm ? 1U : 0U);
    ++s->slot;
    if (s->slot < 17) {
      return false;
    }
    if (s->slot == 17) { /* R */
      return cdm;
    }
    /* W: the header is complete */
    s->address = (uint8_t)((s->header >> 6) & 0x7F);
    s->write = cdm;
    s->in_byte = 1;
    s->byte_slot = 0;
    s->waited = 0;
    CHECK(((s->header >> 2) & 0xF) == mb_crc4_biss((s->header >> 6) & 0x7FF, 11));
    return cdm;
  }
  if (s->byte_slot == 0) { /* S: ready or a wait state */
    if (!cdm) {
      return false;
    }
    if (s->waited < s->waits) {
      ++s->waited;
      return false;
    }
    s->byte_slot = 1;
    s->value = 0;
    return true;
  }
  if (s->byte_slot <= 8) {
    const unsigned bit = 8U - s->byte_slot;
    bool answer;
    if (s->write) {
      s->value = (uint8_t)(s->value | ((cdm ? 1U : 0U) << bit));
      answer = cdm;
    } else {
      answer = ((s->registers[s->address] >> bit) & 1U) != 0U;
    }
    ++s->byte_slot;
    return answer;
  }
  if (s->byte_slot <= 12) {
    const uint8_t v = s->write ? s->value : s->registers[s->address];
    const unsigned crc = mb_crc4_biss(v, 8);
    const unsigned bit = 12U - s->byte_slot;
    ++s->byte_slot;
    return ((crc >> bit) & 1U) != 0U;
  }
  /* P */
  if (s->write) {
    s->registers[s->address] = s->value;
  }
  ++s->address;
  s->byte_slot = 0;
  s->waited = 0;
  return false;
}

static void test_biss_control(void) {
  static mb_biss_control_master m;
  static slave sl;
  uint8_t got[3] = {0, 0, 0};
  const uint8_t put[2] = {0x5A, 0xC3};
  size_t frames = 0;
  bool cds = false;
  memset(&sl, 0, sizeof sl);
  sl.registers[0x40] = 0xA7;
  sl.registers[0x41] = 0x01;
  sl.registers[0x42] = 0xFE;
  sl.waits = 2;

  mb_biss_control_master_init(&m, 0);
  CHECK(mb_biss_control_master_state(&m) == MB_BISS_CONTROL_IDLE);
  CHECK(mb_biss_control_master_start_read(&m, 8, 0x40, got, 1) == MB_INVALID_ARGUMENT);
  CHECK(mb_biss_control_master_start_read(&m, 0, 0x7F, got, 2) == MB_INVALID_ARGUMENT);
  CHECK(mb_biss_control_master_start_read(&m, 1, 0x40, got, 3) == MB_OK);
  CHECK(mb_biss_control_master_start_read(&m, 1, 0x40, got, 3) == MB_BISS_BUSY);
  while (mb_biss_control_master_state(&m) == MB_BISS_CONTROL_BUSY && frames < 1000) {
    const bool cdm = mb_biss_control_master_step(&m, cds);
    cds = slave_step(&sl, cdm);
    ++frames;
  }
  CHECK(mb_biss_control_master_state(&m) == MB_BISS_CONTROL_DONE);
  CHECK(mb_biss_control_master_error(&m) == MB_OK);
  CHECK(mb_biss_control_master_transferred(&m) == 3);
  CHECK(got[0] == 0xA7 && got[1] == 0x01 && got[2] == 0xFE);
  /* no preamble for a fresh master; 2 wait states before each byte */
  CHECK(mb_biss_control_master_frames(&m) == mb_biss_control_frames_for(3) - 14U + 3U * 2U);
  CHECK(mb_biss_control_frames_for(1) == 14U + 18U + 14U + 1U);

  /* a write: confirmed by the echo */
  memset(&sl.slot, 0, sizeof sl - sizeof sl.registers);
  sl.waits = 0;
  CHECK(mb_biss_control_master_start_write(&m, 1, 0x10, put, 2) == MB_OK);
  frames = 0;
  while (mb_biss_control_master_state(&m) == MB_BISS_CONTROL_BUSY && frames < 1000) {
    const bool cdm = mb_biss_control_master_step(&m, cds);
    cds = slave_step(&sl, cdm);
    ++frames;
  }
  CHECK(mb_biss_control_master_state(&m) == MB_BISS_CONTROL_DONE);
  CHECK(sl.registers[0x10] == 0x5A && sl.registers[0x11] == 0xC3);
  /* no preamble either: the read's last byte ended with 14 slots of CDM = 0 (its data, CRC and
     P slots, and the frame that took the P answer) */
  CHECK(mb_biss_control_master_frames(&m) == mb_biss_control_frames_for(2) - 14U);

  /* nobody answers: not acknowledged */
  frames = 0;
  CHECK(mb_biss_control_master_start_read(&m, 2, 0x00, got, 1) == MB_OK);
  while (mb_biss_control_master_state(&m) == MB_BISS_CONTROL_BUSY && frames < 1000) {
    (void)mb_biss_control_master_step(&m, false);
    ++frames;
  }
  CHECK(mb_biss_control_master_state(&m) == MB_BISS_CONTROL_FAILED);
  CHECK(mb_biss_control_master_error(&m) == MB_BISS_NOT_ACKNOWLEDGED);

  /* abort, and a small wait limit */
  mb_biss_control_master_init(&m, 3);
  CHECK(mb_biss_control_master_start_read(&m, 0, 0x00, got, 1) == MB_OK);
  (void)mb_biss_control_master_step(&m, false);
  mb_biss_control_master_abort(&m);
  CHECK(mb_biss_control_master_state(&m) == MB_BISS_CONTROL_FAILED &&
        mb_biss_control_master_error(&m) == MB_BISS_ABORTED);
  CHECK(!mb_biss_control_master_step(&m, false));
}

/* Optional outputs left NULL, absent inputs, and the callback table's combinations. */
static void test_null_and_absent(void) {
  static mb_modbus_server_framer fr;
  static device dev;
  const uint8_t id0_request[1] = {0x02};
  const uint8_t eeprom_read[3] = {0xEA, 0x05, 0xEF};
  uint8_t id0[6] = {0x02, 0x00, 0x34, 0x12, 0x00, 0x00};
  const uint8_t classic[8] = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
  const uint8_t answer[6] = {0x03, 4, 0x12, 0x34, 0xAB, 0xCD};
  const mb_biss_layout absys = mb_biss_absys_layout();
  mb_biss_layout two[2];
  mb_biss_slave_values v;
  mb_modbus_callbacks cb;
  mb_modbus_frame f;
  uint8_t rsp[MB_MODBUS_MAX_PDU_SIZE];
  uint32_t words[4] = {0, 0, 0, 0};
  size_t n = 0, bits = 0;
  mb_result res;
  id0[5] = xor_of(id0, 5);

  CHECK(mb_tformat_encode_request(MB_TFORMAT_ID3, 0, 0, NULL, 0, &n) == MB_BUFFER_TOO_SMALL);
  CHECK(mb_tformat_decode_response(id0, 6, NULL, NULL).status == MB_COMPLETE);
  CHECK(mb_tformat_decode_response_for(id0_request, 1, id0, 6, NULL, NULL).status == MB_COMPLETE);
  CHECK(mb_tformat_decode_request(eeprom_read, 3, NULL).status == MB_COMPLETE);
  CHECK(mb_modbus_decode_rtu(classic, 8, NULL).status == MB_COMPLETE);
  CHECK(mb_modbus_decode_response_unpaired(answer, 6, NULL).status == MB_COMPLETE);
  {
    const mb_modbus_framer_options one = {1, 0, false};
    mb_modbus_server_framer_init(&fr, NULL); /* address 0: broadcasts alone */
    res = mb_modbus_server_framer_feed(&fr, classic, 8, NULL);
    CHECK(res.status == MB_INCOMPLETE && mb_modbus_server_framer_skipped(&fr) == 1);
    mb_modbus_server_framer_init(&fr, &one);
    res = mb_modbus_server_framer_feed(&fr, classic, 8, NULL);
    CHECK(res.status == MB_COMPLETE && res.count == 8);
  }

  /* BiSS-C: no layouts, no words, no values; the Ack bound given */
  CHECK(mb_biss_decode_frame(words, 4, 64, NULL, 1, 0, 0, false, NULL).error ==
        MB_INVALID_ARGUMENT);
  res = mb_biss_decode_frame(NULL, 0, 64, &absys, 1, 0, 0, false, NULL);
  CHECK(res.status == MB_INCOMPLETE);
  v.multi_turn = 0;
  v.single_turn = 77;
  v.ne = true;
  v.nw = true;
  CHECK(mb_biss_encode_frame(&absys, NULL, 0, 1, false, words, 4, &bits) == MB_INVALID_ARGUMENT);
  CHECK(mb_biss_encode_frame(&absys, &v, 0, 1, false, NULL, 0, &bits) == MB_BUFFER_TOO_SMALL);
  CHECK(mb_biss_encode_frame(&absys, &v, 0, 40, false, words, 4, &bits) == MB_OK);
  res = mb_biss_decode_frame(words, 4, bits, &absys, 1, 0, 8, false, NULL);
  CHECK(res.status == MB_FAILED && res.error == MB_BISS_NO_START);
  res = mb_biss_decode_frame(words, 4, bits, &absys, 1, 0, 64, false, NULL);
  CHECK(res.status == MB_COMPLETE);
  two[0] = absys;
  two[1] = absys;
  res = mb_biss_decode_frame(words, 4, bits, two, 2, 0, 0, false, NULL);
  CHECK(res.status != MB_COMPLETE); /* one slave's frame read as a chain of two */

  /* the server: no table; FC16 and FC17 without a holding register reader: 01 */
  memset(&cb, 0, sizeof cb);
  f.slave = 1;
  f.pdu = classic + 1;
  f.pdu_size = 5;
  f.crc = 0;
  CHECK(mb_modbus_serve_frame(NULL, 1, &f, rsp, sizeof rsp, &n) == MB_INVALID_ARGUMENT);
  cb.write_single_register = write_register;
  cb.write_multiple_registers = write_registers;
  cb.context = &dev;
  {
    const uint8_t m[7] = {0x16, 0x00, 1, 0xFF, 0xFF, 0x00, 0x00};
    const uint8_t rw[12] = {0x17, 0x00, 1, 0x00, 1, 0x00, 2, 0x00, 1, 2, 0x11, 0x22};
    CHECK(mb_modbus_serve_pdu(&cb, m, 7, rsp, sizeof rsp, &n) == MB_OK);
    CHECK(n == 2 && rsp[0] == 0x96 && rsp[1] == 0x01);
    CHECK(mb_modbus_serve_pdu(&cb, rw, 12, rsp, sizeof rsp, &n) == MB_OK);
    CHECK(n == 2 && rsp[0] == 0x97 && rsp[1] == 0x01);
    cb.read_holding_registers = read_holding;
    cb.write_single_register = NULL;
    cb.write_multiple_registers = NULL;
    CHECK(mb_modbus_serve_pdu(&cb, m, 7, rsp, sizeof rsp, &n) == MB_OK);
    CHECK(n == 2 && rsp[0] == 0x96 && rsp[1] == 0x01);
  }
}

int main(void) {
  test_errors_and_crcs();
  test_tformat_codec();
  test_tformat_receiver();
  test_modbus_server();
  test_modbus_client();
  test_biss_frames();
  test_biss_control();
  test_null_and_absent();
  printf("c_api_test: %d checks, %d failed\n", checks, failures);
  return failures == 0 ? 0 : 1;
}
