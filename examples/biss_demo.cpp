// The BiSS-C part of the demo: a master reads position and registers from the AMO ABSYS
// emulator over an in-memory bit stream. Each frame, the emulator's SL samples go through
// decode_frame exactly as an SPI capture would, the CDS bit feeds the register-access state
// machine, and its CDM bit goes back to the emulator.
#include <motionbus/biss.hpp>
#include <motionbus/devices/absys.hpp>
#include <motionbus/devices/absys_emulator.hpp>

#include <cstdint>
#include <cstdio>

namespace mb = motionbus;
namespace bs = motionbus::biss;
namespace ab = motionbus::devices::absys;

namespace {

class session {
 public:
  explicit session(ab::emulator& e) : enc_(e) {}

  // One frame; an error when the emulator cannot write it or the capture does not decode.
  mb::errc frame() {
    std::uint32_t words[2] = {0xFFFFFFFFU, 0xFFFFFFFFU};
    const auto n = enc_.frame(words, 2, 1);  // a line delay of 2 bits, Ack 1
    if (!n.ok()) {
      return n.error();
    }
    const auto r = bs::decode_frame(words, 64, ab::layout);
    if (!r.is_complete()) {
      return r.is_failed() ? r.error() : mb::errc::no_frame;
    }
    last_ = r->slaves[0];
    line_delay_ = r->line_delay;
    enc_.control(master_.step(r->cds));
    ++frames_;
    return mb::errc::ok;
  }
  // Runs frames until the running access ends; returns its result.
  mb::errc finish() {
    while (master_.busy()) {
      const mb::errc e = frame();
      if (e != mb::errc::ok) {
        return e;
      }
    }
    return master_.error();
  }
  mb::errc read(std::uint8_t address, std::uint8_t* out, std::size_t n) {
    const mb::errc e = master_.start_read(0, address, mb::mutable_byte_view(out, n));
    return e == mb::errc::ok ? finish() : e;
  }
  // Writes one register, then lets the frames run while the encoder completes the write: it
  // refuses any access that arrives before (ABSYS §3.2, write_time_us).
  mb::errc write(std::uint8_t address, std::uint8_t value) {
    const std::uint8_t v[1] = {value};
    mb::errc e = master_.start_write(0, address, mb::byte_view(v, 1));
    e = e == mb::errc::ok ? finish() : e;
    for (std::uint32_t t = 0; e == mb::errc::ok && t < ab::write_time_us(address, value);
         t += enc_.frame_period_us()) {
      e = frame();
    }
    return e;
  }
  const bs::slave_data& last() const { return last_; }
  std::size_t frames() const { return frames_; }
  std::size_t line_delay() const { return line_delay_; }

 private:
  ab::emulator& enc_;
  bs::control_master master_;
  bs::slave_data last_{};
  std::size_t frames_ = 0;
  std::size_t line_delay_ = 0;
};

void check(mb::errc e, const char* what) {
  if (e != mb::errc::ok) {
    std::printf("  %s failed: %s\n", what, mb::to_string(e));
  }
}

}  // namespace

int main() {
  ab::emulator enc;  // WMKA-style rotary encoder: 512 periods x 2^10 = 524288 pulses per turn
  session s(enc);
  const double pulses = static_cast<double>(enc.pulses_per_revolution());

  enc.set_position(131072);
  for (int i = 0; i < 3; ++i) {
    enc.set_position(enc.absolute_position() + 4096);
    check(s.frame(), "frame");
    std::printf("  position %u pulses = %.3f deg, nE %d, nW %d, line delay %zu bits\n",
                static_cast<unsigned>(s.last().single_turn),
                360.0 * static_cast<double>(s.last().single_turn) / pulses, s.last().ne ? 1 : 0,
                s.last().nw ? 1 : 0, s.line_delay());
  }

  std::uint8_t id[2] = {};
  std::uint8_t mfr[2] = {};
  std::uint8_t serial[ab::serial_number_size] = {};
  std::uint8_t device[ab::device_id_size] = {};
  std::uint8_t rev = 0;
  check(s.read(ab::reg::manufacturer_id, mfr, 2), "manufacturer");
  check(s.read(ab::reg::revision, &rev, 1), "revision");
  check(s.read(ab::reg::profile_id, id, 2), "profile ID");
  check(s.read(ab::reg::serial_number, serial, sizeof serial), "serial number");
  check(s.read(ab::reg::device_id, device, sizeof device), "device ID");
  // Serial number: three ASCII bytes, the number (big-endian), one ASCII byte (§2.4); device
  // ID: two ASCII bytes, the number, two ASCII bytes (§2.5).
  const auto sn = ab::decode_serial_number(serial);
  const auto dev = ab::decode_device_id(device);
  check(sn.error(), "serial number decode");
  check(dev.error(), "device ID decode");
  if (sn.is_complete() && dev.is_complete()) {
    std::printf(
        "  identity: manufacturer \"%c%c\", slave revision 0x%02X, profile 0x%02X%02X "
        "(BP3, %u-bit data), serial %.3s %u %c, device ID %u\n",
        mfr[0], mfr[1], rev, id[0], id[1], id[1], sn->prefix, static_cast<unsigned>(sn->number),
        sn->suffix, static_cast<unsigned>(dev->number));
  }

  std::uint8_t bank[bs::bank_size] = {};
  check(s.read(0x00, bank, bs::bank_size), "EDS common part");  // bank 0x80 after power-on
  const auto common = bs::decode_eds_common(mb::byte_view(bank, bs::bank_size));
  check(s.write(ab::reg::bank_select, ab::bank::eds_bp3), "bank select");
  check(s.read(0x00, bank, bs::bank_size), "EDS BP3");
  const auto bp3 = bs::decode_bp3(mb::byte_view(bank, bs::bank_size));
  check(common.is_incomplete() ? mb::errc::truncated : common.error(), "EDS common part decode");
  check(bp3.is_incomplete() ? mb::errc::truncated : bp3.error(), "EDS BP3 decode");
  if (common.is_complete() && bp3.is_complete()) {
    const bs::crc_format crc = bs::crc_from_eds(bp3->crc_poly, bp3->crc_start);
    std::printf(
        "  EDS: version %u, %u banks, BP3 in bank 0x%02X; %s encoder, %u x 2^%u = %llu "
        "pulses/rev, %u data bits, CRC%u poly 0x%X start %u\n",
        common->version, common->length, common->profile_bank,
        bp3->type == bs::encoder_type::rotary ? "rotary" : "linear",
        static_cast<unsigned>(bp3->sip_count), static_cast<unsigned>(bp3->sip_resolution),
        static_cast<unsigned long long>(bp3->pulses_per_revolution()), bp3->layout().data_bits(),
        crc.width, (1U << crc.width) | crc.poly, static_cast<unsigned>(crc.start));
  }

  // Error status 0x6B: nE and nW latched, active low as in the frame (0x03: no error).
  std::uint8_t status[3] = {};
  check(s.read(ab::reg::error_status, &status[0], 1), "error status");
  enc.set_error(ab::sensor_error::in_operation);  // synchronisation lost for one frame ...
  check(s.frame(), "frame");
  const bool ne_low = !s.last().ne;
  enc.set_error(ab::sensor_error::none);  // ... and regained: nE high again, 0x6B keeps it
  check(s.read(ab::reg::error_status, &status[1], 1), "error status");
  check(s.write(ab::reg::command, static_cast<std::uint8_t>(ab::command::reset_errors)),
        "reset errors");
  check(s.read(ab::reg::error_status, &status[2], 1), "error status");
  std::printf(
      "  error status 0x%02X at power-on; an error in operation (nE %d) latches 0x%02X (error "
      "%s), command 06 returns 0x%02X\n",
      status[0], ne_low ? 0 : 1, status[1],
      ab::decode_error_status(status[1]).error ? "latched" : "none", status[2]);

  const std::size_t before = s.frames();
  check(s.write(ab::reg::command, static_cast<std::uint8_t>(ab::command::set_offset_to_position)),
        "set offset");
  std::uint8_t off[4] = {};
  check(s.read(ab::reg::offset, off, 4), "offset");  // after the 17 ms EEPROM writes
  check(s.frame(), "frame");
  std::printf(
      "  command 02 (offset := position): offset 0x%02X%02X%02X%02X, position now %u; "
      "%zu frames of 100 us including the 17 ms the encoder is busy\n",
      off[0], off[1], off[2], off[3], static_cast<unsigned>(s.last().single_turn),
      s.frames() - before);
  return 0;
}
