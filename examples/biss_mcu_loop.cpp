// The shape of a BiSS-C master in drive firmware: every control cycle an SPI transfer clocks
// MA and samples SL into a 64-bit buffer; the position comes out of decode_frame, and the CDS
// bit of each frame drives the register-access state machine, whose CDM bit the firmware puts
// on MA during the timeout (MA held low = CDM 1). Here a register read of the manufacturer ID
// and the BP3 profile (resolution) runs alongside the position polling.
//
// No heap, no exceptions. The "SPI peripheral" is the ABSYS emulator, so the loop runs on a
// host too; on a microcontroller, spi_transfer and set_cdm are the two hardware hooks.
#include <motionbus/biss.hpp>
#include <motionbus/devices/absys.hpp>
#include <motionbus/devices/absys_emulator.hpp>

#include <cstdint>
#include <cstdio>

namespace mb = motionbus;
namespace bs = motionbus::biss;
namespace ab = motionbus::devices::absys;

namespace {

// --- what the firmware provides ---------------------------------------------------------------
ab::emulator encoder;  // stands in for the encoder behind the RS-422 transceivers

// Clocks 64 MA periods and returns the SL samples, first sample in the MSB of rx[0].
void spi_transfer(std::uint32_t rx[2], std::uint32_t cycle) {
  rx[0] = 0xFFFFFFFFU;
  rx[1] = 0xFFFFFFFFU;
  // a line delay of 1..3 bits, as cable length and transceivers make it
  (void)encoder.frame(mb::span<std::uint32_t>(rx, 2), 1U + cycle % 3U, 1);
}

// Drives MA during the timeout: held low for CDM = 1, high for CDM = 0.
void set_cdm(bool cdm) {
  encoder.control(cdm);
}

}  // namespace

int main() {
  encoder.set_position(0x0007FFF0U);  // 512 pitches x 1024 increments: near the end of a turn
  bs::control_master control;         // lives as long as the firmware
  std::uint8_t manufacturer[2] = {};
  std::uint8_t bp3[bs::bank_size] = {};
  enum { read_manufacturer, select_bp3, read_bp3, finished } job = read_manufacturer;
  std::uint32_t position = 0;
  int bad_frames = 0;

  for (std::uint32_t cycle = 0; cycle < 4000 && job != finished; ++cycle) {
    encoder.set_position(encoder.absolute_position() + 3U);  // the shaft turns
    std::uint32_t rx[2];
    spi_transfer(rx, cycle);
    const auto r = bs::decode_frame(mb::span<const std::uint32_t>(rx, 2), 64, ab::layout);
    if (!r.is_complete()) {
      ++bad_frames;  // a real drive would count this toward its encoder-fault limit
      set_cdm(false);
      continue;
    }
    const bs::slave_data& d = r->slaves[0];
    position = static_cast<std::uint32_t>(d.single_turn);
    // register access, one bit per frame
    if (!control.busy()) {
      if (job == read_manufacturer && control.state() == bs::control_state::idle) {
        (void)control.start_read(0, ab::reg::manufacturer_id,
                                 mb::mutable_byte_view(manufacturer, 2));
      } else if (job == read_manufacturer && control.state() == bs::control_state::done) {
        job = select_bp3;
        static constexpr std::uint8_t bank[1] = {ab::bank::eds_bp3};
        (void)control.start_write(0, ab::reg::bank_select, mb::byte_view(bank, 1));
      } else if (job == select_bp3 && control.state() == bs::control_state::done) {
        job = read_bp3;
        (void)control.start_read(0, 0x00, mb::mutable_byte_view(bp3, bs::bank_size));
      } else if (job == read_bp3 && control.state() == bs::control_state::done) {
        job = finished;
      } else if (control.state() == bs::control_state::failed) {
        std::printf("register access failed: %s\n", mb::to_string(control.error()));
        return 1;
      }
    }
    set_cdm(control.step(r->cds));
    if (cycle % 500U == 0U) {
      std::printf("cycle %4u: position %u%s\n", static_cast<unsigned>(cycle),
                  static_cast<unsigned>(position), d.error() ? " (encoder error)" : "");
    }
  }
  const auto profile = bs::decode_bp3(mb::byte_view(bp3, bs::bank_size));
  if (job != finished || !profile.is_complete() || manufacturer[0] != 'A' ||
      manufacturer[1] != 'm') {
    std::printf("register read did not complete\n");
    return 1;
  }
  std::printf(
      "manufacturer \"%c%c\", %s encoder, %llu pulses per revolution, last position %u, "
      "%d bad frames\n",
      manufacturer[0], manufacturer[1],
      profile->type == bs::encoder_type::rotary ? "rotary" : "linear",
      static_cast<unsigned long long>(profile->pulses_per_revolution()),
      static_cast<unsigned>(position), bad_frames);
  return bad_frames == 0 ? 0 : 1;
}
