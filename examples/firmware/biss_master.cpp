// motionbus firmware example — a BiSS-C master and an AMO ABSYS encoder in one image. No SPI is
// modelled by the emulators this runs on, so the encoder is the ABSYS emulator and the line an
// in-memory bit stream: each frame, the emulator's SL samples go through decode_frame exactly as
// an SPI capture would, the CDS bit feeds the register-access state machine, and its CDM bit
// goes back to the emulator. The master reads the position, the identity registers and the
// electronic data sheet, resets the errors and sets the offset (command 02), and reports each
// result as a line of text on the UART; the test command checks the lines.
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "motionbus/biss.hpp"
#include "motionbus/devices/absys.hpp"
#include "motionbus/devices/absys_emulator.hpp"
#include "report.hpp"

namespace mb = motionbus;
namespace bs = motionbus::biss;
namespace ab = motionbus::devices::absys;

namespace {

ab::emulator encoder;  // WMKA-style rotary: 512 periods x 2^10 = 524288 pulses per turn
bs::control_master master;
bs::slave_data last;
std::size_t line_delay = 0;

// One frame: the encoder's samples decoded, the CDS bit to the master, its CDM bit back.
bool frame() {
  std::uint32_t words[2] = {0xFFFFFFFFU, 0xFFFFFFFFU};
  const auto n = encoder.frame(words, 2, 1);  // a line delay of 2 bits, Ack 1
  const auto r = bs::decode_frame(words, 64, ab::layout);
  if (!n.ok() || !r.is_complete()) {
    return false;
  }
  last = r->slaves[0];
  line_delay = r->line_delay;
  encoder.control(master.step(r->cds));
  return true;
}

mb::errc finish() {
  while (master.busy()) {
    if (!frame()) {
      return mb::errc::no_frame;
    }
  }
  return master.error();
}

mb::errc read(std::uint8_t address, std::uint8_t* out, std::size_t n) {
  const mb::errc e = master.start_read(0, address, mb::mutable_byte_view(out, n));
  return e == mb::errc::ok ? finish() : e;
}

// Writes one register, then lets the frames run while the encoder completes the write (it
// refuses any access that arrives before: ABSYS document §3.2).
mb::errc write(std::uint8_t address, std::uint8_t value) {
  const std::uint8_t v[1] = {value};
  mb::errc e = master.start_write(0, address, mb::byte_view(v, 1));
  e = e == mb::errc::ok ? finish() : e;
  for (std::uint32_t t = 0; e == mb::errc::ok && t < ab::write_time_us(address, value);
       t += encoder.frame_period_us()) {
    if (!frame()) {
      return mb::errc::no_frame;
    }
  }
  return e;
}

void result(const char* what, mb::errc e) {
  if (e != mb::errc::ok) {
    report::text("error ");
    report::text(what);
    report::text(" ");
    report::text(mb::to_string(e));
    report::text("\n");
  }
}

}  // namespace

int main() {
  board::init();
  encoder.set_position(131072 + 4096);
  const bool ok = frame();
  report::text(ok ? "position " : "no frame ");
  report::dec(static_cast<std::uint32_t>(last.single_turn));
  report::text(" ne ");
  report::dec(last.ne ? 1U : 0U);
  report::text(" nw ");
  report::dec(last.nw ? 1U : 0U);
  report::text(" delay ");
  report::dec(static_cast<std::uint32_t>(line_delay));
  report::text("\n");

  std::uint8_t mfr[2] = {};
  std::uint8_t id[2] = {};
  std::uint8_t rev = 0;
  result("manufacturer", read(ab::reg::manufacturer_id, mfr, 2));
  result("revision", read(ab::reg::revision, &rev, 1));
  result("profile", read(ab::reg::profile_id, id, 2));
  const char name[3] = {static_cast<char>(mfr[0]), static_cast<char>(mfr[1]), '\0'};
  report::text("manufacturer ");
  report::text(name);
  report::text(" revision ");
  report::hex(rev, 2);
  report::text(" profile ");
  report::hex((static_cast<std::uint32_t>(id[0]) << 8U) | id[1], 4);
  report::text("\n");

  std::uint8_t bank[bs::bank_size] = {};
  result("eds common", read(0x00, bank, bs::bank_size));  // bank 0x80 after power-on
  const auto common = bs::decode_eds_common(mb::byte_view(bank, bs::bank_size));
  result("bank select", write(ab::reg::bank_select, ab::bank::eds_bp3));
  result("eds bp3", read(0x00, bank, bs::bank_size));
  const auto bp3 = bs::decode_bp3(mb::byte_view(bank, bs::bank_size));
  if (common.is_complete() && bp3.is_complete()) {
    const bs::crc_format crc = bs::crc_from_eds(bp3->crc_poly, bp3->crc_start);
    report::text("eds version ");
    report::dec(common->version);
    report::text(" banks ");
    report::dec(common->length);
    report::text(bp3->type == bs::encoder_type::rotary ? " rotary" : " linear");
    report::text(" pulses ");
    report::dec(static_cast<std::uint32_t>(bp3->pulses_per_revolution()));
    report::text(" bits ");
    report::dec(bp3->layout().data_bits());
    report::text(" crc ");
    report::hex((1U << crc.width) | crc.poly, 2);
    report::text("\n");
  }

  // Error status 0x6B: the frame's nE and nW latched, active low (0x03: no error).
  std::uint8_t status = 0;
  result("status", read(ab::reg::error_status, &status, 1));
  encoder.set_error(ab::sensor_error::in_operation);  // one frame with nE low, then regained
  (void)frame();
  encoder.set_error(ab::sensor_error::none);
  std::uint8_t latched = 0;
  result("status", read(ab::reg::error_status, &latched, 1));
  result("reset errors",
         write(ab::reg::command, static_cast<std::uint8_t>(ab::command::reset_errors)));
  std::uint8_t cleared = 0;
  result("status", read(ab::reg::error_status, &cleared, 1));
  report::text("status ");
  report::hex(status, 2);
  report::text(" error ");
  report::hex(latched, 2);
  report::text(" after reset ");
  report::hex(cleared, 2);
  report::text("\n");

  result("set offset",
         write(ab::reg::command, static_cast<std::uint8_t>(ab::command::set_offset_to_position)));
  std::uint8_t off[4] = {};
  result("offset", read(ab::reg::offset, off, 4));
  (void)frame();
  report::text("offset ");
  report::hex((static_cast<std::uint32_t>(off[0]) << 24U) |
                  (static_cast<std::uint32_t>(off[1]) << 16U) |
                  (static_cast<std::uint32_t>(off[2]) << 8U) | off[3],
              8);
  report::text(" position ");
  report::dec(static_cast<std::uint32_t>(last.single_turn));
  report::text("\ndone\n");
  for (;;) {
  }
}
