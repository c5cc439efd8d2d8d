// The C API's calls (c/include/motionbus/c.h), measured by the meter (tests/meter/meter.py,
// measure_capi()) in an image of their own: this file and c/motionbus_c.cpp, the library's C
// source as a C firmware links it. Each `op_capi_*` makes the calls a C firmware would make, on
// the inputs the meter writes into `meter_in`, and writes what it got into `meter_out`, which
// the meter checks.

#include <motionbus/c.h>
#include <motionbus/biss/control.hpp>

#include <cstddef>
#include <cstdint>

#define METER_OP extern "C" __attribute__((used, noinline))

extern "C" {
__attribute__((used, aligned(8))) std::uint8_t meter_in[512];
__attribute__((used)) std::uint32_t meter_in_size;
__attribute__((used, aligned(8))) std::uint32_t meter_out[64];
__attribute__((used)) std::uint8_t meter_adu[256];
__attribute__((used)) std::uint16_t meter_registers[128];
// The image's entry (never run by the meter: it calls functions one at a time).
__attribute__((used)) void meter_entry() {}
}

namespace {

mb_tformat_response tformat_response;
mb_result last;
mb_tformat_receiver receiver;
mb_modbus_server_framer framer;
mb_modbus_frame frame;
mb_biss_frame biss;
mb_biss_control_master master;
std::uint8_t control_read[2];

// The slave the control master talks to (the C++ one, as in ops.cpp: not measured here).
struct register_file {
  std::uint8_t bytes[128];
  bool readable(std::uint8_t) const { return true; }
  bool writable(std::uint8_t) const { return true; }
  bool ready() const { return true; }
  std::uint8_t read(std::uint8_t a) { return bytes[a & 0x7FU]; }
  void write(std::uint8_t a, std::uint8_t v) { bytes[a & 0x7FU] = v; }
};
register_file biss_registers;
motionbus::biss::control_slave<register_file> slave(biss_registers);

void put_result(const mb_result& r) {
  meter_out[0] = r.status;
  meter_out[1] = r.error;
}

// The device of the Modbus operations: holding registers in meter_registers (128 of them).
std::uint8_t read_holding(std::uint16_t address, std::uint16_t quantity, std::uint16_t* out,
                          void* context) {
  const auto* regs = static_cast<const std::uint16_t*>(context);
  if (address + quantity > 128U) {
    return 0x02;
  }
  for (std::uint16_t i = 0; i < quantity; ++i) {
    out[i] = regs[address + i];
  }
  return 0;
}
std::uint8_t write_registers(std::uint16_t address, std::uint16_t quantity,
                             const std::uint16_t* values, void* context) {
  auto* regs = static_cast<std::uint16_t*>(context);
  if (address + quantity > 128U) {
    return 0x02;
  }
  for (std::uint16_t i = 0; i < quantity; ++i) {
    regs[address + i] = values[i];
  }
  return 0;
}
const mb_modbus_callbacks callbacks = {nullptr, nullptr, read_holding,    nullptr, nullptr,
                                       nullptr, nullptr, write_registers, nullptr, meter_registers};

}  // namespace

// CRC-16/MODBUS of meter_in.
METER_OP void op_capi_crc16() {
  meter_out[0] = mb_crc16_modbus(meter_in, meter_in_size);
}

// T-format: one response decoded from meter_in.
METER_OP void op_capi_tformat_decode_response() {
  last = mb_tformat_decode_response(meter_in, meter_in_size, nullptr, &tformat_response);
}
METER_OP void op_capi_report_tformat() {
  put_result(last);
  meter_out[2] = tformat_response.abs;
  meter_out[3] = tformat_response.abm;
  meter_out[4] = tformat_response.almc;
  meter_out[5] = tformat_response.enid;
  meter_out[6] = tformat_response.sf;
  meter_out[7] = tformat_response.cf;
}

// T-format: the stream receiver, byte by byte, after a request of Data ID `code`.
METER_OP void op_capi_receiver_start(unsigned code) {
  mb_tformat_receiver_init(&receiver, nullptr);
  std::uint8_t request[MB_TFORMAT_MAX_REQUEST_SIZE];
  std::size_t n = 0;
  (void)mb_tformat_encode_request(static_cast<std::uint8_t>(code), 0, 0, request, sizeof request,
                                  &n);
  mb_tformat_receiver_sent(&receiver, request, n);
}
METER_OP bool op_capi_receiver_byte(unsigned byte) {
  return mb_tformat_receiver_put(&receiver, static_cast<std::uint8_t>(byte));
}
METER_OP void op_capi_report_receiver(unsigned ready) {
  meter_out[0] = 0;
  meter_out[1] = 0;
  if (ready == 0U) {
    return;
  }
  last = mb_tformat_receiver_result(&receiver, &tformat_response);
  op_capi_report_tformat();
}

// Modbus: the server framer, byte by byte (slave 1).
METER_OP void op_capi_framer_start() {
  const mb_modbus_framer_options options = {1, 0, false};
  mb_modbus_server_framer_init(&framer, &options);
}
METER_OP bool op_capi_framer_byte(unsigned byte) {
  return mb_modbus_server_framer_put(&framer, static_cast<std::uint8_t>(byte));
}
METER_OP void op_capi_report_framer(unsigned ready) {
  meter_out[0] = 0;
  meter_out[1] = 0;
  if (ready == 0U) {
    return;
  }
  const mb_result r = mb_modbus_server_framer_result(&framer, &frame);
  put_result(r);
  if (r.status == MB_COMPLETE) {
    meter_out[2] = frame.slave;
    meter_out[3] = static_cast<std::uint32_t>(frame.pdu_size);
    meter_out[4] = frame.pdu[0];
    meter_out[5] = frame.crc;
  }
}
// The silence after bytes the framer could not frame: its result as op_capi_report_framer
// reports one (measure_framer_noise in meter.py).
METER_OP void op_capi_framer_idle() {
  const mb_result r = mb_modbus_server_framer_idle(&framer, &frame);
  meter_out[0] = 0;
  meter_out[1] = 0;
  put_result(r);
}
// The frame the framer handed over, served through the callback table; the reply in meter_adu.
METER_OP void op_capi_serve_frame() {
  std::size_t n = 0;
  meter_out[2] = mb_modbus_serve_frame(&callbacks, 1, &frame, meter_adu, sizeof meter_adu, &n);
  meter_out[0] = static_cast<std::uint32_t>(n);
  meter_out[1] = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(meter_adu));
}

// BiSS-C: one ABSYS frame from a capture of meter_in_size bits in meter_in (32-bit words).
METER_OP void op_capi_biss_decode_frame() {
  static const mb_biss_layout absys = mb_biss_absys_layout();
  last = mb_biss_decode_frame(reinterpret_cast<const std::uint32_t*>(meter_in), 4, meter_in_size,
                              &absys, 1, 0, 0, false, &biss);
}
METER_OP void op_capi_report_biss() {
  put_result(last);
  meter_out[2] = static_cast<std::uint32_t>(biss.slaves[0].single_turn);
  meter_out[3] = (biss.slaves[0].ne ? 2U : 0U) | (biss.slaves[0].nw ? 1U : 0U);
  meter_out[4] = biss.slaves[0].crc;
  meter_out[5] = static_cast<std::uint32_t>(biss.start);
}

// BiSS-C: the control master reading two registers from `address` of slave 0.
METER_OP void op_capi_control_start(unsigned address) {
  slave = motionbus::biss::control_slave<register_file>(biss_registers);
  for (unsigned i = 0; i < 128U; ++i) {
    biss_registers.bytes[i] = meter_in[i];
  }
  mb_biss_control_master_init(&master, 0);
  meter_out[1] = mb_biss_control_master_start_read(&master, 0, static_cast<std::uint8_t>(address),
                                                   control_read, sizeof control_read);
}
METER_OP bool op_capi_master_step(unsigned cds) {
  return mb_biss_control_master_step(&master, cds != 0U);
}
METER_OP unsigned op_capi_slave_step(unsigned cdm) {
  return slave.step(cdm != 0U) ? 1U : 0U;
}
METER_OP void op_capi_report_control() {
  meter_out[0] = mb_biss_control_master_state(&master);
  meter_out[2] = control_read[0];
  meter_out[3] = control_read[1];
  meter_out[4] = mb_biss_control_master_error(&master);
}
