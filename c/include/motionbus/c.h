/* motionbus — the C API (C99): the library's codecs and stream objects for C firmware and C
 * host programs. One compiled C++ source (c/motionbus_c.cpp, the CMake target motionbus::c, a
 * static library) implements it on the C++ headers; nothing is re-implemented.
 *
 * Shape (docs/c.md):
 *  - Encoders return an mb_errc (MB_OK or the error) and write into the caller's buffer, the
 *    bytes written through `written`. Nothing is written on error.
 *  - Decoders return an mb_result: complete (value written to the caller's struct, `count` =
 *    bytes consumed), incomplete (`count` = at least that many more bytes needed) or failed
 *    (`error`, `count` = bytes the caller may drop, CRC evidence in expected/received).
 *  - Stream objects (T-format receiver, Modbus server framer, BiSS-C control master) live in
 *    caller-owned storage: a union of the size and alignment given below (a `static` one is in
 *    .bss), set up by its _init function before any other call. No heap, no I/O, no global
 *    state; no C++ exception crosses the boundary (the source is built without exceptions).
 *  - Views into the caller's or an object's memory (mb_modbus_frame.pdu, mb_modbus_response.data)
 *    are valid while that memory is unchanged: a framer's frame until the next call on it.
 *  - Interrupts: as the C++ objects' firmware contracts say (tformat/receiver.hpp,
 *    modbus/framer.hpp, biss/control.hpp): put()/feed() may run in a receive interrupt, idle()
 *    in the idle-line timer's, step() where the frame's CDS bit is known; never two calls at
 *    once on one object.
 */
#ifndef MOTIONBUS_C_H
#define MOTIONBUS_C_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* --- errors ---------------------------------------------------------------------------------
 * The values of motionbus::errc (core/errc.hpp), one for one; the C++ source checks each. */
typedef enum mb_errc {
  MB_OK = 0,
  MB_TRUNCATED = 1,
  MB_BUFFER_TOO_SMALL = 2,
  MB_INVALID_ARGUMENT = 3,
  MB_CRC_MISMATCH = 4,
  MB_OUT_OF_RANGE = 5,
  MB_LENGTH_MISMATCH = 6,
  MB_RESERVED_BITS = 7,
  MB_NO_FRAME = 8,
  MB_TFORMAT_SYNC_CODE = 32,
  MB_TFORMAT_PARITY = 33,
  MB_TFORMAT_UNKNOWN_DATA_ID = 34,
  MB_TFORMAT_LENGTH = 35,
  MB_TFORMAT_CF_MISMATCH = 36,
  MB_TFORMAT_ADDRESS_MISMATCH = 37,
  MB_TFORMAT_COMMUNICATION_ALARM = 38,
  MB_TFORMAT_START_BIT = 39,
  MB_TFORMAT_DELIMITER = 40,
  MB_TFORMAT_DATA_MISMATCH = 41,
  MB_MODBUS_ILLEGAL_FUNCTION = 64,
  MB_MODBUS_QUANTITY = 65,
  MB_MODBUS_BYTE_COUNT = 66,
  MB_MODBUS_ADDRESS_OVERFLOW = 67,
  MB_MODBUS_COIL_VALUE = 68,
  MB_MODBUS_MISMATCH = 69,
  MB_MODBUS_SLAVE_ADDRESS = 70,
  MB_MODBUS_PDU_LENGTH = 71,
  MB_MODBUS_ASCII_CHARACTER = 80,
  MB_MODBUS_ASCII_ODD_DIGITS = 81,
  MB_MODBUS_ASCII_END = 82,
  MB_MODBUS_REFERENCE_TYPE = 96,
  MB_MODBUS_FILE_NUMBER = 97,
  MB_MODBUS_RECORD_NUMBER = 98,
  MB_BISS_NO_ACK = 128,
  MB_BISS_NO_START = 129,
  MB_BISS_NOT_ACKNOWLEDGED = 130,
  MB_BISS_ACCESS_DENIED = 131,
  MB_BISS_ECHO_MISMATCH = 132,
  MB_BISS_TIMEOUT = 133,
  MB_BISS_WRITE_NOT_CONFIRMED = 134,
  MB_BISS_ABORTED = 135,
  MB_BISS_BUSY = 136,
  MB_BISS_LAYOUT = 137,
  MB_BISS_EDS = 138
} mb_errc;

/* The error's name as the tools print it ("crc_mismatch"); "unknown" outside the enumeration.
 * Static storage. */
const char* mb_errc_name(int error);

/* --- decode results ------------------------------------------------------------------------ */
typedef enum mb_status { MB_INCOMPLETE = 0, MB_COMPLETE = 1, MB_FAILED = 2 } mb_status;

typedef struct mb_result {
  uint8_t status; /* mb_status */
  uint8_t error;  /* mb_errc: MB_OK unless failed */
  /* complete: bytes (bits, for BiSS-C) consumed; incomplete: at least this many more needed;
   * failed: bytes (bits) the caller may drop before trying again (0: none known) */
  size_t count;
  uint32_t expected; /* failed: evidence (e.g. the CRC computed), else 0 */
  uint32_t received; /* failed: evidence (e.g. the CRC received), else 0 */
} mb_result;

/* --- caller-owned storage -------------------------------------------------------------------
 * Sizes of the C++ objects on the target's ABI (checked at compile time by the C++ source,
 * which fails to build if any differs): 32-bit targets (Cortex-M, RV32, armhf) and 64-bit
 * hosts. The alignment is that of size_t and pointers, which the storage unions carry. */
#if defined(__SIZEOF_POINTER__) && __SIZEOF_POINTER__ == 4
#define MB_TFORMAT_RECEIVER_SIZE 68
#define MB_MODBUS_SERVER_FRAMER_SIZE 308
#define MB_BISS_CONTROL_MASTER_SIZE 68
#define MB_STORAGE_ALIGN 4
#else
#define MB_TFORMAT_RECEIVER_SIZE 88
#define MB_MODBUS_SERVER_FRAMER_SIZE 344
#define MB_BISS_CONTROL_MASTER_SIZE 112
#define MB_STORAGE_ALIGN 8
#endif

typedef union mb_tformat_receiver {
  unsigned char bytes[MB_TFORMAT_RECEIVER_SIZE];
  size_t align_size;
  void* align_pointer;
} mb_tformat_receiver;

typedef union mb_modbus_server_framer {
  unsigned char bytes[MB_MODBUS_SERVER_FRAMER_SIZE];
  size_t align_size;
  void* align_pointer;
} mb_modbus_server_framer;

typedef union mb_biss_control_master {
  unsigned char bytes[MB_BISS_CONTROL_MASTER_SIZE];
  size_t align_size;
  void* align_pointer;
} mb_biss_control_master;

/* --- CRCs ------------------------------------------------------------------------------------ */
/* CRC-16/MODBUS of `size` bytes (check value of "123456789": 0x4B37). */
uint16_t mb_crc16_modbus(const uint8_t* data, size_t size);
/* The T-format CRC (x^8 + 1: the XOR of the bytes; "123456789": 0x31). */
uint8_t mb_crc8_tformat(const uint8_t* data, size_t size);
/* BiSS CRC6 (x^6 + x + 1, start 0, inverted as sent) over the low `count` bits of `bits`,
 * most significant first (a count above 64 is taken as 64): a sensor data frame's CRC over its
 * data, nE and nW. */
uint8_t mb_crc6_biss(uint64_t bits, unsigned count);
/* BiSS CRC4 (x^4 + x + 1, start 0, inverted) of control communication, likewise (the header's
 * CTS, ID and address bits; a register byte). */
uint8_t mb_crc4_biss(uint64_t bits, unsigned count);

/* --- T-format (Tamagawa Smart-Abs) ------------------------------------------------------------
 * Data IDs: the 4-bit codes of the spec's Table 1. */
enum {
  MB_TFORMAT_ID0 = 0x0, /* read ABS */
  MB_TFORMAT_ID1 = 0x1, /* read ABM */
  MB_TFORMAT_ID2 = 0x2, /* read ENID */
  MB_TFORMAT_ID3 = 0x3, /* read all */
  MB_TFORMAT_ID6 = 0x6, /* EEPROM write */
  MB_TFORMAT_ID7 = 0x7, /* reset errors */
  MB_TFORMAT_ID8 = 0x8, /* reset single-turn */
  MB_TFORMAT_IDC = 0xC, /* reset multi-turn */
  MB_TFORMAT_IDD = 0xD  /* EEPROM read */
};
#define MB_TFORMAT_MAX_REQUEST_SIZE 4
#define MB_TFORMAT_MAX_RESPONSE_SIZE 11

/* A response as the master sees it; the fields present follow its Data ID. */
typedef struct mb_tformat_response {
  uint8_t id; /* Data ID code */
  uint8_t cf;
  uint8_t sf;      /* status field (not ID6/IDD) */
  uint8_t enid;    /* encoder ID */
  uint8_t almc;    /* alarm bits */
  uint8_t address; /* EEPROM address (ID6/IDD) */
  bool busy;       /* EEPROM busy (ID6/IDD) */
  uint8_t edf;     /* EEPROM data (ID6/IDD) */
  uint8_t crc;
  uint32_t abs; /* single-turn position */
  uint32_t abm; /* multi-turn count */
} mb_tformat_response;

/* A request as the encoder sees it. */
typedef struct mb_tformat_request {
  uint8_t id;
  uint8_t cf;
  uint8_t address; /* ID6, IDD */
  uint8_t edf;     /* ID6 */
  uint8_t crc;     /* ID6, IDD */
} mb_tformat_request;

/* Decode options; NULL wherever they are taken means the defaults (17 / 16 bits, checked). */
typedef struct mb_tformat_options {
  uint8_t single_turn_bits; /* valid bits of ABS, 1..24 (default 17) */
  uint8_t multi_turn_bits;  /* valid bits of ABM, 1..24 (default 16) */
  bool check_unused_bits;   /* bits above them must be 0 (default true) */
  bool resolution_from_enid; /* ID3: the resolution of a known ENID instead (default false) */
} mb_tformat_options;

/* The defaults, to change one field of. */
mb_tformat_options mb_tformat_default_options(void);

/* The request for `id` (`address` for ID6/IDD, `data` for ID6). Errors: unknown Data ID,
 * out of range (address above 127), buffer too small. */
mb_errc mb_tformat_encode_request(uint8_t id, uint8_t address, uint8_t data, uint8_t* out,
                                  size_t out_size, size_t* written);
/* One response from the start of `in` (T-format spec §6.3): complete (`out` set), incomplete, or
 * failed with 1 byte to drop (CF sync code, parity, unknown ID, CRC, reserved bits, out of range). */
mb_result mb_tformat_decode_response(const uint8_t* in, size_t size,
                                     const mb_tformat_options* options, mb_tformat_response* out);
/* The same, checked against the request sent (`request`, `request_size` bytes): also
 * communication alarm, CF, EEPROM address and data mismatches; invalid argument for a request
 * that is not one. */
mb_result mb_tformat_decode_response_for(const uint8_t* request, size_t request_size,
                                         const uint8_t* in, size_t size,
                                         const mb_tformat_options* options,
                                         mb_tformat_response* out);
/* Encoder side: one request from the start of `in`. */
mb_result mb_tformat_decode_request(const uint8_t* in, size_t size, mb_tformat_request* out);
/* Encoder side: the response for `r->id` with r's fields (CF and CRC computed). */
mb_errc mb_tformat_encode_response(const mb_tformat_response* r, uint8_t* out, size_t out_size,
                                   size_t* written);

/* The stream receiver (master side, tformat/receiver.hpp). */
typedef struct mb_tformat_receiver_options {
  bool echo_expected;           /* half duplex with the receiver on: skip the request's echo */
  bool check_against_request;   /* check responses against the last request sent (default) */
  mb_tformat_options decode;
} mb_tformat_receiver_options;

mb_tformat_receiver_options mb_tformat_receiver_default_options(void);
/* Sets up `rx` (NULL options: the defaults). */
void mb_tformat_receiver_init(mb_tformat_receiver* rx, const mb_tformat_receiver_options* options);
/* The request just written to the line (up to 4 bytes). */
void mb_tformat_receiver_sent(mb_tformat_receiver* rx, const uint8_t* request, size_t size);
/* One received byte; true when it settles something, which mb_tformat_receiver_result gives. */
bool mb_tformat_receiver_put(mb_tformat_receiver* rx, uint8_t byte);
/* What the last put() that returned true settled (`out` set when complete). */
mb_result mb_tformat_receiver_result(const mb_tformat_receiver* rx, mb_tformat_response* out);
/* A chunk: the first thing settled, `count` = bytes of `in` taken (incomplete: all of them);
 * after a failure call again with the rest (or nothing) until it reports incomplete. */
mb_result mb_tformat_receiver_feed(mb_tformat_receiver* rx, const uint8_t* in, size_t size,
                                   mb_tformat_response* out);
/* The line went quiet: failed (truncated, bytes dropped) when part of a frame was held. */
mb_result mb_tformat_receiver_idle(mb_tformat_receiver* rx);
size_t mb_tformat_receiver_dropped(const mb_tformat_receiver* rx);
size_t mb_tformat_receiver_echoes_skipped(const mb_tformat_receiver* rx);
size_t mb_tformat_receiver_pending(const mb_tformat_receiver* rx);
bool mb_tformat_receiver_echo_missed(const mb_tformat_receiver* rx);

/* --- Modbus RTU -------------------------------------------------------------------------------- */
#define MB_MODBUS_MAX_ADU_SIZE 256
#define MB_MODBUS_MAX_PDU_SIZE 253

/* A frame: the slave address and a view of its PDU (into the decoded input or the framer). */
typedef struct mb_modbus_frame {
  uint8_t slave;
  const uint8_t* pdu;
  size_t pdu_size;
  uint16_t crc; /* as received */
} mb_modbus_frame;

/* Wraps `pdu` for `slave` (0 broadcast, 1..247): address, PDU, CRC. */
mb_errc mb_modbus_encode_rtu(uint8_t slave, const uint8_t* pdu, size_t pdu_size, uint8_t* out,
                             size_t out_size, size_t* written);
/* A whole ADU: failed (PDU length, CRC, slave address), else complete. */
mb_result mb_modbus_decode_rtu(const uint8_t* adu, size_t size, mb_modbus_frame* out);

/* The server framer (modbus/framer.hpp, a server's role). `address` 1..247 (it also takes
 * broadcasts); `last_address` above it: every address up to it too (0: `address` alone);
 * `length_only`: no t3.5 signal, frames end where the length rule says. NULL options: all
 * zero (address 0: broadcasts alone). */
typedef struct mb_modbus_framer_options {
  uint8_t address;
  uint8_t last_address;
  bool length_only;
} mb_modbus_framer_options;

void mb_modbus_server_framer_init(mb_modbus_server_framer* framer,
                                  const mb_modbus_framer_options* options);
/* One received byte; true when it settles something (mb_modbus_server_framer_result). */
bool mb_modbus_server_framer_put(mb_modbus_server_framer* framer, uint8_t byte);
/* What the last put() that returned true settled; a frame's PDU points into the framer. */
mb_result mb_modbus_server_framer_result(const mb_modbus_server_framer* framer,
                                         mb_modbus_frame* out);
/* A chunk, as mb_tformat_receiver_feed. */
mb_result mb_modbus_server_framer_feed(mb_modbus_server_framer* framer, const uint8_t* in,
                                       size_t size, mb_modbus_frame* out);
/* The t3.5 silence: the bytes held end a frame (complete: `out` set; the framer is empty). */
mb_result mb_modbus_server_framer_idle(mb_modbus_server_framer* framer, mb_modbus_frame* out);
size_t mb_modbus_server_framer_pending(const mb_modbus_server_framer* framer);
size_t mb_modbus_server_framer_dropped(const mb_modbus_server_framer* framer);
size_t mb_modbus_server_framer_skipped(const mb_modbus_server_framer* framer);

/* The server: a table of callbacks, each returning 0 or a Modbus exception code (2 illegal
 * address, 3 illegal value, 4 device failure, ...) and given the table's `context`. A NULL
 * callback is a function not served: exception 01. Packed bits: the LSB of the first byte is
 * the first coil; a read's bits arrive cleared. FC16 (mask write) is served with a holding
 * register reader and a register writer, FC17 with a holding register reader and
 * write_multiple_registers. The request's own limits are checked before any callback
 * (exceptions 03, 02), and a write callback is called only after every other check. */
typedef struct mb_modbus_callbacks {
  uint8_t (*read_coils)(uint16_t address, uint16_t quantity, uint8_t* packed, void* context);
  uint8_t (*read_discrete_inputs)(uint16_t address, uint16_t quantity, uint8_t* packed,
                                  void* context);
  uint8_t (*read_holding_registers)(uint16_t address, uint16_t quantity, uint16_t* out,
                                    void* context);
  uint8_t (*read_input_registers)(uint16_t address, uint16_t quantity, uint16_t* out,
                                  void* context);
  uint8_t (*write_single_coil)(uint16_t address, bool on, void* context);
  uint8_t (*write_single_register)(uint16_t address, uint16_t value, void* context);
  uint8_t (*write_multiple_coils)(uint16_t address, uint16_t quantity, const uint8_t* packed,
                                  void* context);
  uint8_t (*write_multiple_registers)(uint16_t address, uint16_t quantity,
                                      const uint16_t* values, void* context);
  /* FC11: writes the byte count and the device bytes into `out` (`capacity` bytes), their total
   * size to `size`. */
  uint8_t (*report_server_id)(uint8_t* out, size_t capacity, size_t* size, void* context);
  void* context;
} mb_modbus_callbacks;

/* Serves one frame (from the framer or mb_modbus_decode_rtu) for the server at `own_address`:
 * the response ADU in `out` (256 bytes at least), its size in `written`, 0 when nothing is to be
 * sent (another address; a broadcast, executed). Errors: buffer too small. */
mb_errc mb_modbus_serve_frame(const mb_modbus_callbacks* callbacks, uint8_t own_address,
                              const mb_modbus_frame* frame, uint8_t* out, size_t out_size,
                              size_t* written);
/* Serves a request PDU (no address, no CRC: Modbus TCP): the response PDU in `out` (253 bytes
 * at least), 0 bytes for an empty request. */
mb_errc mb_modbus_serve_pdu(const mb_modbus_callbacks* callbacks, const uint8_t* pdu,
                            size_t pdu_size, uint8_t* out, size_t out_size, size_t* written);

/* Client requests (PDUs: wrap them with mb_modbus_encode_rtu). */
mb_errc mb_modbus_encode_read(uint8_t function, uint16_t address, uint16_t quantity,
                              uint8_t* out, size_t out_size, size_t* written);
mb_errc mb_modbus_encode_write_single_coil(uint16_t address, bool on, uint8_t* out,
                                           size_t out_size, size_t* written);
mb_errc mb_modbus_encode_write_single_register(uint16_t address, uint16_t value, uint8_t* out,
                                               size_t out_size, size_t* written);
mb_errc mb_modbus_encode_write_multiple_coils(uint16_t address, uint16_t quantity,
                                              const uint8_t* packed, size_t packed_size,
                                              uint8_t* out, size_t out_size, size_t* written);
mb_errc mb_modbus_encode_write_multiple_registers(uint16_t address, const uint16_t* values,
                                                  size_t count, uint8_t* out, size_t out_size,
                                                  size_t* written);
mb_errc mb_modbus_encode_mask_write_register(uint16_t address, uint16_t and_mask,
                                             uint16_t or_mask, uint8_t* out, size_t out_size,
                                             size_t* written);
mb_errc mb_modbus_encode_read_write_multiple_registers(uint16_t read_address,
                                                       uint16_t read_quantity,
                                                       uint16_t write_address,
                                                       const uint16_t* values, size_t count,
                                                       uint8_t* out, size_t out_size,
                                                       size_t* written);
/* Any function with an opaque data part (FC07, 0B, 0C, 11; custom functions). */
mb_errc mb_modbus_encode_raw(uint8_t function, const uint8_t* data, size_t data_size,
                             uint8_t* out, size_t out_size, size_t* written);

/* A response as a client sees it; `data` points into the decoded PDU. */
typedef struct mb_modbus_response {
  const uint8_t* data; /* packed bits, register bytes (big-endian), FC08/11 data, raw data */
  size_t data_size;
  uint8_t function; /* without the exception flag */
  bool exception;
  uint8_t exception_code; /* wire value, when exception */
  uint8_t byte_count;
  uint16_t address;  /* echo: FC05, 06, 0F, 10, 16 */
  uint16_t quantity; /* FC01-04 (as asked), echo: FC0F, 10 */
  uint16_t value;    /* echo: FC05, 06 */
  uint16_t and_mask; /* echo: FC16 */
  uint16_t or_mask;  /* echo: FC16 */
  uint16_t sub_function;  /* FC08 */
  uint16_t status;        /* FC07, 0B, 0C */
  uint16_t event_count;   /* FC0B, 0C */
  uint16_t message_count; /* FC0C */
  uint16_t fifo_count;    /* FC18 */
} mb_modbus_response;

/* The response PDU to the request PDU `sent` (as encoded): complete (an exception response too,
 * `exception` set) or failed (PDU length, invalid argument: `sent` is no request, mismatch,
 * truncated, byte count, reserved bits). */
mb_result mb_modbus_decode_response_for(const uint8_t* sent, size_t sent_size, const uint8_t* pdu,
                                        size_t pdu_size, mb_modbus_response* out);
/* A response PDU seen without its request (a bus monitor): the checks it carries itself. */
mb_result mb_modbus_decode_response_unpaired(const uint8_t* pdu, size_t pdu_size,
                                             mb_modbus_response* out);
/* Register `index` of big-endian register bytes; bit `index` of packed bits. */
uint16_t mb_modbus_register_at(const uint8_t* data, size_t index);
bool mb_modbus_bit_at(const uint8_t* packed, size_t index);

/* --- BiSS-C -------------------------------------------------------------------------------------
 * One slave's sensor data layout: multi-turn, single-turn and alignment bits (1..64 data bits in
 * all), nE and nW present or not, the CRC (width 0..16, polynomial without its x^width term:
 * 0x03 for the CRC6 0x43, start value, sent inverted or not). */
typedef struct mb_biss_layout {
  uint8_t multi_turn_bits;
  uint8_t single_turn_bits;
  uint8_t alignment_bits;
  bool has_error;
  bool has_warning;
  uint8_t crc_width;
  uint32_t crc_poly;
  uint32_t crc_start;
  bool crc_inverted;
} mb_biss_layout;

/* The AMO ABSYS layout: 32 single-turn bits, nE, nW, CRC6 0x43 inverted (40 bits). */
mb_biss_layout mb_biss_absys_layout(void);

typedef struct mb_biss_slave_data {
  uint64_t data;        /* the data field as sent */
  uint64_t multi_turn;
  uint64_t single_turn; /* alignment bits removed */
  bool ne;              /* nE line level: false = error active */
  bool nw;              /* nW line level: false = warning active */
  uint32_t crc;         /* as received */
  uint32_t crc_computed;
} mb_biss_slave_data;

#define MB_BISS_MAX_CHAIN 8

typedef struct mb_biss_frame {
  size_t line_delay; /* idle bits before the Ack */
  size_t start;      /* index of the Start bit */
  bool cds;          /* the CDS bit */
  size_t count;      /* slaves decoded: slaves[0..count-1] are written, the rest left as they were */
  mb_biss_slave_data slaves[MB_BISS_MAX_CHAIN];
} mb_biss_frame;

/* Decodes the sensor data frame of a chain of `chain_size` (1..8) slaves from an SL capture of
 * `bit_count` samples in 32-bit words (first sample in the most significant bit, or the least
 * with `lsb_first`), searching at most `max_line_delay` idle and `max_ack_bits` Ack samples
 * (0: the defaults, 64 and 256). Counts in bits. Failed: no Ack, no Start, CRC mismatch
 * (the first slave whose CRC fails), layout, invalid argument. */
mb_result mb_biss_decode_frame(const uint32_t* words, size_t word_count, size_t bit_count,
                               const mb_biss_layout* chain, size_t chain_size,
                               size_t max_line_delay, size_t max_ack_bits, bool lsb_first,
                               mb_biss_frame* out);

/* Slave side (emulators, test benches): the SL samples of one slave's frame, MSB first. */
typedef struct mb_biss_slave_values {
  uint64_t multi_turn;
  uint64_t single_turn;
  bool ne;
  bool nw;
} mb_biss_slave_values;
mb_errc mb_biss_encode_frame(const mb_biss_layout* layout, const mb_biss_slave_values* values,
                             size_t line_delay, size_t ack_bits, bool cds, uint32_t* words,
                             size_t word_count, size_t* bits);

/* The control master (register access over CDM/CDS, biss/control.hpp). */
typedef enum mb_biss_control_state {
  MB_BISS_CONTROL_IDLE = 0,
  MB_BISS_CONTROL_BUSY = 1,
  MB_BISS_CONTROL_DONE = 2,
  MB_BISS_CONTROL_FAILED = 3
} mb_biss_control_state;

/* `max_wait_frames`: wait states accepted per byte (0: the default, 4096). */
void mb_biss_control_master_init(mb_biss_control_master* master, size_t max_wait_frames);
/* Starts a read of `size` (1..128) registers from `address` of slave `slave_id` (0..7) into
 * `out`, which must outlive the access. Errors: busy, invalid argument. */
mb_errc mb_biss_control_master_start_read(mb_biss_control_master* master, uint8_t slave_id,
                                          uint8_t address, uint8_t* out, size_t size);
mb_errc mb_biss_control_master_start_write(mb_biss_control_master* master, uint8_t slave_id,
                                           uint8_t address, const uint8_t* data, size_t size);
void mb_biss_control_master_abort(mb_biss_control_master* master);
/* One frame: the CDS bit of the frame just read; returns the CDM bit to send with the next. */
bool mb_biss_control_master_step(mb_biss_control_master* master, bool cds);
mb_biss_control_state mb_biss_control_master_state(const mb_biss_control_master* master);
mb_errc mb_biss_control_master_error(const mb_biss_control_master* master);
size_t mb_biss_control_master_transferred(const mb_biss_control_master* master);
size_t mb_biss_control_master_frames(const mb_biss_control_master* master);
/* Frames an access of `bytes` bytes takes without wait states, preamble included. */
size_t mb_biss_control_frames_for(size_t bytes);

#ifdef __cplusplus
}
#endif

#endif /* MOTIONBUS_C_H */
