// motionbus — AMO ABSYS absolute encoders (WMIA/WMKA angular, LMIA/LMKA linear) over BiSS-C:
// the register map of BiSS-C slave revision 0x03, commands, preset modes, error status, and
// the position-with-offset arithmetic (ABSYS interface text §1–§3).
//
// Sensor data: 32-bit position, nE, nW (unused, always 1), CRC6 0x43 inverted: biss::absys_layout.
#ifndef MOTIONBUS_DEVICES_ABSYS_HPP
#define MOTIONBUS_DEVICES_ABSYS_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/biss/eds.hpp"
#include "motionbus/biss/frame.hpp"
#include "motionbus/core/bytes.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {
namespace devices {
namespace absys {

/// Sensor data layout (also biss::absys_layout).
inline constexpr biss::slave_layout layout = biss::absys_layout;

/// Register addresses (§2.1). Multi-byte values are big-endian (most significant byte at the
/// lowest address). 0x00..0x3F is the window onto the bank selected at 0x40.
namespace reg {
inline constexpr std::uint8_t bank_window = 0x00;    ///< 0x00..0x3F
inline constexpr std::uint8_t bank_select = 0x40;    ///< R/W, not persistent, 0x80 after power-on
inline constexpr std::uint8_t eds_bank = 0x41;       ///< R/W, 0x80
inline constexpr std::uint8_t profile_id = 0x42;     ///< 0x42..0x43, 0x63 0x20 (BP3, 32 bits)
inline constexpr std::uint8_t serial_number = 0x44;  ///< 0x44..0x4B
inline constexpr std::uint8_t offset = 0x4C;         ///< 0x4C..0x4F, R/W, persistent
inline constexpr std::uint8_t command = 0x60;        ///< R/W
inline constexpr std::uint8_t position = 0x63;       ///< 0x63..0x66, R: the position as sent
inline constexpr std::uint8_t preset_mode = 0x6A;    ///< R/W, persistent
inline constexpr std::uint8_t error_status = 0x6B;   ///< R, latched, active low: 0x03 healthy
inline constexpr std::uint8_t functional_reserve = 0x6F;            ///< R, 0..254
inline constexpr std::uint8_t functional_reserve_indicator = 0x70;  ///< R, 0 / 1
inline constexpr std::uint8_t device_id = 0x75;                     ///< 0x75..0x7C
inline constexpr std::uint8_t revision = 0x7D;                      ///< R, 0x03
inline constexpr std::uint8_t manufacturer_id = 0x7E;               ///< 0x7E..0x7F, "Am"
}  // namespace reg

/// Register banks behind the window (§2.2).
namespace bank {
inline constexpr std::uint8_t eds_common = 0x80;  ///< EDS common part (1/4)
inline constexpr std::uint8_t eds_bp3 = 0x81;     ///< EDS standard profile BP3 (2/4)
inline constexpr std::uint8_t eds_reserved_3 = 0x82;
inline constexpr std::uint8_t eds_reserved_4 = 0x83;
inline constexpr std::uint8_t user = 0x84;  ///< user / OEM data, free to read and write
inline constexpr std::uint8_t not_allowed = 0xFF;
}  // namespace bank

/// Values of the command register (§2.3).
enum class command : std::uint8_t {
  set_offset_to_position = 0x02,  ///< the actual position becomes the offset (17 ms)
  reset_offset = 0x03,            ///< offset = 0 (17 ms)
  reset_errors = 0x06,            ///< error status back to status_healthy (0x03)
};

/// Preset mode register (§2.3).
enum class preset_mode : std::uint8_t {
  with_offset = 0x00,  ///< position sent = actual position - offset
  actual = 0x01,       ///< position sent = actual position (offset ignored)
};

/// Error status register 0x6B (§2.7): bit 0 the warning, bit 1 the error, bits 2..7 "Set to
/// 0. To be defined."; it holds the sensor data's nW and nE latched until command 06. The text
/// gives no polarity for the register. Read here as the frame's bits are, active low (§1,
/// Table 1: "Error/Warning: Active on Low (0)"), so 1 = inactive: the only reading in which the
/// default 0x03 (§2.1) and a warning that "is always inactive and it is set to '1'" (§1) agree.
/// 0x03 is a healthy encoder; 0x01 an error latched; command 06 returns it to 0x03 (to 0x01
/// while the error is still present, as the next frame latches it again).
inline constexpr std::uint8_t status_nw = 0x01;       ///< bit 0: 0 = warning latched (nW low)
inline constexpr std::uint8_t status_ne = 0x02;       ///< bit 1: 0 = error latched (nE low)
inline constexpr std::uint8_t status_healthy = 0x03;  ///< default, no error and no warning

/// The error status register read (§2.7; polarity as above).
struct error_status {
  bool error = false;          ///< bit 1 is 0: an error was latched since the last command 06
  bool warning = false;        ///< bit 0 is 0: a warning was latched (never on the ABSYS)
  std::uint8_t undefined = 0;  ///< bits 2..7 as read ("Set to 0. To be defined.")
};
constexpr error_status decode_error_status(std::uint8_t value) noexcept {
  error_status s;
  s.error = (value & status_ne) == 0U;
  s.warning = (value & status_nw) == 0U;
  s.undefined = static_cast<std::uint8_t>(value & ~status_healthy);
  return s;
}
/// The register value that latches a frame's nE and nW line levels.
constexpr std::uint8_t status_of(bool ne, bool nw) noexcept {
  return static_cast<std::uint8_t>((ne ? status_ne : 0U) | (nw ? status_nw : 0U));
}

/// Serial number (§2.4, registers 0x44..0x4B): three ASCII bytes (0x44..0x46), the number
/// (0x47..0x4A, most significant byte first), one ASCII byte (0x4B). The text's example is
/// 0x00BC614E (12345678) between "AT" and a third and a last character garbled in the text.
struct serial_number {
  char prefix[3] = {};
  std::uint32_t number = 0;
  char suffix = 0;
};
/// Device ID (§2.5, registers 0x75..0x7C): two ASCII bytes, the ID (0x77..0x7A, most
/// significant byte first), two ASCII bytes (the text's example: 0x0011F58E).
struct device_id {
  char prefix[2] = {};
  std::uint32_t number = 0;
  char suffix[2] = {};
};
/// Register bytes of the serial number and of the device ID.
inline constexpr std::size_t serial_number_size = 8;
inline constexpr std::size_t device_id_size = 8;

namespace detail {
// Copies `n` ASCII bytes from `in` at `at`; false for a byte above 0x7F (not ASCII).
constexpr bool ascii(byte_view in, std::size_t at, std::size_t n, char* out) noexcept {
  for (std::size_t i = 0; i < n; ++i) {
    if (in[at + i] > 0x7FU) {
      return false;
    }
    out[i] = static_cast<char>(in[at + i]);
  }
  return true;
}
}  // namespace detail

/// Decodes the 8 bytes read from 0x44..0x4B (more are ignored). Complete: consumed() = 8.
/// Incomplete: fewer bytes (needed() the rest). Failed: errc::out_of_range for a byte above
/// 0x7F where ASCII belongs.
constexpr decode_result<serial_number> decode_serial_number(byte_view regs) noexcept {
  if (regs.size() < serial_number_size) {
    return need_input{serial_number_size - regs.size()};
  }
  serial_number s;
  if (!detail::ascii(regs, 0, 3, s.prefix) || !detail::ascii(regs, 7, 1, &s.suffix)) {
    return decode_failure{errc::out_of_range, serial_number_size};
  }
  s.number = static_cast<std::uint32_t>(load_be<4>(regs, 3));
  return decode_result<serial_number>::complete(s, serial_number_size);
}
/// Decodes the 8 bytes read from 0x75..0x7C, with the outcomes of decode_serial_number.
constexpr decode_result<device_id> decode_device_id(byte_view regs) noexcept {
  if (regs.size() < device_id_size) {
    return need_input{device_id_size - regs.size()};
  }
  device_id d;
  if (!detail::ascii(regs, 0, 2, d.prefix) || !detail::ascii(regs, 6, 2, d.suffix)) {
    return decode_failure{errc::out_of_range, device_id_size};
  }
  d.number = static_cast<std::uint32_t>(load_be<4>(regs, 2));
  return decode_result<device_id>::complete(d, device_id_size);
}

/// Vendor values.
inline constexpr std::uint8_t revision_03 = 0x03;
inline constexpr std::uint16_t bp3_32bit_profile_id = 0x6320;
inline constexpr char manufacturer[2] = {'A', 'm'};
/// Register access timings (§3.4), in microseconds.
inline constexpr std::uint32_t persistent_write_us = 4000;  ///< one persistent byte (> 4 ms)
inline constexpr std::uint32_t offset_command_us = 17000;   ///< command 02/03: four EEPROM writes
inline constexpr std::uint32_t eeprom_read_us = 50;         ///< a non-cached read

/// How long writing `value` to `address` keeps the encoder busy (ABSYS document §3.2, §3.4):
/// nothing for the cached non-persistent registers (bank selection, a command other than 02
/// and 03), 17 ms for the offset commands 02 and 03, 4 ms for every other register (offset
/// bytes, preset mode, the EDS bank register, the user bank). A master waits this long before
/// its next access: the encoder refuses one that arrives while the write is in progress.
constexpr std::uint32_t write_time_us(std::uint8_t address, std::uint8_t value) noexcept {
  if (address == reg::bank_select) {
    return 0;
  }
  if (address == reg::command) {
    return value == static_cast<std::uint8_t>(command::set_offset_to_position) ||
                   value == static_cast<std::uint8_t>(command::reset_offset)
               ? offset_command_us
               : 0U;
  }
  return persistent_write_us;
}
/// Time from power-on to valid position data (§1, Table 1).
inline constexpr std::uint32_t power_on_delay_ms = 1800;

/// Linear encoders: POSITION_WITH_OFFSET = POSITION_ABSOLUTE - OFFSET, signed two's complement
/// on 32 bits (§2.3).
constexpr std::int32_t linear_position(std::uint32_t absolute, std::uint32_t offset) noexcept {
  const std::uint32_t d = absolute - offset;  // modulo 2^32
  return d <= 0x7FFFFFFFU ? static_cast<std::int32_t>(d)
                          : -static_cast<std::int32_t>(~d) - 1;  // two's complement, no UB
}

/// Rotary encoders: POSITION_WITH_OFFSET = (POSITION_ABSOLUTE - OFFSET) MODULO PULSES_PER_REV,
/// unsigned (§2.3): a mathematical modulo, so the result is in 0..pulses-1 also when the offset
/// exceeds the position. `pulses` 0 returns the plain 32-bit difference.
constexpr std::uint32_t rotary_position(std::uint32_t absolute, std::uint32_t offset,
                                        std::uint64_t pulses) noexcept {
  if (pulses == 0U) {
    return absolute - offset;
  }
  const std::uint64_t a = absolute % pulses;
  const std::uint64_t o = offset % pulses;
  return static_cast<std::uint32_t>(a >= o ? a - o : pulses - (o - a));
}

/// The EDS an ABSYS device carries by default (§2.8, §2.9) for a given type and resolution.
constexpr biss::bp3_profile default_bp3(biss::encoder_type type, std::uint32_t sip_count,
                                        std::uint32_t sip_resolution) noexcept {
  biss::bp3_profile p;
  p.version = 0x02;
  p.type = type;
  p.sip_count = sip_count;
  p.sip_resolution = sip_resolution;
  return p;
}

}  // namespace absys
}  // namespace devices
}  // namespace motionbus

#endif  // MOTIONBUS_DEVICES_ABSYS_HPP
