// motionbus — an AMO ABSYS encoder emulator for BiSS-C test benches and demos: sensor data,
// the register file with its banks and electronic data sheet, offset / preset / command
// behaviour, the latched error status, and register write times turned into wait states.
//
// Per frame, a test bench or a master loop calls
//   frame(bits...)      the SL samples of the sensor data (biss::encode_frame with this
//                       encoder's values and the CDS bit it owes the master), and
//   control(cdm)        the CDM bit the master sent with that frame (the answer lands in the
//                       next frame's CDS),
// which also advances time by `config::frame_period_us`. Register timings (ABSYS document §3.1,
// §3.2, §3.4): reads are answered without wait states (0.05 ms for an EEPROM value, below a
// frame period of 100 µs or more); a write takes 4 ms (offset, preset mode, the EDS bank
// register 0x41 and the user bank: every register but the cached non-persistent bank
// selection and command register), the offset commands 02 and 03 take 17 ms. While one is in
// progress, a further read or write access is refused with an error ("11" in the header's R/W
// answer: errc::biss_access_denied at the master), as the encoder does; the bytes of a
// sequential write are paced by wait states, which signal each write's completion.
//
// Firmware contract (Cortex-M4; sizes checked by the test command): emulator size: 296 bytes
// (register file, two EDS banks, the control slave). It refers to itself (its control slave
// holds its register file), so it cannot be copied, and a `static` one is in .data: 296 bytes
// of flash copied to RAM at boot. frame() and control() run once a frame in that order, from
// one context: 2127 instructions and 280 bytes of stack at worst for both (meter, Cortex-M4
// -Os; most of it the 64-bit remainder of the rotary position, a library call on a 32-bit
// core). The setters (set_position, set_error, ...) must not run in between.
#ifndef MOTIONBUS_DEVICES_ABSYS_EMULATOR_HPP
#define MOTIONBUS_DEVICES_ABSYS_EMULATOR_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/biss/codec.hpp"
#include "motionbus/biss/control.hpp"
#include "motionbus/biss/eds.hpp"
#include "motionbus/devices/absys.hpp"

namespace motionbus {
namespace devices {
namespace absys {

struct emulator_config {
  biss::encoder_type type = biss::encoder_type::rotary;
  /// Rotary: signal periods per revolution; linear: nm per signal period.
  std::uint32_t sip_count = 512;
  /// SIP_RES: rotary pulses per revolution = sip_count << sip_resolution.
  std::uint32_t sip_resolution = 10;
  std::uint8_t slave_id = 0;
  std::uint32_t frame_period_us = 100;
  /// Registers 0x44..0x4B (§2.4): three ASCII bytes, 0x00BC614E, one ASCII byte (the text's
  /// third and last characters are garbled: 'J' and 'C' stand in for them).
  std::uint8_t serial_number[serial_number_size] = {'A', 'T', 'J', 0x00, 0xBC, 0x61, 0x4E, 'C'};
  std::uint8_t device_id[device_id_size] = {'X', 'X', 0x00, 0x11, 0xF5, 0x8E, '0', '1'};
};

/// The sensor error the emulator reports (nE active).
enum class sensor_error : std::uint8_t {
  none = 0,
  in_operation = 1,  ///< clears when set_error(sensor_error::none) says it has gone
  /// "Remains latched" (§1, Figure 1 notes), release unstated: chosen, until the emulator is
  /// built again (a power cycle); command 06 resets register 0x6B only (§2.7; docs/biss.md §4).
  at_power_on = 2,
};

class emulator {
 public:
  constexpr explicit emulator(const emulator_config& cfg = {}) noexcept
      : cfg_(cfg), regs_(*this), slave_(regs_, biss::control_slave_options{cfg.slave_id, true}) {
    (void)biss::encode_eds_common(biss::eds_common{},
                                  mutable_byte_view(eds_common_, biss::bank_size));
    (void)biss::encode_bp3(default_bp3(cfg.type, cfg.sip_count, cfg.sip_resolution),
                           mutable_byte_view(eds_bp3_, biss::bank_size));
  }
  emulator(const emulator&) = delete;  // the control slave refers to this object
  emulator& operator=(const emulator&) = delete;

  // --- the physical encoder -----------------------------------------------------------------
  /// Sets the measured (absolute) position.
  constexpr void set_position(std::uint32_t p) noexcept { position_ = p; }
  constexpr std::uint32_t absolute_position() const noexcept { return position_; }
  /// Sets the sensor error condition (lost synchronisation, bad absolute reading) and latches
  /// it in the error status register at once, whether or not a frame is read meanwhile. One in
  /// operation clears from the frame when synchronisation comes back (ABSYS document, Figure 1
  /// notes); one at power-on stays (sensor_error::at_power_on).
  constexpr void set_error(sensor_error e) noexcept {
    error_ = e != sensor_error::none;
    power_on_error_ = power_on_error_ || e == sensor_error::at_power_on;
    latch();
  }
  constexpr void set_functional_reserve(std::uint8_t value, std::uint8_t indicator) noexcept {
    reserve_ = value > 254U ? 254U : value;
    reserve_indicator_ = indicator != 0U ? 1U : 0U;
  }
  constexpr std::uint64_t pulses_per_revolution() const noexcept {
    return cfg_.sip_resolution > 31U
               ? 0U
               : (static_cast<std::uint64_t>(cfg_.sip_count) << cfg_.sip_resolution);
  }

  // --- what the master sees -------------------------------------------------------------------
  /// The position sent in the sensor data and in registers 0x63..0x66 (preset mode applied).
  constexpr std::uint32_t reported_position() const noexcept {
    if (preset_ == static_cast<std::uint8_t>(preset_mode::actual)) {
      return position_;
    }
    if (cfg_.type == biss::encoder_type::linear) {
      return position_ - offset_;  // the signed result's two's-complement bits
    }
    return rotary_position(position_, offset_, pulses_per_revolution());
  }
  /// This frame's sensor data values.
  constexpr biss::slave_values values() const noexcept {
    biss::slave_values v;
    v.single_turn = reported_position();
    v.ne = !(error_ || power_on_error_);
    v.nw = true;  // warning unused (§1)
    return v;
  }
  /// Writes this frame's SL samples into `out`: `line_delay` idle samples (the line delay a
  /// master reports as chain_frame::line_delay), `ack_bits` of Ack, Start, the CDS owed to the
  /// master, data, nE, nW, CRC6. Returns the bits written.
  template <class Word>
  constexpr result<std::size_t> frame(span<Word> out, std::size_t line_delay = 1,
                                      std::size_t ack_bits = 1) const noexcept {
    biss::line_options line;
    line.line_delay = line_delay;
    line.ack_bits = ack_bits;
    line.cds = cds_;
    return biss::encode_frame(layout, values(), out, line);
  }
  /// The same into a plain array of words.
  template <class Word, std::size_t N>
  constexpr result<std::size_t> frame(Word (&out)[N], std::size_t line_delay = 1,
                                      std::size_t ack_bits = 1) const noexcept {
    return frame(span<Word>(out, N), line_delay, ack_bits);
  }
  /// The CDS bit the next frame carries.
  constexpr bool cds() const noexcept { return cds_; }
  /// The CDM bit the master sent with this frame; advances time by one frame period.
  constexpr void control(bool cdm) noexcept {
    cds_ = slave_.step(cdm);
    tick(cfg_.frame_period_us);
  }

  // --- state, for tests and demos -----------------------------------------------------------
  constexpr std::uint32_t offset() const noexcept { return offset_; }
  constexpr std::uint8_t error_status() const noexcept { return status_; }
  constexpr std::uint8_t selected_bank() const noexcept { return bank_; }
  constexpr bool busy() const noexcept { return busy_us_ > 0U; }
  constexpr std::uint32_t frame_period_us() const noexcept { return cfg_.frame_period_us; }
  constexpr std::size_t register_accesses() const noexcept { return slave_.accesses(); }
  /// Accesses refused because the previous operation was still in progress.
  constexpr std::size_t refused_while_busy() const noexcept { return slave_.refused_busy(); }
  const std::uint8_t* user_bank() const noexcept { return user_; }

  /// The register file as control communication sees it (biss::control_slave's interface).
  class registers {
   public:
    constexpr explicit registers(emulator& e) noexcept : e_(&e) {}
    constexpr bool readable(std::uint8_t a) const noexcept {
      if (a < 0x40U) {
        return e_->bank_ >= bank::eds_common && e_->bank_ <= bank::user;
      }
      return true;  // the rest of the map reads (reserved addresses as 0)
    }
    constexpr bool writable(std::uint8_t a) const noexcept {
      if (a < 0x40U) {
        return e_->bank_ == bank::user;
      }
      return a == reg::bank_select || a == reg::eds_bank ||
             (a >= reg::offset && a <= reg::offset + 3U) || a == reg::command ||
             a == reg::preset_mode;
    }
    constexpr bool ready() const noexcept { return e_->busy_us_ == 0U; }
    constexpr std::uint8_t read(std::uint8_t a) const noexcept { return e_->read_register(a); }
    constexpr void write(std::uint8_t a, std::uint8_t v) noexcept { e_->write_register(a, v); }

   private:
    emulator* e_;
  };

  /// Register value as a read returns it.
  constexpr std::uint8_t read_register(std::uint8_t a) const noexcept {
    if (a < 0x40U) {
      switch (bank_) {
        case bank::eds_common: return eds_common_[a];
        case bank::eds_bp3: return eds_bp3_[a];
        case bank::user: return user_[a];
        default: return 0;  // reserved EDS banks read 0x00
      }
    }
    const std::uint32_t pos = reported_position();
    switch (a) {
      case reg::bank_select: return bank_;
      case reg::eds_bank: return eds_bank_;
      case reg::profile_id: return static_cast<std::uint8_t>(bp3_32bit_profile_id >> 8U);
      case reg::profile_id + 1U: return static_cast<std::uint8_t>(bp3_32bit_profile_id & 0xFFU);
      case reg::command: return command_;
      case reg::preset_mode: return preset_;
      case reg::error_status: return status_;
      case reg::functional_reserve: return reserve_;
      case reg::functional_reserve_indicator: return reserve_indicator_;
      case reg::revision: return revision_03;
      case reg::manufacturer_id: return static_cast<std::uint8_t>(manufacturer[0]);
      case reg::manufacturer_id + 1U: return static_cast<std::uint8_t>(manufacturer[1]);
      default: break;
    }
    // coverage-branch: a >= 0x44 here: the bank window and the switch answer all below
    if (a >= reg::serial_number && a < reg::serial_number + serial_number_size) {
      return cfg_.serial_number[a - reg::serial_number];
    }
    // coverage-branch: a >= 0x4C here: 0x44..0x4B answered just above
    if (a >= reg::offset && a < reg::offset + 4U) {
      return static_cast<std::uint8_t>((offset_ >> (8U * (3U - (a - reg::offset)))) & 0xFFU);
    }
    if (a >= reg::position && a < reg::position + 4U) {
      return static_cast<std::uint8_t>((pos >> (8U * (3U - (a - reg::position)))) & 0xFFU);
    }
    if (a >= reg::device_id && a < reg::device_id + device_id_size) {
      return cfg_.device_id[a - reg::device_id];
    }
    return 0;
  }

 private:
  constexpr void tick(std::uint32_t us) noexcept { busy_us_ = busy_us_ > us ? busy_us_ - us : 0U; }
  // The error status register latches the frame's active-low nE and nW (§2.7): a 0 stays.
  // Run where they can change (set_error) and after command 06: every frame in between
  // carries the same bits.
  constexpr void latch() noexcept {
    const biss::slave_values v = values();
    status_ = static_cast<std::uint8_t>(status_ & status_of(v.ne, v.nw));
  }

  constexpr void write_register(std::uint8_t a, std::uint8_t v) noexcept {
    if (a < 0x40U) {
      if (bank_ == bank::user) {
        user_[a] = v;
      }
    } else if (a == reg::bank_select) {
      bank_ = v == bank::not_allowed ? bank_ : v;  // 0xFF is not allowed: ignored
    } else if (a == reg::eds_bank) {
      eds_bank_ = v;
    } else if (a >= reg::offset && a < reg::offset + 4U) {
      const unsigned shift = 8U * (3U - (a - reg::offset));
      offset_ = (offset_ & ~(0xFFU << shift)) | (static_cast<std::uint32_t>(v) << shift);
    } else if (a == reg::preset_mode) {
      preset_ = v & 0x01U;
    } else if (a == reg::command) {
      command_ = v;
      run_command(v);
    }
    busy_us_ = write_time_us(a, v);  // §3.4, one table for every register
  }
  constexpr void run_command(std::uint8_t v) noexcept {
    switch (v) {
      case static_cast<std::uint8_t>(command::set_offset_to_position): offset_ = position_; break;
      case static_cast<std::uint8_t>(command::reset_offset): offset_ = 0; break;
      case static_cast<std::uint8_t>(command::reset_errors):
        status_ = status_healthy;  // 0x03; an error still present latches again at once
        latch();
        break;
      default: break;
    }
  }
  emulator_config cfg_;
  registers regs_;
  biss::control_slave<registers> slave_;
  std::uint8_t eds_common_[biss::bank_size] = {};
  std::uint8_t eds_bp3_[biss::bank_size] = {};
  std::uint8_t user_[biss::bank_size] = {};
  std::uint32_t position_ = 0;
  std::uint32_t offset_ = 0;
  std::uint32_t busy_us_ = 0;
  std::uint8_t bank_ = bank::eds_common;
  std::uint8_t eds_bank_ = bank::eds_common;
  std::uint8_t command_ = 0;
  std::uint8_t preset_ = 0;
  std::uint8_t status_ = status_healthy;  // default 0x03 (§2.1): no error, no warning
  std::uint8_t reserve_ = 254;            // until movement is detected (§2.6)
  std::uint8_t reserve_indicator_ = 0;
  bool error_ = false;
  bool power_on_error_ = false;
  bool cds_ = false;
};

}  // namespace absys
}  // namespace devices
}  // namespace motionbus

#endif  // MOTIONBUS_DEVICES_ABSYS_EMULATOR_HPP
