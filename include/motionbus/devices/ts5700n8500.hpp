// motionbus — Tamagawa Smart-Abs TS5700N8500 (17-bit single-turn, 16-bit multi-turn, ENID 0x11):
// reset and EEPROM sequences as plans the user's I/O executes, over-heat and temperature
// registers, alarm meanings and timing. Built on the generic T-format codec.
// Source: TS5700N8500 specification §5.4, §6.1, §6.5, §7, §10; docs/tformat.md §6, §7.
#ifndef MOTIONBUS_DEVICES_TS5700N8500_HPP
#define MOTIONBUS_DEVICES_TS5700N8500_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/frame.hpp"

namespace motionbus {
namespace devices {
namespace ts5700n8500 {

inline constexpr std::uint8_t enid = 0x11;
inline constexpr tformat::resolution resolution{17, 16};
inline constexpr std::uint32_t counts_per_turn = 1U << 17U;

// --- timing (spec §6.1, §8.1, §10; docs/tformat.md §7) ----------------------------------------
/// Bit and field times in nanoseconds at a bit rate (bits/s); a field is 10 bits.
constexpr std::uint32_t bit_ns(std::uint32_t bit_rate) noexcept {
  return bit_rate == 0U ? 0U : 1000000000U / bit_rate;
}
constexpr std::uint32_t field_ns(std::uint32_t bit_rate) noexcept {
  return 10U * bit_ns(bit_rate);
}
inline constexpr std::uint32_t standard_bit_rate = 2500000;  ///< 2.5 Mbps
inline constexpr std::uint32_t fast_bit_rate = 5000000;      ///< 5 Mbps (other encoders)
inline constexpr std::uint32_t response_delay_ns = 3000;  ///< typ., after the request's delimiter
/// Fields on the wire for one transaction (request + response), excluding turnaround.
constexpr std::uint32_t transaction_fields(tformat::data_id id) noexcept {
  return static_cast<std::uint32_t>(tformat::request_size(id) + tformat::layout_of(id).size);
}
/// Transaction time in ns: fields only (docs/tformat.md §7: ID0 28 µs, ID3 48 µs at 2.5 Mbps).
constexpr std::uint32_t transaction_ns(tformat::data_id id,
                                       std::uint32_t bit_rate = standard_bit_rate) noexcept {
  return transaction_fields(id) * field_ns(bit_rate);
}
inline constexpr std::uint32_t reset_interval_us = 40;  ///< between the 10 reset requests
inline constexpr unsigned reset_repeat = 10;
inline constexpr std::uint32_t eeprom_write_us = 18000;  ///< write / page change / ID8 completion
inline constexpr std::uint32_t power_on_standby_us = 1500000;  ///< no battery (1 s with battery)

// --- plans: sequences of requests the user's I/O sends ---------------------------------------
/// One request to send, then a pause before the next step.
struct plan_step {
  std::uint8_t request[tformat::max_request_size] = {};
  std::uint8_t size = 0;
  std::uint32_t wait_after_us = 0;
  /// For EEPROM reads that verify a write: the EDF the response must carry.
  bool verify = false;
  std::uint8_t expected_edf = 0;
  constexpr byte_view view() const noexcept { return byte_view(request, size); }
};

template <std::size_t N>
struct plan {
  plan_step steps[N] = {};
  std::size_t size = 0;
  constexpr const plan_step* begin() const noexcept { return steps; }
  constexpr const plan_step* end() const noexcept { return steps + size; }
};

namespace detail {
template <std::size_t N>
constexpr errc add_step(plan<N>& p, tformat::data_id id, std::uint32_t wait_us,
                        std::uint8_t address = 0, std::uint8_t data = 0) noexcept {
  if (p.size >= N) {
    return errc::buffer_too_small;
  }
  plan_step& s = p.steps[p.size];
  const auto n = tformat::encode_request(id, address, data,
                                         mutable_byte_view(s.request, tformat::max_request_size));
  if (!n) {
    return n.error();
  }
  s.size = static_cast<std::uint8_t>(n.value());
  s.wait_after_us = wait_us;
  ++p.size;
  return errc::ok;
}
}  // namespace detail

/// A reset (ID7 errors, ID8 single-turn zero, IDC multi-turn and errors): the request 10 times,
/// 40 µs apart, with the shaft still; the last step waits for completion (18 ms for ID8).
/// Other IDs: errc::invalid_argument.
constexpr result<plan<10>> reset_plan(tformat::data_id id) noexcept {
  if (id != tformat::data_id::reset_errors && id != tformat::data_id::reset_single_turn &&
      id != tformat::data_id::reset_multi_turn) {
    return errc::invalid_argument;
  }
  plan<10> p;
  for (unsigned i = 0; i < reset_repeat; ++i) {
    const bool last = i + 1U == reset_repeat;
    const std::uint32_t wait =
        last ? (id == tformat::data_id::reset_single_turn ? eeprom_write_us : reset_interval_us)
             : reset_interval_us;
    (void)detail::add_step(p, id, wait);
  }
  return p;
}

/// Selects EEPROM page 0..5 (user) or 7 (temperature functions): write address 127, then wait
/// 18 ms (the EEPROM is busy after a page change).
constexpr result<plan<1>> page_change_plan(std::uint8_t page) noexcept {
  if (page > 7U || page == 6U) {
    return errc::out_of_range;
  }
  plan<1> p;
  (void)detail::add_step(p, tformat::data_id::eeprom_write, eeprom_write_us,
                         tformat::page_select_address, page);
  return p;
}

/// Whether `address` of `page` may be written: 0..126 of the user pages 0..5; on page 7 only
/// the over-heat threshold (address 4; address 5, the temperature, is read only). The encoder
/// answers a write anywhere else with ID3 data (spec §6.1.1, §7, §9.4 Table 6 No.2).
constexpr bool writable(std::uint8_t page, std::uint8_t address) noexcept {
  return page <= 5U ? address < tformat::page_select_address : (page == 7U && address == 4U);
}

/// Writes `data` at `address` of `page`, then verifies it: page change, write, wait 18 ms, the
/// page specified again (a written value reads back only after that or a power cycle: spec
/// §10, "Access to EEPROM"), wait 18 ms, read back (a write response only confirms reception;
/// spec §6.3.5). The last step is marked verify with the expected EDF. errc::out_of_range for
/// an address the encoder does not open for writing (writable()).
constexpr result<plan<4>> write_verify_plan(std::uint8_t page, std::uint8_t address,
                                            std::uint8_t data) noexcept {
  if (!writable(page, address)) {
    return errc::out_of_range;
  }
  plan<4> p;
  (void)detail::add_step(p, tformat::data_id::eeprom_write, eeprom_write_us,
                         tformat::page_select_address, page);
  (void)detail::add_step(p, tformat::data_id::eeprom_write, eeprom_write_us, address, data);
  (void)detail::add_step(p, tformat::data_id::eeprom_write, eeprom_write_us,
                         tformat::page_select_address, page);
  (void)detail::add_step(p, tformat::data_id::eeprom_read, 0, address);
  p.steps[3].verify = true;
  p.steps[3].expected_edf = data;
  return p;
}

// --- page 7: temperature functions (spec §7) ---------------------------------------------------
inline constexpr std::uint8_t temperature_page = 7;
inline constexpr std::uint8_t overheat_address = 4;
inline constexpr std::uint8_t temperature_address = 5;
inline constexpr std::uint8_t overheat_factory = 0xDA;  ///< 90 °C
inline constexpr std::uint8_t overheat_off = 0x00;

/// The over-heat threshold byte for `celsius` (1..127): °C + 128 (spec §7.2.1: 90 °C → 0xDA).
constexpr result<std::uint8_t> encode_overheat_threshold(int celsius) noexcept {
  if (celsius < 1 || celsius > 127) {
    return errc::out_of_range;
  }
  return static_cast<std::uint8_t>(celsius + 128);
}

/// Decoded over-heat setting: disabled when bit 7 is 0 (spec §7.2.2).
struct overheat_setting {
  bool enabled = false;
  int celsius = 0;
};
constexpr overheat_setting decode_overheat_threshold(std::uint8_t value) noexcept {
  if ((value & 0x80U) == 0U) {
    return {false, 0};
  }
  return {true, static_cast<int>(value) - 128};
}

/// Substrate temperature: two's complement °C (spec §7.3; its table's "0000 0001 = -1 °C" is
/// read as +1 °C, as a two's complement table and §7.3.1's example say: docs/tformat.md §7).
constexpr int decode_temperature(std::uint8_t value) noexcept {
  return value >= 0x80U ? static_cast<int>(value) - 256 : static_cast<int>(value);
}

// --- alarms (spec §6.5) ---------------------------------------------------------------------
/// How the encoder holds an ALMC flag (spec §6.5).
enum class latch_rule : std::uint8_t {
  none = 0,     ///< "Non-latched": follows its condition (FS, BA)
  latched = 1,  ///< "Latched" or "Latched during main power-on": held until a reset (ID7, IDC)
  /// CE: two cases by the shaft speed when the error is detected. Case I, at 100 min^-1 or
  /// more: "Non-latched", checked every 45° of mechanical angle and "automatically released at
  /// every 45°" once the deviation is below ±22.5°. Case II, below 100 min^-1: "Latched during
  /// main power-on" (held until a reset).
  by_speed = 2,
};
/// The shaft speed from which a counting error is case I, non-latched (spec §6.5), in min^-1.
inline constexpr std::uint32_t counting_error_case_i_rpm = 100;
/// The magnitude of a signed shaft speed (min^-1; negative: the other direction). §6.5 gives
/// the CE cases by speed alone (§5.4.1 Note 3's cases: "in one direction", either one), so
/// the magnitude counts: -150 min^-1 is case I, -50 case II.
constexpr std::uint32_t speed_magnitude(std::int32_t rpm) noexcept {
  return rpm < 0 ? 0U - static_cast<std::uint32_t>(rpm) : static_cast<std::uint32_t>(rpm);
}

struct alarm_info {
  const char* symbol;
  const char* name;
  const char* action;
  tformat::almc_bit flag;
  latch_rule latch;

  /// Whether the flag is held until a reset when raised with the shaft at `rpm` (min^-1,
  /// signed: its magnitude counts).
  constexpr bool latched_at(std::int32_t rpm) const noexcept {
    return latch == latch_rule::latched ||
           (latch == latch_rule::by_speed && speed_magnitude(rpm) < counting_error_case_i_rpm);
  }
};

inline constexpr alarm_info alarm_table[8] = {
    {"OS", "over-speed", "reset errors (ID7 or IDC); the multi-turn data may be wrong",
     tformat::almc_bit::os, latch_rule::latched},
    {"FS", "full absolute status",
     "slow below 100 rpm and wait: the single-turn data has only 5 bits of accuracy meanwhile",
     tformat::almc_bit::fs, latch_rule::none},
    {"CE", "counting error",
     "stop the servo; at 100 rpm or more it releases itself (checked every 45 degrees), below "
     "it stays until reset errors (ID7 or IDC); or cycle power",
     tformat::almc_bit::ce, latch_rule::by_speed},
    {"OF", "counter overflow", "reset errors (ID7 or IDC)", tformat::almc_bit::of,
     latch_rule::latched},
    {"OH", "over-heat", "let the encoder cool, then reset errors (ID7 or IDC)",
     tformat::almc_bit::oh, latch_rule::latched},
    {"ME", "multi-turn error", "return to the origin and reset errors (ID7 or IDC)",
     tformat::almc_bit::me, latch_rule::latched},
    {"BE", "battery error",
     "check or replace the battery, then reset errors and multi-turn data (IDC)",
     tformat::almc_bit::be, latch_rule::latched},
    {"BA", "battery alarm", "check or replace the battery; clears itself when the voltage recovers",
     tformat::almc_bit::ba, latch_rule::none},
};

/// The ALMC bits whose table row has rule `r`.
constexpr std::uint8_t alarm_mask(latch_rule r) noexcept {
  std::uint8_t m = 0;
  for (const alarm_info& i : alarm_table) {
    m = i.latch == r ? static_cast<std::uint8_t>(m | static_cast<std::uint8_t>(i.flag)) : m;
  }
  return m;
}

constexpr const alarm_info& info(tformat::almc_bit a) noexcept {
  for (const alarm_info& i : alarm_table) {
    if (i.flag == a) {
      return i;
    }
  }
  return alarm_table[0];
}

}  // namespace ts5700n8500
}  // namespace devices
}  // namespace motionbus

#endif  // MOTIONBUS_DEVICES_TS5700N8500_HPP
