// The AMO ABSYS emulator driven by the library's BiSS master over an in-memory bit stream:
// identity, EDS, offset, preset, commands, latched errors, write wait states.
#include "motionbus/devices/absys_emulator.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "motionbus/biss.hpp"
#include "motionbus/devices/absys.hpp"

using namespace motionbus;
namespace bs = motionbus::biss;
namespace ab = motionbus::devices::absys;

namespace {

// One frame on an in-memory line: the emulator's SL samples, decoded as a master would, the
// CDS handed to the control master, its CDM handed back to the emulator.
struct bench {
  ab::emulator& enc;
  bs::control_master master;
  std::size_t frames = 0;
  bs::slave_data last{};

  explicit bench(ab::emulator& e) : enc(e) {}

  bool frame() {
    std::uint32_t words[3] = {};
    const auto n = enc.frame(span<std::uint32_t>(words, 3), 2, 1 + frames % 3U);
    REQUIRE(n.ok());
    const auto r = bs::decode_frame(span<const std::uint32_t>(words, 3), *n, ab::layout);
    REQUIRE(r.is_complete());
    last = r->slaves[0];
    enc.control(master.step(r->cds));
    ++frames;
    return master.busy();
  }
  errc run() {
    while (frame()) {
    }
    return master.error();
  }
  errc read(std::uint8_t address, std::uint8_t* out, std::size_t n) {
    REQUIRE(master.start_read(0, address, mutable_byte_view(out, n)) == errc::ok);
    return run();
  }
  errc write(std::uint8_t address, std::vector<std::uint8_t> data) {
    REQUIRE(master.start_write(0, address, byte_view(data.data(), data.size())) == errc::ok);
    return run();
  }
  // Frames with no access running until the encoder has finished its write.
  void settle() {
    while (enc.busy()) {
      frame();
    }
  }
  std::uint8_t read1(std::uint8_t address) {
    std::uint8_t v = 0;
    REQUIRE(read(address, &v, 1) == errc::ok);
    return v;
  }
};

}  // namespace

TEST_CASE("ABSYS emulator: sensor data and identity through the BiSS master") {
  ab::emulator enc;
  enc.set_position(123456);
  bench b(enc);
  b.frame();
  CHECK(b.last.single_turn == 123456);
  CHECK(b.last.ne);
  CHECK(b.last.nw);
  CHECK(b.read1(ab::reg::manufacturer_id) == 'A');
  CHECK(b.read1(ab::reg::manufacturer_id + 1) == 'm');
  CHECK(b.read1(ab::reg::revision) == 0x03);
  std::uint8_t id[2] = {};
  REQUIRE(b.read(ab::reg::profile_id, id, 2) == errc::ok);
  CHECK(id[0] == 0x63);
  CHECK(id[1] == 0x20);
  // §2.4: ASCII at 0x44..0x46, the serial number 0x00BC614E at 0x47..0x4A, ASCII at 0x4B
  std::uint8_t sn[8] = {};
  REQUIRE(b.read(ab::reg::serial_number, sn, 8) == errc::ok);
  CHECK(sn[0] == 'A');
  CHECK(sn[1] == 'T');
  CHECK(sn[2] >= 0x20);  // printable ASCII
  CHECK(sn[2] <= 0x7E);
  CHECK(sn[3] == 0x00);
  CHECK(sn[4] == 0xBC);
  CHECK(sn[5] == 0x61);
  CHECK(sn[6] == 0x4E);
  CHECK(sn[7] >= 0x20);
  CHECK(sn[7] <= 0x7E);
  CHECK(b.read1(0x47) == 0x00);
  CHECK(b.read1(0x4A) == 0x4E);
  // the EDS through the bank window
  CHECK(b.read1(ab::reg::bank_select) == 0x80);
  std::uint8_t bank[64] = {};
  REQUIRE(b.read(0x00, bank, 64) == errc::ok);
  CHECK(bs::decode_eds_common(byte_view(bank, 64), {true}).is_complete());
  REQUIRE(b.write(ab::reg::bank_select, {0x81}) == errc::ok);
  REQUIRE(b.read(0x00, bank, 64) == errc::ok);
  const auto p = bs::decode_bp3(byte_view(bank, 64), {true});
  REQUIRE(p.is_complete());
  CHECK(p->pulses_per_revolution() == 512U * 1024U);
  // device configuration banks are not for users
  REQUIRE(b.write(ab::reg::bank_select, {0x05}) == errc::ok);
  std::uint8_t x = 0;
  CHECK(b.read(0x00, &x, 1) == errc::biss_access_denied);
  // read-only registers refuse writes
  CHECK(b.write(ab::reg::revision, {0x04}) == errc::biss_access_denied);
}

TEST_CASE("ABSYS emulator: offset, preset mode and commands, with write wait states") {
  ab::emulator enc;  // rotary, 512 x 2^10 pulses per revolution, 100 us frames
  enc.set_position(5000);
  bench b(enc);
  // offset 0x00000064 through the four registers: 4 ms each = 40 frames of wait states
  const std::size_t before = b.frames;
  REQUIRE(b.write(ab::reg::offset, {0x00, 0x00, 0x00, 0x64}) == errc::ok);
  CHECK(enc.offset() == 100);
  CHECK(b.frames - before >= 3U * 40U);
  b.frame();
  CHECK(b.last.single_turn == 4900);
  std::uint8_t pos[4] = {};
  // the last byte's write is still in progress: a new access is refused (§3.1, §3.2)
  CHECK(enc.busy());
  CHECK(b.read(ab::reg::position, pos, 4) == errc::biss_access_denied);
  CHECK(enc.refused_while_busy() == 1);
  b.settle();
  REQUIRE(b.read(ab::reg::position, pos, 4) == errc::ok);
  CHECK(((pos[0] << 24U) | (pos[1] << 16U) | (pos[2] << 8U) | pos[3]) == 4900U);
  // offset above the position: modulo pulses per revolution
  enc.set_position(50);
  b.frame();
  CHECK(b.last.single_turn == 512U * 1024U - 50U);
  // preset mode 1: the offset is ignored
  REQUIRE(b.write(ab::reg::preset_mode, {0x01}) == errc::ok);
  b.frame();
  CHECK(b.last.single_turn == 50);
  b.settle();
  REQUIRE(b.write(ab::reg::preset_mode, {0x00}) == errc::ok);
  b.settle();
  // command 02: offset = actual position; 17 ms = 170 frames before the next access is served
  enc.set_position(777);
  REQUIRE(b.write(ab::reg::command, {0x02}) == errc::ok);
  CHECK(enc.offset() == 777);
  const std::size_t t0 = b.frames;
  std::uint8_t low = 0;
  CHECK(b.read(ab::reg::offset + 3, &low, 1) == errc::biss_access_denied);
  b.settle();
  CHECK(b.frames - t0 >= 165U);
  CHECK(b.read1(ab::reg::offset + 3) == (777 & 0xFF));
  b.frame();
  CHECK(b.last.single_turn == 0);
  // command 03: offset reset
  REQUIRE(b.write(ab::reg::command, {0x03}) == errc::ok);
  CHECK(enc.offset() == 0);
  b.settle();
  b.frame();
  CHECK(b.last.single_turn == 777);
}

TEST_CASE("ABSYS emulator: an access while a write is in progress is refused (§3.1-§3.4)") {
  ab::emulator enc;
  bench b(enc);
  // the EDS bank register is one of the "other registers": > 4 ms
  // (a refused access takes 32 frames, preamble and header: less than the 40 of a write)
  REQUIRE(b.write(ab::reg::eds_bank, {0x81}) == errc::ok);
  CHECK(enc.busy());
  CHECK(b.write(ab::reg::preset_mode, {0x01}) == errc::biss_access_denied);
  CHECK(enc.read_register(ab::reg::preset_mode) == 0);  // the refused write did nothing
  b.settle();
  REQUIRE(b.write(ab::reg::eds_bank, {0x81}) == errc::ok);
  std::uint8_t v = 0;
  CHECK(b.read(ab::reg::revision, &v, 1) == errc::biss_access_denied);
  CHECK(enc.refused_while_busy() == 2);
  b.settle();
  CHECK(b.read1(ab::reg::eds_bank) == 0x81);
  // bank selection and command 06 are cached and not persistent: instant, nothing refused
  REQUIRE(b.write(ab::reg::bank_select, {0x81}) == errc::ok);
  CHECK(!enc.busy());
  REQUIRE(b.write(ab::reg::command, {0x06}) == errc::ok);
  CHECK(b.read1(ab::reg::bank_select) == 0x81);
  CHECK(enc.refused_while_busy() == 2);
  // the profile's table of write times is the emulator's
  CHECK(ab::write_time_us(ab::reg::bank_select, 0x84) == 0);
  CHECK(ab::write_time_us(ab::reg::command, 0x06) == 0);
  CHECK(ab::write_time_us(ab::reg::command, 0x02) == ab::offset_command_us);
  CHECK(ab::write_time_us(ab::reg::eds_bank, 0x80) == ab::persistent_write_us);
  CHECK(ab::write_time_us(0x10, 0x00) == ab::persistent_write_us);
}

TEST_CASE("ABSYS emulator: linear encoder offset is signed") {
  ab::emulator_config cfg;
  cfg.type = bs::encoder_type::linear;
  cfg.sip_count = 1000;
  cfg.sip_resolution = 0;
  ab::emulator enc(cfg);
  enc.set_position(10);
  bench b(enc);
  REQUIRE(b.write(ab::reg::offset, {0x00, 0x00, 0x00, 0x14}) == errc::ok);
  b.frame();
  CHECK(ab::linear_position(enc.absolute_position(), enc.offset()) == -10);
  CHECK(static_cast<std::int32_t>(b.last.single_turn - 0x100000000ULL) == -10);
}

TEST_CASE("ABSYS emulator: 0x6B latches nE/nW active low, 0x03 healthy; command 06 -> 0x03") {
  // ABSYS document §2.1 (default 0x03), §2.7 (bit 0 warning, bit 1 error, latched until command
  // 06), §1 (nE/nW "Active on Low (0)"; the warning "is always inactive and it is set to '1'")
  ab::emulator enc;
  bench b(enc);
  CHECK(b.read1(ab::reg::error_status) == 0x03);  // power-on default: no error, no warning
  REQUIRE(b.write(ab::reg::command, {0x06}) == errc::ok);
  CHECK(b.read1(ab::reg::error_status) == 0x03);  // reset: healthy, not 0x00
  enc.set_error(ab::sensor_error::in_operation);
  b.frame();
  CHECK(b.last.error());                          // nE low in the frame ...
  CHECK(b.read1(ab::reg::error_status) == 0x01);  // ... bit 1 low in the register
  enc.set_error(ab::sensor_error::none);
  b.frame();
  CHECK(!b.last.error());                         // regained during operation
  CHECK(b.read1(ab::reg::error_status) == 0x01);  // but latched; the warning bit stays 1
  REQUIRE(b.write(ab::reg::command, {0x06}) == errc::ok);
  CHECK(b.read1(ab::reg::error_status) == 0x03);
  enc.set_error(ab::sensor_error::at_power_on);  // stays
  enc.set_error(ab::sensor_error::none);
  b.frame();
  CHECK(b.last.error());
  REQUIRE(b.write(ab::reg::command, {0x06}) == errc::ok);
  CHECK(b.read1(ab::reg::error_status) == 0x01);  // an error still present latches again
  CHECK(enc.error_status() == 0x01);
  // the user bank is free to write and read
  REQUIRE(b.write(ab::reg::bank_select, {0x84}) == errc::ok);
  REQUIRE(b.write(0x10, {1, 2, 3}) == errc::ok);
  b.settle();
  std::uint8_t u[3] = {};
  REQUIRE(b.read(0x10, u, 3) == errc::ok);
  CHECK(u[2] == 3);
  CHECK(enc.user_bank()[0x11] == 2);
}

TEST_CASE("ABSYS emulator: 0x6B latches the error when it is set, not when a frame is read") {
  // docs/biss.md §4: the register latches nE where it changes (set_error) and after command
  // 06; an error gone before the next frame is still latched; command 06 leaves the frame's
  // power-on error alone (§1 "remains latched", the library's choice)
  ab::emulator enc;
  bench b(enc);
  enc.set_error(ab::sensor_error::in_operation);
  enc.set_error(ab::sensor_error::none);  // gone before any frame carried it
  CHECK(enc.error_status() == 0x01);
  b.frame();
  CHECK(!b.last.error());
  CHECK(b.read1(ab::reg::error_status) == 0x01);
  REQUIRE(b.write(ab::reg::command, {0x06}) == errc::ok);
  CHECK(b.read1(ab::reg::error_status) == 0x03);
  enc.set_error(ab::sensor_error::at_power_on);
  REQUIRE(b.write(ab::reg::command, {0x06}) == errc::ok);
  b.frame();
  CHECK(b.last.error());  // nE still low after command 06
  CHECK(b.read1(ab::reg::error_status) == 0x01);
}

TEST_CASE("ABSYS emulator registers: banks, command, preset, reserve, undefined addresses") {
  ab::emulator e;
  ab::emulator::registers regs(e);
  regs.write(ab::reg::bank_select, ab::bank::eds_reserved_3);
  CHECK(e.selected_bank() == ab::bank::eds_reserved_3);
  CHECK(regs.read(0x00) == 0);  // reserved EDS banks read 0x00
  regs.write(ab::reg::eds_bank, 0x81);
  CHECK(regs.read(ab::reg::eds_bank) == 0x81);
  CHECK(regs.read(ab::reg::command) == 0);
  CHECK(regs.read(ab::reg::preset_mode) == e.read_register(ab::reg::preset_mode));
  e.set_functional_reserve(200, 1);
  CHECK(regs.read(ab::reg::functional_reserve) == 200);
  CHECK(regs.read(ab::reg::functional_reserve_indicator) == 1);
  CHECK(regs.read(0x50) == 0);         // no register there
  regs.write(ab::reg::command, 0x77);  // no such command: nothing happens
  CHECK(e.offset() == 0);
}

TEST_CASE("ABSYS emulator: its error status register decodes as the error bit it sends") {
  ab::emulator enc;
  CHECK(ab::decode_error_status(enc.error_status()).error == !enc.values().ne);
  enc.set_error(ab::sensor_error::in_operation);
  CHECK(ab::decode_error_status(enc.error_status()).error);
  CHECK(!enc.values().ne);
  CHECK(!ab::decode_error_status(enc.error_status()).warning);  // never on the ABSYS
}

TEST_CASE("ABSYS emulator: serial number and device ID read by the master decode (§2.4, §2.5)") {
  ab::emulator enc;
  bench b(enc);
  std::uint8_t raw[ab::serial_number_size] = {};
  REQUIRE(b.read(ab::reg::serial_number, raw, sizeof raw) == errc::ok);
  const auto e = ab::decode_serial_number(raw);
  REQUIRE(e.is_complete());
  CHECK(e->number == 0x00BC614EU);
  std::uint8_t raw_id[ab::device_id_size] = {};
  REQUIRE(b.read(ab::reg::device_id, raw_id, sizeof raw_id) == errc::ok);
  CHECK(ab::decode_device_id(raw_id)->number == 0x0011F58EU);
}

TEST_CASE("ABSYS emulator: frame() into a plain array, decoded from it; the line delay") {
  ab::emulator enc;
  enc.set_position(0x0004CDEFU);
  std::uint32_t words[2] = {0xFFFFFFFFU, 0xFFFFFFFFU};
  const auto n = enc.frame(words, 4, 2);  // line delay 4, Ack 2
  REQUIRE(n.ok());
  CHECK(*n == 4U + 2U + 2U + 40U);
  const auto r = bs::decode_frame(words, 64, ab::layout);
  REQUIRE(r.is_complete());
  const bs::slave_data& d = r->slaves[0];
  CHECK(r->line_delay == 4);  // the idle samples alone
  CHECK(r->ack_bits() == 2);
  CHECK(r->start == 6);  // the Start bit after both
  CHECK(d.single_turn == 0x0004CDEFU);
}

TEST_CASE("ABSYS emulator registers: what each bank and address allows, refused writes ignored") {
  ab::emulator e;
  ab::emulator::registers regs(e);
  // the bank window: readable in the EDS and user banks only, writable in the user bank only
  CHECK(regs.readable(0x00));
  CHECK_FALSE(regs.writable(0x00));
  regs.write(0x00, 0x55);  // the EDS common bank: ignored
  CHECK(regs.read(0x00) != 0x55);
  regs.write(ab::reg::bank_select, ab::bank::user);
  CHECK(regs.writable(0x00));
  regs.write(0x00, 0x55);
  CHECK(regs.read(0x00) == 0x55);
  regs.write(ab::reg::bank_select, 0x90);  // past the user bank: nothing in the window
  CHECK(e.selected_bank() == 0x90);
  CHECK_FALSE(regs.readable(0x00));
  regs.write(ab::reg::bank_select, 0x7F);  // below the EDS banks
  CHECK_FALSE(regs.readable(0x00));
  regs.write(ab::reg::bank_select, ab::bank::not_allowed);  // 0xFF: ignored
  CHECK(e.selected_bank() == 0x7F);
  // the writable registers past the window, and some that are not
  CHECK(regs.writable(ab::reg::bank_select));
  CHECK(regs.writable(ab::reg::eds_bank));
  CHECK(regs.writable(ab::reg::offset + 3U));
  CHECK(regs.writable(ab::reg::command));
  CHECK(regs.writable(ab::reg::preset_mode));
  CHECK_FALSE(regs.writable(ab::reg::serial_number));
  CHECK_FALSE(regs.writable(ab::reg::offset + 4U));
  CHECK_FALSE(regs.writable(0x50));
  // a write to a read-only or undefined address changes nothing
  const std::uint8_t serial = regs.read(ab::reg::serial_number);
  regs.write(ab::reg::serial_number, static_cast<std::uint8_t>(serial + 1U));
  CHECK(regs.read(ab::reg::serial_number) == serial);
  regs.write(0x50, 0x12);
  CHECK(regs.read(0x50) == 0);
  CHECK(e.offset() == 0);
  // addresses past the 7-bit register map read 0
  CHECK(e.read_register(0x80) == 0);
  CHECK(e.read_register(0xFF) == 0);
}

TEST_CASE(
    "ABSYS emulator: functional reserve clamped to 254, indicator 0 or 1; SIP_RES too large") {
  ab::emulator e;
  ab::emulator::registers regs(e);
  e.set_functional_reserve(255, 0);
  CHECK(regs.read(ab::reg::functional_reserve) == 254);
  CHECK(regs.read(ab::reg::functional_reserve_indicator) == 0);
  e.set_functional_reserve(7, 9);
  CHECK(regs.read(ab::reg::functional_reserve) == 7);
  CHECK(regs.read(ab::reg::functional_reserve_indicator) == 1);
  ab::emulator_config cfg;
  cfg.sip_resolution = 32;  // past the emulator's limit, 31 (§2.9.4 allows 0 to 20): 0
  const ab::emulator wide(cfg);
  CHECK(wide.pulses_per_revolution() == 0U);
  CHECK(ab::emulator().pulses_per_revolution() == (std::uint64_t{512} << 10U));
}

TEST_CASE("ABSYS emulator as built: at 0, not busy, reserve 254, 100 us frames, frame defaults") {
  // §2.6: "After power-on the Functional Reserve will always be 254 till movement is
  // detected"; the indicator has no default in §2.1 ("-"): the emulator starts at 0. The frame
  // period (100 us, the header's "frame period of 100 µs or more") and frame()'s line delay 1
  // and Ack 1 are the defaults the Python binding repeats (python/src/absys.cpp: absys.Emulator
  // and its frame()); the position starts at 0 until set_position().
  ab::emulator e;
  CHECK(e.frame_period_us() == 100U);
  CHECK(e.absolute_position() == 0U);
  CHECK(e.reported_position() == 0U);
  CHECK(!e.busy());
  ab::emulator::registers regs(e);
  CHECK(regs.ready());
  CHECK(regs.read(ab::reg::functional_reserve) == 254);
  CHECK(regs.read(ab::reg::functional_reserve_indicator) == 0);
  std::uint32_t by_default[2] = {};
  std::uint32_t explicit_args[2] = {};
  const auto n = e.frame(by_default);
  REQUIRE(n.ok());
  CHECK(*n == 1U + 1U + 2U + 40U);  // line delay 1, Ack 1, Start and CDS, 40 bits of data
  CHECK(*n == *e.frame(explicit_args, 1, 1));
  CHECK(by_default[0] == explicit_args[0]);
  CHECK(by_default[1] == explicit_args[1]);
  std::uint32_t span_words[2] = {};
  CHECK(*e.frame(span<std::uint32_t>(span_words, 2)) == *n);
  CHECK(span_words[0] == explicit_args[0]);
  CHECK(span_words[1] == explicit_args[1]);
}

TEST_CASE("ABSYS emulator: sensor_error's numbers (interface: the Python binding's SensorError)") {
  // python/src/absys.cpp binds SensorError as none 0, in_operation 1, at_power_on 2
  CHECK(static_cast<int>(ab::sensor_error::none) == 0);
  CHECK(static_cast<int>(ab::sensor_error::in_operation) == 1);
  CHECK(static_cast<int>(ab::sensor_error::at_power_on) == 2);
}

TEST_CASE("ABSYS emulator: SIP_RES 31 still gives pulses per revolution, 32 does not") {
  // §2.9.4 allows SIP_RES 0 to 20; the emulator computes SIP_CNT x 2^SIP_RES up to 31, its own
  // limit (a 32-bit count so shifted fits 64 bits), and reports 0 above it
  ab::emulator_config cfg;
  cfg.sip_count = 1;
  cfg.sip_resolution = 31;
  const ab::emulator e(cfg);
  CHECK(e.pulses_per_revolution() == (std::uint64_t{1} << 31U));
  cfg.sip_resolution = 32;  // no pulses per revolution: the plain difference (rotary_position)
  const ab::emulator past(cfg);
  CHECK(past.pulses_per_revolution() == 0U);
}

TEST_CASE("ABSYS emulator registers: each multi-byte register's first and last byte, and past") {
  // §2.1: 0x40 bank selection "can be written or read" whatever the bank (§2.2); 0x4C..0x4F the
  // offset, 0x50..0x5F reserved (0x00); 0x60 the command register, R/W; 0x63..0x66 the
  // position, 0x67..0x69 reserved; 0x75..0x7C the device ID, 0x7D the revision
  ab::emulator e;
  ab::emulator::registers regs(e);
  regs.write(ab::reg::bank_select, 0x90);  // a reserved bank: the window closes, 0x40 does not
  CHECK_FALSE(regs.readable(0x3F));
  CHECK(regs.readable(ab::reg::bank_select));
  CHECK(regs.read(ab::reg::bank_select) == 0x90);
  const std::uint8_t offset[] = {0xA1, 0xB2, 0xC3, 0xD4};
  for (std::uint8_t i = 0; i < 4; ++i) {
    regs.write(static_cast<std::uint8_t>(ab::reg::offset + i), offset[i]);
  }
  CHECK(e.offset() == 0xA1B2C3D4U);
  CHECK(regs.read(ab::reg::serial_number + 7U) == 'C');  // the serial number's last byte
  for (std::uint8_t i = 0; i < 4; ++i) {
    CHECK(regs.read(static_cast<std::uint8_t>(ab::reg::offset + i)) == offset[i]);
  }
  CHECK(regs.read(ab::reg::offset + 4U) == 0);  // 0x50: reserved
  regs.write(ab::reg::command, 0x77);
  CHECK(regs.read(ab::reg::command) == 0x77);  // R/W: the value written reads back
  regs.write(ab::reg::preset_mode, static_cast<std::uint8_t>(ab::preset_mode::actual));
  e.set_position(0xCAFEBABEU);
  const std::uint8_t position[] = {0xCA, 0xFE, 0xBA, 0xBE};
  for (std::uint8_t i = 0; i < 4; ++i) {
    CHECK(regs.read(static_cast<std::uint8_t>(ab::reg::position + i)) == position[i]);
  }
  CHECK(regs.read(ab::reg::position + 4U) == 0);  // 0x67: reserved
  const ab::emulator_config cfg;
  for (std::uint8_t i = 0; i < ab::device_id_size; ++i) {
    CHECK(regs.read(static_cast<std::uint8_t>(ab::reg::device_id + i)) == cfg.device_id[i]);
  }
  CHECK(regs.read(ab::reg::revision) == ab::revision_03);
}
