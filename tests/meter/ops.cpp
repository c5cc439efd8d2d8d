// The operations the meter measures (tests/meter/meter.py): each `op_*` function is one call a
// firmware would make, on inputs the meter writes into `meter_in` (or passes as arguments), and
// writes what it decoded or built into `meter_out`, which the meter checks against its own
// computation before it reports a figure. Built freestanding for each core and level; the
// `selfcheck_*` functions are loops of known instruction count and stack use that check the
// meter itself.

#include <motionbus/biss/codec.hpp>
#include <motionbus/biss/control.hpp>
#include <motionbus/core/link_health.hpp>
#include <motionbus/core/position.hpp>
#include <motionbus/devices/absys_emulator.hpp>
#include <motionbus/devices/sm_unit_emulator.hpp>
#include <motionbus/devices/ts5700n8500_emulator.hpp>
#include <motionbus/modbus/ascii.hpp>
#include <motionbus/modbus/framer.hpp>
#include <motionbus/modbus/pdu_client.hpp>
#include <motionbus/modbus/pdu_server.hpp>
#include <motionbus/modbus/rtu.hpp>
#include <motionbus/modbus/server.hpp>
#include <motionbus/tformat/codec.hpp>
#include <motionbus/tformat/line.hpp>
#include <motionbus/tformat/receiver.hpp>

#include <cstddef>
#include <cstdint>
#include <new>

namespace mb = motionbus;
namespace tf = motionbus::tformat;
namespace md = motionbus::modbus;
namespace bs = motionbus::biss;

#define METER_OP extern "C" __attribute__((used, noinline))

extern "C" {
// Inputs and outputs, at symbols the meter reads from the ELF.
__attribute__((used, aligned(8))) std::uint8_t meter_in[512];
__attribute__((used)) std::uint32_t meter_in_size;
__attribute__((used, aligned(8))) std::uint32_t meter_out[64];
__attribute__((used)) std::uint8_t meter_adu[256];
__attribute__((used)) std::uint16_t meter_registers[128];
}

namespace {

mb::byte_view input() {
  return mb::byte_view(meter_in, meter_in_size);
}

// The results of the measured calls: each operation constructs its result here (in place: a
// returned result initialises the object directly, C++17's guaranteed copy elision, as where a
// firmware keeps what it decoded), and an unmeasured `op_report_*` call copies it into
// meter_out.
mb::decode_result<tf::response> tformat_result = mb::need_input{};
tf::line_result<tf::response> line_result = mb::need_input{};
mb::decode_result<md::rtu_frame> rtu_result = mb::need_input{};
mb::decode_result<md::response> client_result = mb::need_input{};
bs::frame_result<1> biss_result = mb::need_input{};

// Constructs the result of `call()` in `slot` (no temporary, no copy).
template <class R, class Call>
void keep(R& slot, Call&& call) {
  ::new (static_cast<void*>(&slot)) R(call());
}

void put_response(const mb::decode_result<tf::response>& r) {
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    meter_out[2] = r->abs;
    meter_out[3] = r->abm;
    meter_out[4] = r->almc;
    meter_out[5] = r->enid;
    meter_out[6] = r->sf;
    meter_out[7] = r->cf;
  }
}

// Bytes built by an operation: their size and address (the meter reads them from memory).
void put_bytes(mb::byte_view b) {
  meter_out[0] = static_cast<std::uint32_t>(b.size());
  meter_out[1] = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(b.data()));
}

// --- T-format ---------------------------------------------------------------------------------
tf::receiver rx;
motionbus::devices::ts5700n8500::emulator encoder;
motionbus::devices::ts5700n8500::reply encoder_reply;

// --- Modbus -------------------------------------------------------------------------------------
// The server's framer (a server's firmware links no client code), and the framer whose role is
// chosen at run time, measured beside it.
md::rtu_server_framer framer({1});
md::rtu_framer either_framer(md::framer_role::server, {1});

struct holding_registers {
  std::uint8_t read_registers(std::uint8_t, std::uint16_t address, mb::span<std::uint16_t> out) {
    if (address + out.size() > 128U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = meter_registers[address + i];
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> in) {
    if (address + in.size() > 128U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < in.size(); ++i) {
      meter_registers[address + i] = in[i];
    }
    return 0;
  }
};

// The same registers through the big-endian accessors (the server then needs no register
// buffer and no conversion).
struct holding_registers_be {
  std::uint8_t read_registers_be(std::uint8_t, std::uint16_t address, std::uint16_t quantity,
                                 mb::mutable_byte_view out) {
    if (address + quantity > 128U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      const std::uint16_t v = meter_registers[address + i];
      out[2 * i] = static_cast<std::uint8_t>(v >> 8U);
      out[2 * i + 1] = static_cast<std::uint8_t>(v);
    }
    return 0;
  }
  std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity,
                                  mb::byte_view data) {
    if (address + quantity > 128U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      meter_registers[address + i] = md::register_at(data, i);
    }
    return 0;
  }
};

// --- BiSS-C --------------------------------------------------------------------------------------
struct register_file {
  std::uint8_t bytes[128];
  bool readable(std::uint8_t) const { return true; }
  bool writable(std::uint8_t) const { return true; }
  bool ready() const { return true; }
  std::uint8_t read(std::uint8_t a) { return bytes[a & 0x7FU]; }
  void write(std::uint8_t a, std::uint8_t v) { bytes[a & 0x7FU] = v; }
};
register_file biss_registers;
mb::devices::absys::emulator absys;
mb::devices::sm_unit::emulator sm_unit;
bs::control_master master;
bs::control_slave<register_file> slave(biss_registers);
std::uint8_t master_read[4];

}  // namespace

// T-format ---------------------------------------------------------------------------------------
METER_OP void op_tformat_encode_request_id3() {
  const auto n = tf::encode_request(tf::data_id::read_all, mb::mutable_byte_view(meter_adu, 4));
  put_bytes(mb::byte_view(meter_adu, n.value_or(0)));
}
METER_OP void op_tformat_encode_request_id6(unsigned address, unsigned data) {
  const auto n =
      tf::encode_request(tf::data_id::eeprom_write, static_cast<std::uint8_t>(address),
                         static_cast<std::uint8_t>(data), mb::mutable_byte_view(meter_adu, 4));
  put_bytes(mb::byte_view(meter_adu, n.value_or(0)));
}
METER_OP void op_tformat_decode_response() {
  keep(tformat_result, [] { return tf::decode_response(input()); });
}
METER_OP void op_report_tformat() {
  put_response(tformat_result);
}
// `code`: the Data ID of the request the receiver is told was sent.
METER_OP void op_tformat_receiver_start(unsigned code) {
  rx = tf::receiver();
  tformat_result = mb::need_input{};
  const std::uint8_t request[1] = {tf::control_field(static_cast<std::uint8_t>(code))};
  rx.sent(mb::byte_view(request, 1));
}
// The receive interrupt's call: put() one byte; the meter passes what it returned to the
// report, which reads the receiver's result() when it was true.
METER_OP bool op_tformat_receiver_byte(unsigned byte) {
  return rx.put(static_cast<std::uint8_t>(byte));
}
METER_OP void op_report_receiver(unsigned ready) {
  if (ready != 0U) {
    tformat_result = rx.result();
  } else {
    tformat_result = mb::need_input{};
  }
  put_response(tformat_result);
}
METER_OP void op_tformat_line_decode() {
  keep(line_result, [] {
    return tf::decode_response_line(
        mb::span<const std::uint32_t>(reinterpret_cast<const std::uint32_t*>(meter_in),
                                      (meter_in_size + 31U) / 32U),
        mb::bit_order::msb_first, meter_in_size);
  });
}
METER_OP void op_report_line() {
  const auto& r = line_result;
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    meter_out[2] = r->frame.abs;
    meter_out[3] = r->frame.abm;
    meter_out[4] = r->frame.almc;
    meter_out[5] = r->frame.enid;
    meter_out[6] = r->frame.sf;
    meter_out[7] = r->frame.cf;
    meter_out[8] = static_cast<std::uint32_t>(r->start_bit);
  }
}
METER_OP void op_tformat_encoder_setup(unsigned single_turn, unsigned turns) {
  encoder = motionbus::devices::ts5700n8500::emulator();
  encoder.set_position(single_turn, turns);
}
METER_OP void op_tformat_encoder_respond(unsigned now_us) {
  encoder_reply = encoder.respond(input(), now_us);
  put_bytes(encoder_reply.view());
}

// Modbus
// -------------------------------------------------------------------------------------------
METER_OP void op_modbus_crc16_bitwise() {
  meter_out[0] = mb::crc16_modbus<mb::crc_table_size::bitwise>::compute(input());
}
METER_OP void op_modbus_crc16_nibble() {
  meter_out[0] = mb::crc16_modbus<mb::crc_table_size::nibble>::compute(input());
}
METER_OP void op_modbus_crc16_byte() {
  meter_out[0] = mb::crc16_modbus<mb::crc_table_size::byte>::compute(input());
}
METER_OP void op_modbus_framer_start() {
  framer = md::rtu_server_framer({1});
  rtu_result = mb::need_input{};
}
METER_OP bool op_modbus_framer_byte(unsigned byte) {
  return framer.put(static_cast<std::uint8_t>(byte));
}
METER_OP void op_modbus_either_framer_start() {
  either_framer = md::rtu_framer(md::framer_role::server, {1});
  rtu_result = mb::need_input{};
}
METER_OP bool op_modbus_either_framer_byte(unsigned byte) {
  return either_framer.put(static_cast<std::uint8_t>(byte));
}
METER_OP void op_report_rtu();
// What the last put() settled (`ready`: what it returned), reported as op_report_rtu does.
template <class Framer>
void report_put(const Framer& f, unsigned ready) {
  if (ready != 0U) {
    rtu_result = f.result();
  } else {
    rtu_result = mb::need_input{};
  }
  op_report_rtu();
}
METER_OP void op_report_either_framer(unsigned ready) {
  report_put(either_framer, ready);
}
METER_OP void op_report_framer(unsigned ready) {
  report_put(framer, ready);
}
METER_OP void op_report_rtu() {
  const auto& r = rtu_result;
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    meter_out[2] = r->slave;
    meter_out[3] = static_cast<std::uint32_t>(r->pdu.size());
    meter_out[4] = r->pdu[0];
    meter_out[5] = r->crc;
  }
}
METER_OP void op_modbus_decode_rtu() {
  keep(rtu_result, [] { return md::decode_rtu(input()); });
}
METER_OP void op_modbus_client_fc03(unsigned quantity) {
  mb::byte_view pdu;
  {
    const auto f = md::decode_rtu(input());
    if (!f.is_complete()) {
      client_result = mb::decode_failure{f.error(), 0};
      return;
    }
    pdu = f->pdu;
  }
  keep(client_result, [&] {
    return md::decode_read_response(md::function_code::read_holding_registers,
                                    static_cast<std::uint16_t>(quantity), pdu);
  });
}
METER_OP void op_report_client() {
  const auto& r = client_result;
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    std::uint32_t sum = 0;
    std::uint32_t mix = 0;
    const std::size_t n = r->quantity;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t v = md::register_at(r->data, i);
      sum += v;
      mix = (mix * 31U) ^ v;
    }
    meter_out[2] = static_cast<std::uint32_t>(n);
    meter_out[3] = sum;
    meter_out[4] = mix;
  }
}
// A server's work from the frame the framer checked (rtu_result, set by op_modbus_decode_rtu
// outside the measurement) to the response ADU.
METER_OP void op_modbus_serve_frame() {
  holding_registers_be device;
  const auto n =
      md::serve_frame(device, 1, rtu_result.value(), mb::mutable_byte_view(meter_adu, 256));
  put_bytes(mb::byte_view(meter_adu, n.value_or(0)));
}
METER_OP void op_modbus_serve() {
  holding_registers device;
  const auto n = md::serve_rtu(device, 1, input(), mb::mutable_byte_view(meter_adu, 256));
  put_bytes(mb::byte_view(meter_adu, n.value_or(0)));
}
METER_OP void op_modbus_encode_request_fc03(unsigned address, unsigned quantity) {
  std::uint8_t pdu[5];
  const auto p = md::encode_read(
      md::function_code::read_holding_registers, static_cast<std::uint16_t>(address),
      static_cast<std::uint16_t>(quantity), mb::mutable_byte_view(pdu, sizeof pdu));
  const auto a =
      md::encode_rtu(17, mb::byte_view(pdu, p.value_or(0)), mb::mutable_byte_view(meter_adu, 256));
  put_bytes(mb::byte_view(meter_adu, a.value_or(0)));
}

// BiSS-C
// --------------------------------------------------------------------------------------------
METER_OP void op_biss_decode_frame() {
  keep(biss_result, [] {
    return bs::decode_frame(
        mb::span<const std::uint32_t>(reinterpret_cast<const std::uint32_t*>(meter_in), 2),
        meter_in_size, bs::absys_layout);
  });
}
METER_OP void op_report_biss() {
  const auto& r = biss_result;
  const auto& d = r->slaves[0];
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    meter_out[2] = static_cast<std::uint32_t>(d.single_turn);
    meter_out[3] = (d.ne ? 1U : 0U) | (d.nw ? 2U : 0U) | (r->cds ? 4U : 0U);
    meter_out[4] = d.crc;
    meter_out[5] = static_cast<std::uint32_t>(r->start);
  }
}
METER_OP void op_biss_crc6(unsigned high, unsigned low) {
  const std::uint64_t bits = (static_cast<std::uint64_t>(high) << 32U) | low;
  meter_out[0] = mb::crc6_biss<>().update_bits(bits, 34).value();
}
METER_OP void op_biss_control_start(unsigned address) {
  master = bs::control_master();
  slave = bs::control_slave<register_file>(biss_registers);
  for (unsigned i = 0; i < 128U; ++i) {
    biss_registers.bytes[i] = meter_in[i];
  }
  meter_out[1] = static_cast<std::uint32_t>(master.start_read(
      0, static_cast<std::uint8_t>(address), mb::mutable_byte_view(master_read, 2)));
}
METER_OP unsigned op_biss_master_step(unsigned cds) {
  return master.step(cds != 0U) ? 1U : 0U;
}
METER_OP unsigned op_biss_slave_step(unsigned cdm) {
  return slave.step(cdm != 0U) ? 1U : 0U;
}
METER_OP void op_report_control() {
  meter_out[0] = static_cast<std::uint32_t>(master.state());
  meter_out[2] = master_read[0];
  meter_out[3] = master_read[1];
  meter_out[4] = static_cast<std::uint32_t>(master.error());
}

// --- device emulators ---------------------------------------------------------------------------
METER_OP void op_absys_setup(unsigned position) {
  absys.set_position(position);
}
// One frame of the ABSYS emulator as a bench drives it: the frame's SL samples, then the CDM
// bit the master sent with it.
METER_OP void op_absys_frame() {
  const auto n = absys.frame(mb::span<std::uint32_t>(meter_out + 1, 2));
  absys.control(false);
  meter_out[0] = static_cast<std::uint32_t>(n.value_or(0));
}
// The SM unit emulator behind serve_rtu, one request ADU in meter_in, the response in meter_adu.
METER_OP void op_sm_unit_serve() {
  const auto n = md::serve_rtu(sm_unit, 1, input(), mb::mutable_byte_view(meter_adu, 256));
  put_bytes(mb::byte_view(meter_adu, n.value_or(0)));
}

// Self-checks of the meter ------------------------------------------------------------------------
// selfcheck_loop(n): 2 + 2n instructions (n >= 1); selfcheck_stack: 64 bytes below the caller's
// stack pointer written, 4 instructions; selfcheck_it (Cortex-M4): 5 instructions whichever way
// the IT block's condition goes.
#if defined(__arm__)
extern "C" __attribute__((naked, used)) void selfcheck_loop(unsigned) {
  __asm__ volatile(
      "   .syntax unified\n"
      "1: subs r0, r0, #1\n"
      "   bne 1b\n"
      "   movs r0, #0\n"
      "   bx lr\n");
}
extern "C" __attribute__((naked, used)) void selfcheck_stack(unsigned) {
  __asm__ volatile(
      "   .syntax unified\n"
      "   sub sp, #64\n"
      "   str r0, [sp]\n"
      "   add sp, #64\n"
      "   bx lr\n");
}
// selfcheck_thumb2: one Thumb-2 instruction (add.w), which the Cortex-M0+ check must refuse.
extern "C" __attribute__((naked, used)) void selfcheck_thumb2(unsigned) {
  __asm__ volatile(
      "   .inst.w 0xF1000001\n"
      "   bx lr\n");
}
#if defined(__ARM_ARCH_7EM__)
extern "C" __attribute__((naked, used)) void selfcheck_it(unsigned) {
  __asm__ volatile(
      "   .syntax unified\n"
      "   cmp r0, #0\n"
      "   ite eq\n"
      "   moveq r0, #1\n"
      "   movne r0, #2\n"
      "   bx lr\n");
}
#endif
#elif defined(__riscv)
extern "C" __attribute__((naked, used)) void selfcheck_loop(unsigned) {
  __asm__ volatile(
      "1: addi a0, a0, -1\n"
      "   bnez a0, 1b\n"
      "   li a0, 0\n"
      "   ret\n");
}
extern "C" __attribute__((naked, used)) void selfcheck_stack(unsigned) {
  __asm__ volatile(
      "   addi sp, sp, -64\n"
      "   sw a0, 0(sp)\n"
      "   addi sp, sp, 64\n"
      "   ret\n");
}
#endif

// --- Modbus ASCII (issue 25): the ASCII framer of a server, per character -------------------
namespace {
md::ascii_framer ascii_server(md::framer_role::server, {1});
mb::decode_result<md::ascii_frame> ascii_result = mb::need_input{};
}  // namespace
METER_OP void op_modbus_ascii_framer_start() {
  ascii_server = md::ascii_framer(md::framer_role::server, {1});
  ascii_result = mb::need_input{};
}
METER_OP bool op_modbus_ascii_framer_byte(unsigned c) {
  return ascii_server.put(static_cast<std::uint8_t>(c));
}
// What the last put() settled (`ready`: what it returned): status, error, slave, PDU size, its
// first byte, the LRC.
METER_OP void op_report_ascii_framer(unsigned ready) {
  ascii_result = ready != 0U ? ascii_server.result() : mb::need_input{};
  const auto& r = ascii_result;
  meter_out[0] = static_cast<std::uint32_t>(r.status());
  meter_out[1] = static_cast<std::uint32_t>(r.error());
  if (r.is_complete()) {
    meter_out[2] = r->slave;
    meter_out[3] = static_cast<std::uint32_t>(r->pdu.size());
    meter_out[4] = r->pdu[0];
    meter_out[5] = r->lrc;
  }
}

// --- encoder position and link health (issue 27): one update per read period -----------------
namespace {
// A TS5700N8500 read with ID3 (2^17 counts x 2^16 turns), and one read with ID0 alone (the
// single-turn value: 2^17), each at most 700 counts a read (6000 min^-1 read every 50 us).
mb::position_tracker multi_turn(mb::position_config::from_bits(17, 16, 700));
mb::position_tracker single_turn(mb::position_config::from_bits(17, 0, 700));
mb::link_health link({3, 3});
void put_position(mb::position_status st, const mb::position_tracker& t) {
  meter_out[0] = static_cast<std::uint32_t>(st);
  const auto c = static_cast<std::uint64_t>(t.counts());
  meter_out[1] = static_cast<std::uint32_t>(c);
  meter_out[2] = static_cast<std::uint32_t>(c >> 32U);
  meter_out[3] = static_cast<std::uint32_t>(t.step());
}
}  // namespace
// Seeds the trackers (unmeasured): multi_turn with (abs, abm), single_turn with abs.
METER_OP void op_position_setup(unsigned abs, unsigned abm) {
  multi_turn.reset();
  single_turn.reset();
  (void)multi_turn.update(abs, abm);
  (void)single_turn.update(abs);
}
// The measured calls: an ID3 reading (ABS, ABM) and an ID0 reading (ABS).
METER_OP void op_position_update_id3(unsigned abs, unsigned abm) {
  put_position(multi_turn.update(abs, abm), multi_turn);
}
METER_OP void op_position_update_id0(unsigned abs) {
  put_position(single_turn.update(abs), single_turn);
}
// One transaction's outcome into the link health: the event and the consecutive failures.
METER_OP void op_link_health_record(unsigned outcome) {
  const mb::link_event e = link.record(static_cast<mb::link_outcome>(outcome));
  meter_out[0] = static_cast<std::uint32_t>(e);
  meter_out[1] = link.counters().consecutive_failures;
  meter_out[2] = link.counters().frames;
}

// The image's entry (never run by the meter: it calls functions one at a time).
extern "C" __attribute__((used)) void meter_entry() {}
