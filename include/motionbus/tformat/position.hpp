// motionbus — T-format encoder position and link health: the core position tracker and link
// health (core/position.hpp, core/link_health.hpp) fed from decode_response results, and the
// response deadline from the frame lengths and the bit rate (docs/position.md).
//
// Which reading a response gives (TS5700N8500 specification Table 2): ID0 and the resets 7, 8,
// C carry ABS alone (a single-turn reading: the tracker unwraps its rollover); ID3 carries ABS
// and ABM (counts_per_turn x 2^multi_turn_bits, the counter wrapping 65535 -> 0 on the
// TS5700N8500, §5.4.2, §6.5 "cyclic counter"); ID1 carries ABM alone (a reading in whole
// turns). Other responses (ID2, EEPROM) carry no position.
#ifndef MOTIONBUS_TFORMAT_POSITION_HPP
#define MOTIONBUS_TFORMAT_POSITION_HPP

#include <cstdint>

#include "motionbus/core/link_health.hpp"
#include "motionbus/core/position.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/tformat/frame.hpp"

namespace motionbus {
namespace tformat {

/// The tracker configuration for responses to `polled` from an encoder of resolution `res`:
/// ID3 both fields, ID1 the turns alone (counts_per_turn 1), any other ID ABS alone. Bits above
/// 24 give an invalid configuration (position_config::valid()).
constexpr position_config position_config_for(resolution res, data_id polled,
                                              std::uint64_t max_step = 0) noexcept {
  const unsigned st = res.single_turn_bits <= 24U ? res.single_turn_bits : 63U;
  const unsigned mt = res.multi_turn_bits <= 24U ? res.multi_turn_bits : 63U;
  switch (polled) {
    case data_id::read_all: return position_config::from_bits(st, mt, max_step);
    case data_id::read_abm: return position_config::from_bits(0, mt, max_step);
    default: return position_config::from_bits(st, 0, max_step);
  }
}

namespace detail {
// ca0/ca1: the request arrived corrupted and "the received data should be invalid without
// fail" (spec §6.3.2).
constexpr bool communication_alarm(const response& v) noexcept {
  return v.layout().sf() && (v.sf & (sf::ca0 | sf::ca1)) != 0U;
}
}  // namespace detail

/// Feeds one transaction's decode result to `t`: a complete response with a position updates it
/// (ID3 ABS and ABM, ID1 ABM, ID0/7/8/C ABS: as configured by position_config_for; the
/// tracker's range must match the polled ID). Any other result (incomplete, failed, ca0/ca1
/// set, no position field) is a read period without a reading: position_tracker::missed(),
/// position_status::no_reading.
constexpr position_status update_position(position_tracker& t,
                                          const decode_result<response>& r) noexcept {
  if (!r.is_complete() || detail::communication_alarm(r.value())) {
    t.missed();
    return position_status::no_reading;
  }
  const response& v = r.value();
  const response_layout lay = v.layout();
  if (lay.abs() && lay.abm()) {
    return t.update(v.abs, v.abm);
  }
  if (lay.abm()) {
    return t.update(v.abm);
  }
  if (lay.abs()) {
    return t.update(v.abs);
  }
  t.missed();
  return position_status::no_reading;
}

/// The link outcome of a T-format transaction: classify() for results that are not complete
/// (tformat_communication_alarm from check_response is invalid); a complete response with ca0
/// or ca1 set is invalid too (the request arrived corrupted), one with ea0 or ea1 in SF, or an
/// ID3 response with a non-zero ALMC (spec §6.3.2: FS, OS and OF appear in ALMC only), is an
/// alarm, else ok.
constexpr link_outcome outcome_of(const decode_result<response>& r) noexcept {
  if (!r.is_complete()) {
    return classify(r);
  }
  const response& v = r.value();
  if (detail::communication_alarm(v)) {
    return link_outcome::invalid;
  }
  const bool alarm = (v.layout().sf() && (v.sf & (sf::ea0 | sf::ea1)) != 0U) ||
                     (v.layout().almc() && v.almc != 0U);
  return alarm ? link_outcome::alarm : link_outcome::ok;
}

/// Records one transaction in `h` (outcome_of).
constexpr link_event record(link_health& h, const decode_result<response>& r) noexcept {
  return h.record(outcome_of(r));
}

/// The encoder's typical response start after the request's last delimiter (TS5700N8500
/// specification §8.1, §9.1: "3 μs (typ.)").
inline constexpr std::uint32_t typical_response_start_ns = 3000;

/// The time of `fields` 10-bit fields at `bit_rate` bits/s, rounded up (0 for a rate of 0).
constexpr std::uint32_t fields_ns(std::uint32_t fields, std::uint32_t bit_rate) noexcept {
  return bit_rate == 0U
             ? 0U
             : static_cast<std::uint32_t>(
                   (std::uint64_t{fields} * 10U * 1000000000U + bit_rate - 1U) / bit_rate);
}

/// The deadline for the response to `id`, counted from the end of the request's last
/// delimiter: the response start allowance plus the response's fields at `bit_rate`. The spec
/// gives only a typical start (3 µs) and no maximum: the allowance is chosen as twice the
/// typical value, `start_ns` (6 µs by default). ID0 at 2.5 Mbps: 6 + 24 = 30 µs; ID3: 6 + 44 =
/// 50 µs; at 5 Mbps 18 and 28 µs. A response not complete by then is a timeout.
constexpr std::uint32_t response_timeout_ns(
    data_id id, std::uint32_t bit_rate,
    std::uint32_t start_ns = 2U * typical_response_start_ns) noexcept {
  return start_ns + fields_ns(layout_of(id).size, bit_rate);
}

/// The same counted from the request's first start bit (the request's fields added): the
/// deadline a master that arms one timer when it starts sending uses.
constexpr std::uint32_t transaction_timeout_ns(
    data_id id, std::uint32_t bit_rate,
    std::uint32_t start_ns = 2U * typical_response_start_ns) noexcept {
  return fields_ns(static_cast<std::uint32_t>(request_size(id)), bit_rate) +
         response_timeout_ns(id, bit_rate, start_ns);
}

}  // namespace tformat
}  // namespace motionbus

#endif  // MOTIONBUS_TFORMAT_POSITION_HPP
