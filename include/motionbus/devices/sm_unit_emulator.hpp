// motionbus — an SM unit emulator on the Modbus server dispatch (modbus/server.hpp), behaving as
// the vendor text says (SM Unit Communication Guidelines §4–§11):
//  - logged in at power-on; writing the password to holding 100..107 toggles login/logout,
//    a wrong password is a login error (04);
//  - password 8..16 characters 0x21..0x7E, padded with NUL or SP; unreadable while logged out
//    (04); writes of any kind while logged out are login errors (04);
//  - the blocks 100..107, 200..207, 300..301 and 350..354 are accessed whole, never one address
//    alone (else 02); 300..301 and 350..354 are read only (writes: 02);
//  - settings 0..39 within their limits (else 03);
//  - errors ranked 01 (function) > 02 (address) > 03 (data) > 04 (login);
//  - broadcasts executed without reply, other addresses ignored (the dispatch does this);
//  - instantaneous data that changes over time (set_time_ms), warnings that can be injected,
//    a warning count, logs 1..3 of 20 samples per channel.
// Choices where the text is silent (documented, tested): FC02 has no documented inputs, so every
// address is an address error; a block must be accessed from its first address with its exact
// length; reading 100..107 gives 16 NUL characters (§10).
//
// Firmware contract (Cortex-M4; sizes checked by the test command): emulator size: 112 bytes.
// Its power-on state (the password `password`, the factory settings) is not all zeros, so a
// `static` one is in .data: 112 bytes of flash copied to RAM at boot. It serves requests through
// modbus::serve_frame / serve_rtu: an FC03 of three settings from the request ADU takes 643
// instructions and 560 bytes of stack (meter, Cortex-M4 -Os: serve_rtu's register buffer, as
// the emulator has uint16_t accessors; the only request measured). Serving and the world's
// setters (set_time_ms, inject_warning) must not run at the same time.
#ifndef MOTIONBUS_DEVICES_SM_UNIT_EMULATOR_HPP
#define MOTIONBUS_DEVICES_SM_UNIT_EMULATOR_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/span.hpp"
#include "motionbus/devices/sm_unit.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/server.hpp"

namespace motionbus {
namespace devices {
namespace sm_unit {

class emulator {
 public:
  static constexpr std::uint8_t function_error = 0x01;
  static constexpr std::uint8_t address_error = 0x02;
  static constexpr std::uint8_t data_error = 0x03;
  static constexpr std::uint8_t login_error = 0x04;

  constexpr emulator() noexcept {
    const char* def = "password";
    for (std::size_t i = 0; i < 8U; ++i) {
      password_[i] = static_cast<std::uint8_t>(def[i]);
    }
    // factory settings: limits off (0) except those whose lower limit is 1
    for (std::uint16_t i = 0; i < holding::setting_count; ++i) {
      settings_[i] = setting_limits(i).value().lower;
    }
    settings_[36] = 800;   // overheat at 80.0 degC
    settings_[37] = 5000;  // 50.00 m/s2
    settings_[38] = 10;    // 1.0 s log interval
  }

  // --- the world ----------------------------------------------------------------------------
  constexpr void set_time_ms(std::uint32_t now_ms) noexcept { now_ms_ = now_ms; }
  /// Raises warnings (warning:: bits): status, count and factor log are updated.
  constexpr void inject_warning(std::uint16_t bits) noexcept {
    status_ = static_cast<std::uint16_t>(status_ | bits);
    factor_[2] = factor_[1];
    factor_[1] = factor_[0];
    factor_[0] = bits;
    ++count_;
  }
  constexpr bool logged_in() const noexcept { return logged_in_; }
  constexpr std::uint16_t setting(std::uint16_t i) const noexcept {
    return i < holding::setting_count ? settings_[i] : 0;
  }
  constexpr std::uint16_t warning_status() const noexcept { return status_; }
  constexpr std::uint16_t warning_count() const noexcept { return count_; }

  /// The instantaneous value of a channel (raw register) at the current time: slow triangle
  /// waves around plausible operating points.
  constexpr std::uint16_t instantaneous_register(channel c) const noexcept {
    const std::uint32_t t = now_ms_ / 100U;  // 0.1 s steps
    const auto tri = [t](std::uint32_t period, std::int32_t amplitude) {
      const std::uint32_t p = t % period;
      const std::int32_t half = static_cast<std::int32_t>(period / 2U);
      const std::int32_t x = static_cast<std::int32_t>(p);
      // coverage-branch: every period below is 10 or more: half is never 0 (a division guard)
      return (x < half ? x : 2 * half - x) * amplitude / (half == 0 ? 1 : half);
    };
    std::int32_t v = 0;
    switch (c) {
      case channel::voltage: v = 2000 + tri(50, 60); break;        // 200.0..206.0 V
      case channel::current: v = 150 + tri(80, 40); break;         // 1.50..1.90 A
      case channel::power: v = 2600 + tri(80, 300); break;         // 260.0..290.0 W
      case channel::temperature: v = 350 + tri(600, 80); break;    // 35.0..43.0 degC
      case channel::acceleration_x: v = -30 + tri(20, 60); break;  // -0.30..0.30 m/s2
      case channel::acceleration_y: v = -10 + tri(30, 20); break;
      case channel::acceleration_z: v = 981 + tri(10, 4) - 2; break;
      case channel::frequency: v = 50; break;
      case channel::torque: v = 120 + tri(40, 30); break;  // 12.0..15.0 N.m
    }
    return static_cast<std::uint16_t>(v & 0xFFFF);
  }

  // --- the server dispatch's accessors -------------------------------------------------------
  /// The SM unit's order of checks (SM unit Modbus-RTU guideline §5, "discovery priority"):
  /// an unsupported function (01); an unsupported start address (02); at a supported address,
  /// an invalid number of registers or bytes (03: the generic decoder's checks, which
  /// serve_rtu answers when this lets the request through); a range that runs past the area or
  /// splits a block (02).
  constexpr std::uint8_t admit(byte_view pdu) const noexcept {
    const std::uint8_t f = pdu[0];
    const bool supported = (f >= 0x01 && f <= 0x06) || f == 0x0F || f == 0x10 || f == 0x11;
    if (!supported) {
      return function_error;
    }
    if (f == 0x11 || pdu.size() < 3U) {
      return 0;  // FC11 has no address; too short for one: the generic decoder's 03
    }
    if (!area_ok(f, modbus::register_at(pdu.subspan(1), 0), 0)) {
      return address_error;
    }
    if (!modbus::decode_request(pdu).is_complete()) {
      return 0;
    }
    const std::uint16_t address = modbus::register_at(pdu.subspan(1), 0);
    const std::uint16_t quantity =
        (f == 0x05 || f == 0x06) ? std::uint16_t{1} : modbus::register_at(pdu.subspan(1), 1);
    return area_ok(f, address, quantity) ? std::uint8_t{0} : address_error;
  }

  constexpr std::uint8_t read_bits(std::uint8_t, std::uint16_t address, std::uint16_t,
                                   mutable_byte_view packed) const noexcept {
    (void)address;
    packed[0] = 0;  // both coils read back as OFF: they act and turn themselves off (§8)
    return 0;
  }

  constexpr std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                                        span<std::uint16_t> out) const noexcept {
    if (function == 0x04) {
      for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = input_register(static_cast<std::uint16_t>(address + i));
      }
      return 0;
    }
    if (address == holding::password && !logged_in_) {
      return login_error;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = holding_register(static_cast<std::uint16_t>(address + i));
    }
    return 0;
  }

  constexpr std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity,
                                     byte_view packed) noexcept {
    (void)quantity;
    if (!logged_in_) {
      return login_error;
    }
    if (modbus::bit_at(packed, 0)) {
      if (address == coil::warning_count_clear) {
        count_ = 0;
      } else {
        status_ = 0;
      }
    }
    return 0;
  }

  constexpr std::uint8_t write_registers(std::uint16_t address,
                                         span<const std::uint16_t> values) noexcept {
    if (address == holding::login || address == holding::password) {
      std::uint8_t text[16] = {};
      std::size_t length = 0;
      if (!unpack_password(values, text, length)) {
        return data_error;
      }
      if (address == holding::login) {
        if (!same_password(text, length)) {
          return login_error;  // authentication failure
        }
        logged_in_ = !logged_in_;
        return 0;
      }
      if (!logged_in_) {
        return login_error;
      }
      for (std::size_t i = 0; i < 16U; ++i) {
        password_[i] = i < length ? text[i] : 0U;
      }
      return 0;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {  // settings 0..39: data first, then login
      const auto l = setting_limits(static_cast<std::uint16_t>(address + i));
      // coverage-branch: !l: admit() lets writes through to settings 0..39 only, all limited
      if (!l || values[i] < l->lower || values[i] > l->upper) {
        return data_error;
      }
    }
    if (!logged_in_) {
      return login_error;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      settings_[address + i] = values[i];
    }
    return 0;
  }

  constexpr std::uint8_t report_server_id(mutable_byte_view out, std::size_t& size) const noexcept {
    out[0] = version_upper;
    out[1] = version_lower;
    size = 2;  // the SM unit's layout: no byte count (§11)
    return 0;
  }

  static constexpr std::uint8_t version_upper = 0x01;
  static constexpr std::uint8_t version_lower = 0x00;

 private:
  // quantity 0 asks whether `address` may start an access to the area at all
  static constexpr bool within(std::uint16_t address, std::uint16_t quantity, std::uint16_t first,
                               std::uint16_t count) noexcept {
    return address >= first &&
           static_cast<std::uint32_t>(address) + (quantity == 0U ? 1U : quantity) <=
               static_cast<std::uint32_t>(first) + count;
  }
  static constexpr bool whole_block(std::uint16_t address, std::uint16_t quantity,
                                    std::uint16_t first, std::uint16_t count) noexcept {
    return address == first && (quantity == 0U || quantity == count);
  }

  constexpr bool area_ok(std::uint8_t f, std::uint16_t address,
                         std::uint16_t quantity) const noexcept {
    // coverage-branch: the edge to the default, which admit() never lets a function reach
    switch (f) {
      case 0x01:
      case 0x05:
      case 0x0F:
        return quantity <= 1U &&
               (address == coil::warning_count_clear || address == coil::warning_reset);
      case 0x02: return false;  // no discrete inputs are documented
      case 0x04: {
        if (within(address, quantity, input::set_parameters, input::set_parameter_count) ||
            within(address, quantity, input::instantaneous, input::instantaneous_count) ||
            within(address, quantity, input::state, input::state_count) ||
            within(address, quantity, input::login_status, 1)) {
          return true;
        }
        for (std::uint16_t log = 1; log <= 3; ++log) {
          for (std::uint16_t c = 0; c < channel_count; ++c) {
            if (within(address, quantity, static_cast<std::uint16_t>(log * 1000U + c * 100U),
                       input::log_samples)) {
              return true;
            }
          }
        }
        return false;
      }
      case 0x03:
        return within(address, quantity, holding::settings, holding::setting_count) ||
               whole_block(address, quantity, holding::login, holding::password_registers) ||
               whole_block(address, quantity, holding::password, holding::password_registers) ||
               whole_block(address, quantity, holding::product_code,
                           holding::product_code_registers) ||
               whole_block(address, quantity, holding::mfg_number, holding::mfg_number_registers);
      case 0x06: return within(address, 1, holding::settings, holding::setting_count);
      case 0x10:
        return within(address, quantity, holding::settings, holding::setting_count) ||
               whole_block(address, quantity, holding::login, holding::password_registers) ||
               whole_block(address, quantity, holding::password, holding::password_registers);
      default: return false;  // coverage: admit() lets only the functions above get here
    }
  }

  constexpr std::uint16_t input_register(std::uint16_t a) const noexcept {
    if (a < input::set_parameter_count) {
      return settings_[a];  // the set values of DIP switch setting No.1
    }
    // admit() lets FC04 read 0..8 and from 100 on only; read_registers() takes any address
    if (a >= input::instantaneous && a < input::instantaneous + input::instantaneous_count) {
      return instantaneous_register(static_cast<channel>(a - input::instantaneous));
    }
    switch (a) {
      case 200: return count_;
      case 201: return status_;
      case 202: return factor_[0];
      case 203: return factor_[1];
      case 204: return factor_[2];
      case 205:
      case 206:
      case 207: return settings_[38];
      case 300: return logged_in_ ? input::logged_in : input::logged_out;
      default: break;
    }
    // logs 1..3 (§7): a recorded ramp per channel, the last sample at the warning; else none: 0
    const unsigned log = a / 1000U, c = (a / 100U) % 10U, sample = a % 100U;
    const bool in_log = log - 1U < 3U && c < channel_count && sample < input::log_samples;
    const unsigned base = in_log ? instantaneous_register(static_cast<channel>(c)) : 0U;
    return static_cast<std::uint16_t>(in_log ? base + sample * log : 0U);
  }

  constexpr std::uint16_t holding_register(std::uint16_t a) const noexcept {
    if (a < holding::setting_count) {
      return settings_[a];
    }
    if (a >= holding::password && a < holding::password + holding::password_registers) {
      const std::size_t i = std::size_t{2} * (a - holding::password);
      return static_cast<std::uint16_t>((password_[i] << 8U) | password_[i + 1U]);
    }
    const char* product = "SM01";
    const char* mfg = "2611220042";
    if (a >= holding::product_code && a < holding::product_code + holding::product_code_registers) {
      const std::size_t i = std::size_t{2} * (a - holding::product_code);
      return static_cast<std::uint16_t>((static_cast<unsigned>(product[i]) << 8U) |
                                        static_cast<unsigned>(product[i + 1U]));
    }
    // the MFG number (admit() lets FC03 read no block past 354; read_registers() any address)
    if (a >= holding::mfg_number && a < holding::mfg_number + holding::mfg_number_registers) {
      const std::size_t i = std::size_t{2} * (a - holding::mfg_number);
      return static_cast<std::uint16_t>((static_cast<unsigned>(mfg[i]) << 8U) |
                                        static_cast<unsigned>(mfg[i + 1U]));
    }
    return 0;  // login block reads as NUL characters
  }

  // 8 registers -> text; NUL or SP padding only at the end; 8..16 characters 0x21..0x7E.
  static constexpr bool unpack_password(span<const std::uint16_t> values, std::uint8_t (&text)[16],
                                        std::size_t& length) noexcept {
    // true only for a caller that does not go through admit(), which takes whole blocks
    if (values.size() != holding::password_registers) {
      // admit() takes the password blocks only whole (8 registers); kept for callers
      return false;
    }
    length = 0;
    bool padding = false;
    for (std::size_t i = 0; i < 16U; ++i) {
      const auto c =
          static_cast<std::uint8_t>(i % 2U == 0U ? values[i / 2U] >> 8U : values[i / 2U] & 0xFFU);
      if (c == 0x00U || c == 0x20U) {
        padding = true;
        continue;
      }
      if (padding || c < 0x21U || c > 0x7EU) {
        return false;
      }
      text[length++] = c;
    }
    return length >= 8U;
  }

  constexpr bool same_password(const std::uint8_t (&text)[16], std::size_t length) const noexcept {
    for (std::size_t i = 0; i < 16U; ++i) {
      const std::uint8_t want = password_[i];
      const std::uint8_t got = i < length ? text[i] : 0U;
      if (want != got) {
        return false;
      }
    }
    return true;
  }

  std::uint8_t password_[16] = {};
  std::uint16_t settings_[holding::setting_count] = {};
  bool logged_in_ = true;  // logged in at power-on (§6 note *1)
  std::uint16_t status_ = 0;
  std::uint16_t count_ = 0;
  std::uint16_t factor_[3] = {};
  std::uint32_t now_ms_ = 0;
};

}  // namespace sm_unit
}  // namespace devices
}  // namespace motionbus

#endif  // MOTIONBUS_DEVICES_SM_UNIT_EMULATOR_HPP
