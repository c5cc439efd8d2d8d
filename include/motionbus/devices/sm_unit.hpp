// motionbus — Tsubaki SM unit (gear-motor monitor, Modbus RTU 9600 8E1, slaves 1..16): typed
// register map, units, warning bits, settings limits, request builders and response decoders,
// on top of the generic Modbus codec. Source: Tsubaki, SM Unit Communication Guidelines §2,
// §5–§11; docs/modbus.md §4.
#ifndef MOTIONBUS_DEVICES_SM_UNIT_HPP
#define MOTIONBUS_DEVICES_SM_UNIT_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/rtu.hpp"

namespace motionbus {
namespace devices {
namespace sm_unit {

// --- line and addresses (§2, §3) -------------------------------------------------------------
inline constexpr std::uint32_t baud = 9600;  ///< 8 data bits, even parity, 1 stop bit
inline constexpr std::uint8_t min_slave = 1;
inline constexpr std::uint8_t max_slave = 16;
inline constexpr std::uint32_t min_silent_interval_us = 5000;
inline constexpr std::uint32_t min_command_interval_us = 100000;

/// Coils (§8).
namespace coil {
inline constexpr std::uint16_t warning_count_clear = 0;
inline constexpr std::uint16_t warning_reset = 100;
}  // namespace coil

/// Input registers (§9).
namespace input {
inline constexpr std::uint16_t set_parameters = 0;  ///< 0..8
inline constexpr std::uint16_t set_parameter_count = 9;
inline constexpr std::uint16_t instantaneous = 100;  ///< 100..108
inline constexpr std::uint16_t instantaneous_count = 9;
inline constexpr std::uint16_t state = 200;  ///< 200..207
inline constexpr std::uint16_t state_count = 8;
inline constexpr std::uint16_t login_status = 300;
inline constexpr std::uint16_t logged_in = 0xFF00;
inline constexpr std::uint16_t logged_out = 0x0000;
inline constexpr std::uint16_t log_samples = 20;  ///< xx00 oldest .. xx19 at the warning
}  // namespace input

/// Holding registers (§10).
namespace holding {
inline constexpr std::uint16_t settings = 0;  ///< 0..39
inline constexpr std::uint16_t setting_count = 40;
inline constexpr std::uint16_t login = 100;         ///< 100..107, block only
inline constexpr std::uint16_t password = 200;      ///< 200..207, block only
inline constexpr std::uint16_t product_code = 300;  ///< 300..301, block only, read only
inline constexpr std::uint16_t mfg_number = 350;    ///< 350..354, block only, read only
inline constexpr std::uint16_t password_registers = 8;
inline constexpr std::uint16_t product_code_registers = 2;
inline constexpr std::uint16_t mfg_number_registers = 5;
}  // namespace holding

/// The measured quantities: instantaneous data (input 100 + index) and log channels
/// (input log * 1000 + index * 100 + sample).
enum class channel : std::uint8_t {
  voltage = 0,
  current = 1,
  power = 2,
  temperature = 3,
  acceleration_x = 4,
  acceleration_y = 5,
  acceleration_z = 6,
  frequency = 7,
  torque = 8,
};
inline constexpr std::size_t channel_count = 9;

/// Unit of a channel: value = raw * numerator / denominator in `unit`; signed channels are two's
/// complement (§9: temperature and accelerations).
struct unit_info {
  const char* unit;
  std::int32_t numerator;
  std::int32_t denominator;
  bool is_signed;
};

constexpr unit_info unit_of(channel c) noexcept {
  switch (c) {
    case channel::voltage: return {"V", 1, 10, false};
    case channel::current: return {"A", 1, 100, false};  // 10 mA steps
    case channel::power: return {"W", 1, 10, false};
    case channel::temperature: return {"degC", 1, 10, true};
    case channel::acceleration_x:
    case channel::acceleration_y:
    case channel::acceleration_z: return {"m/s2", 1, 100, true};
    case channel::frequency: return {"Hz", 1, 1, false};
    case channel::torque: return {"N.m", 1, 10, false};
  }
  return {"", 1, 1, false};
}

/// The register value as the signed or unsigned integer the channel holds (raw units).
constexpr std::int32_t raw_value(channel c, std::uint16_t reg) noexcept {
  return unit_of(c).is_signed && reg >= 0x8000U ? static_cast<std::int32_t>(reg) - 0x10000
                                                : static_cast<std::int32_t>(reg);
}

/// Input register of a log sample: log 1..3, sample 0 (oldest) .. 19 (at the warning).
constexpr result<std::uint16_t> log_address(unsigned log, channel c, unsigned sample) noexcept {
  if (log < 1U || log > 3U || sample >= input::log_samples) {
    return errc::out_of_range;
  }
  return static_cast<std::uint16_t>(log * 1000U + static_cast<unsigned>(c) * 100U + sample);
}

/// Warning bits (§9 note *1): warning status and warning factors.
namespace warning {
inline constexpr std::uint16_t torque_upper_a = 0x0001;
inline constexpr std::uint16_t torque_upper_b = 0x0002;
inline constexpr std::uint16_t torque_lower_a = 0x0004;
inline constexpr std::uint16_t torque_lower_b = 0x0008;
inline constexpr std::uint16_t overheat = 0x0020;
inline constexpr std::uint16_t excessive_shock = 0x0040;
inline constexpr std::uint16_t defined = 0x006F;
}  // namespace warning

/// Name of a warning bit, or nullptr.
constexpr const char* warning_name(std::uint16_t bit) noexcept {
  switch (bit) {
    case warning::torque_upper_a: return "torque_upper_limit_a";
    case warning::torque_upper_b: return "torque_upper_limit_b";
    case warning::torque_lower_a: return "torque_lower_limit_a";
    case warning::torque_lower_b: return "torque_lower_limit_b";
    case warning::overheat: return "overheat";
    case warning::excessive_shock: return "excessive_shock";
    default: return nullptr;
  }
}

/// Lower and upper limits of holding register `index` (0..39) (§10 table; 0 disables a limit).
struct limits {
  std::uint16_t lower;
  std::uint16_t upper;
  const char* unit;
};

constexpr result<limits> setting_limits(std::uint16_t index) noexcept {
  if (index >= holding::setting_count) {
    return errc::out_of_range;
  }
  if (index < 36U) {
    switch (index % 9U) {
      case 0:
      case 1:
      case 2:
      case 3: return limits{0, 200, "%"};       // output torque limits
      case 4: return limits{1, 300, "0.1 s"};   // start time
      default: return limits{0, 300, "0.1 s"};  // shock times
    }
  }
  switch (index) {
    case 36: return limits{0, 1000, "0.1 degC"};    // overheat limit
    case 37: return limits{0, 15000, "0.01 m/s2"};  // excessive shock limit
    case 38: return limits{1, 100, "0.1 s"};        // log acquisition interval
    default: return limits{0, 300, "s"};            // automatic restoration
  }
}

// --- password (§10 Login/Logout, Password) ---------------------------------------------------
/// Checks a password: 8..16 characters, each 0x21..0x7E. Errors: out_of_range (length),
/// invalid_argument (character).
constexpr errc check_password(byte_view password) noexcept {
  if (password.size() < 8U || password.size() > 16U) {
    return errc::out_of_range;
  }
  for (std::size_t i = 0; i < password.size(); ++i) {
    if (password[i] < 0x21U || password[i] > 0x7EU) {
      return errc::invalid_argument;
    }
  }
  return errc::ok;
}

/// The 8 registers of a password: two characters per register, high byte first, padded with
/// NUL to 16 characters.
constexpr void password_registers(byte_view password, span<std::uint16_t> out) noexcept {
  for (std::size_t r = 0; r < holding::password_registers && r < out.size(); ++r) {
    const std::size_t i = 2U * r;
    const unsigned hi = i < password.size() ? password[i] : 0U;
    const unsigned lo = i + 1U < password.size() ? password[i + 1U] : 0U;
    out[r] = static_cast<std::uint16_t>((hi << 8U) | lo);
  }
}

// --- request builders: whole RTU ADUs, checked before anything is sent ------------------------
namespace detail {
template <class Build>
constexpr result<std::size_t> wrap(std::uint8_t slave, mutable_byte_view out,
                                   Build build) noexcept {
  std::uint8_t pdu[modbus::max_pdu_size] = {};
  const result<std::size_t> n = build(mutable_byte_view(pdu, modbus::max_pdu_size));
  if (!n) {
    return n.error();
  }
  return modbus::encode_rtu(slave, byte_view(pdu, n.value()), out);
}
constexpr bool slave_ok(std::uint8_t slave, bool broadcast_allowed) noexcept {
  return (slave >= min_slave && slave <= max_slave) || (broadcast_allowed && slave == 0U);
}
}  // namespace detail

/// FC04 input registers `first`, `count` (instantaneous data, state, set parameters, a log).
constexpr result<std::size_t> read_inputs(std::uint8_t slave, std::uint16_t first,
                                          std::uint16_t count, mutable_byte_view out) noexcept {
  if (!detail::slave_ok(slave, false)) {
    return errc::modbus_slave_address;
  }
  return detail::wrap(slave, out, [&](mutable_byte_view pdu) {
    return modbus::encode_read(modbus::function_code::read_input_registers, first, count, pdu);
  });
}
constexpr result<std::size_t> read_instantaneous(std::uint8_t slave,
                                                 mutable_byte_view out) noexcept {
  return read_inputs(slave, input::instantaneous, input::instantaneous_count, out);
}
constexpr result<std::size_t> read_state(std::uint8_t slave, mutable_byte_view out) noexcept {
  return read_inputs(slave, input::state, input::state_count, out);
}
constexpr result<std::size_t> read_login_status(std::uint8_t slave,
                                                mutable_byte_view out) noexcept {
  return read_inputs(slave, input::login_status, 1, out);
}
/// The 20 samples of one channel of log 1..3.
constexpr result<std::size_t> read_log(std::uint8_t slave, unsigned log, channel c,
                                       mutable_byte_view out) noexcept {
  const result<std::uint16_t> first = log_address(log, c, 0);
  if (!first) {
    return first.error();
  }
  return read_inputs(slave, first.value(), input::log_samples, out);
}

/// FC06 one setting (holding 0..39), range-checked against §10 first (errc::out_of_range).
/// Slave 0 broadcasts to every unit.
constexpr result<std::size_t> write_setting(std::uint8_t slave, std::uint16_t index,
                                            std::uint16_t value, mutable_byte_view out) noexcept {
  if (!detail::slave_ok(slave, true)) {
    return errc::modbus_slave_address;
  }
  const result<limits> l = setting_limits(index);
  if (!l || value < l->lower || value > l->upper) {
    return errc::out_of_range;
  }
  return detail::wrap(slave, out, [&](mutable_byte_view pdu) {
    return modbus::encode_write_single_register(index, value, pdu);
  });
}

/// FC10 settings `first`.. (each range-checked; errc::out_of_range names no partial write).
constexpr result<std::size_t> write_settings(std::uint8_t slave, std::uint16_t first,
                                             span<const std::uint16_t> values,
                                             mutable_byte_view out) noexcept {
  if (!detail::slave_ok(slave, true)) {
    return errc::modbus_slave_address;
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    const result<limits> l = setting_limits(static_cast<std::uint16_t>(first + i));
    if (!l || values[i] < l->lower || values[i] > l->upper) {
      return errc::out_of_range;
    }
  }
  return detail::wrap(slave, out, [&](mutable_byte_view pdu) {
    return modbus::encode_write_multiple_registers(first, values, pdu);
  });
}

namespace detail {
// FC10 of a checked, NUL-padded password to the 8-register block at `block`.
constexpr result<std::size_t> write_password_block(std::uint8_t slave, std::uint16_t block,
                                                   byte_view password,
                                                   mutable_byte_view out) noexcept {
  if (!slave_ok(slave, true)) {
    return errc::modbus_slave_address;
  }
  const errc e = check_password(password);
  if (e != errc::ok) {
    return e;
  }
  std::uint16_t regs[holding::password_registers] = {};
  password_registers(password, regs);
  return wrap(slave, out, [&](mutable_byte_view pdu) {
    return modbus::encode_write_multiple_registers(block, regs, pdu);
  });
}
}  // namespace detail

/// FC10 to 100..107: toggles login/logout with the current password.
constexpr result<std::size_t> login(std::uint8_t slave, byte_view password,
                                    mutable_byte_view out) noexcept {
  return detail::write_password_block(slave, holding::login, password, out);
}

/// FC10 to 200..207: replaces the password (logged in only), checked first.
constexpr result<std::size_t> change_password(std::uint8_t slave, byte_view password,
                                              mutable_byte_view out) noexcept {
  return detail::write_password_block(slave, holding::password, password, out);
}

/// FC03 blocks: product code (300..301), MFG number (350..354), password (200..207).
constexpr result<std::size_t> read_holding_block(std::uint8_t slave, std::uint16_t first,
                                                 std::uint16_t count,
                                                 mutable_byte_view out) noexcept {
  if (!detail::slave_ok(slave, false)) {
    return errc::modbus_slave_address;
  }
  return detail::wrap(slave, out, [&](mutable_byte_view pdu) {
    return modbus::encode_read(modbus::function_code::read_holding_registers, first, count, pdu);
  });
}

/// FC05 coil ON: warning reset (coil 100) or warning-count clear (coil 0).
constexpr result<std::size_t> set_coil(std::uint8_t slave, std::uint16_t coil_address,
                                       mutable_byte_view out) noexcept {
  if (!detail::slave_ok(slave, true)) {
    return errc::modbus_slave_address;
  }
  return detail::wrap(slave, out, [&](mutable_byte_view pdu) {
    return modbus::encode_write_single_coil(coil_address, true, pdu);
  });
}

/// FC11: the software version, answered as two bytes without a byte count (§11).
constexpr result<std::size_t> read_version(std::uint8_t slave, mutable_byte_view out) noexcept {
  if (!detail::slave_ok(slave, false)) {
    return errc::modbus_slave_address;
  }
  return detail::wrap(slave, out, [&](mutable_byte_view pdu) {
    return modbus::encode_raw(0x11, byte_view{}, pdu);
  });
}

// --- response decoding -------------------------------------------------------------------------
/// The SM unit reuses exception 04 as "login error" (§5): authentication failure, a write while
/// logged out, or reading the password while logged out.
constexpr bool is_login_error(const modbus::response& r) noexcept {
  return r.exception && r.exception_code == 0x04;
}

/// Instantaneous data (input registers 100..108) as raw signed/unsigned values per channel.
struct instantaneous {
  std::int32_t raw[channel_count] = {};
  constexpr std::int32_t operator[](channel c) const noexcept {
    return raw[static_cast<std::size_t>(c)];
  }
};

/// Decodes the response to read_instantaneous. Errors: modbus_byte_count (not 9 registers),
/// modbus_mismatch (an exception or another function: check is_login_error first).
constexpr result<instantaneous> decode_instantaneous(const modbus::response& r) noexcept {
  if (r.exception || r.function != 0x04) {
    return errc::modbus_mismatch;
  }
  if (r.data.size() != 2U * channel_count) {
    return errc::modbus_byte_count;
  }
  instantaneous v;
  for (std::size_t i = 0; i < channel_count; ++i) {
    v.raw[i] = raw_value(static_cast<channel>(i), modbus::register_at(r.data, i));
  }
  return v;
}

/// Software version from the FC11 response (two bytes: upper, lower; 01 00 = Ver.1.0.0).
struct version {
  std::uint8_t upper = 0;
  std::uint8_t lower = 0;
};
constexpr result<version> decode_version(const modbus::response& r) noexcept {
  if (r.exception || r.function != 0x11) {
    return errc::modbus_mismatch;
  }
  if (r.data.size() != 2U) {
    return errc::modbus_byte_count;
  }
  return version{r.data[0], r.data[1]};
}

}  // namespace sm_unit
}  // namespace devices
}  // namespace motionbus

#endif  // MOTIONBUS_DEVICES_SM_UNIT_HPP
