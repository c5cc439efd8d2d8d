// motionbus — BiSS-C encoder position and link health: the core position tracker and link
// health (core/position.hpp, core/link_health.hpp) fed from decode_frame results, and the
// frame's deadline from the clock rate, the measured line delay and the timeout
// (docs/position.md).
//
// A slave's reading is its multi-turn and single-turn fields (slave_data::multi_turn,
// single_turn): counts_per_turn = 2^single_turn_bits unless told otherwise, turns =
// 2^multi_turn_bits (1 for a single-turn slave, whose rollover the tracker unwraps). A rotary
// BP3 encoder whose turn is not a power of two (ABSYS: POSITION_WITH_OFFSET modulo
// PULSES_PER_REV, ABSYS document §2.3; pulses = SIP_CNT x 2^SIP_RES, §2.9.4) is configured
// from its electronic data sheet.
#ifndef MOTIONBUS_BISS_POSITION_HPP
#define MOTIONBUS_BISS_POSITION_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/biss/codec.hpp"
#include "motionbus/biss/eds.hpp"
#include "motionbus/biss/frame.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/link_health.hpp"
#include "motionbus/core/position.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {
namespace biss {

/// The tracker configuration of a slave of layout `l`: 2^single_turn_bits counts a turn,
/// 2^multi_turn_bits turns (more than 62 bits in all: invalid).
constexpr position_config position_config_for(const slave_layout& l,
                                              std::uint64_t max_step = 0) noexcept {
  return position_config::from_bits(l.single_turn_bits, l.multi_turn_bits, max_step);
}

/// The same with `counts_per_turn` given (the single-turn value wraps at it, not at a power of
/// two): 2^multi_turn_bits turns of `counts_per_turn` counts.
constexpr position_config position_config_for(const slave_layout& l, std::uint64_t counts_per_turn,
                                              std::uint64_t max_step) noexcept {
  if (l.multi_turn_bits > 62U) {
    return {0, 0, max_step};
  }
  return {counts_per_turn, std::uint64_t{1} << l.multi_turn_bits, max_step};
}

/// A rotary BP3 encoder from its electronic data sheet: pulses_per_revolution() counts a turn,
/// 2^MT_LEN turns. A linear encoder or a pulse count of 0 gives an invalid configuration (a
/// linear scale has no turn to unwrap).
constexpr position_config position_config_for(const bp3_profile& p,
                                              std::uint64_t max_step = 0) noexcept {
  if (p.type != encoder_type::rotary || p.mt_length > 62U) {
    return {0, 0, max_step};
  }
  return {p.pulses_per_revolution(), std::uint64_t{1} << p.mt_length, max_step};
}

/// Feeds slave `slave` (chain order, 0 first) of one frame's decode result to `t`: a complete
/// frame whose slave reports no error (nE high) updates it with the slave's multi-turn and
/// single-turn fields. Any other result (incomplete, failed, nE active: the ABSYS document §1
/// sets nE for "an incorrect absolute position", so its data is not a reading; a slave index
/// past the chain) is a read period without a reading: missed(), position_status::no_reading.
template <std::size_t N>
constexpr position_status update_position(position_tracker& t, const frame_result<N>& r,
                                          std::size_t slave = 0) noexcept {
  if (!r.is_complete() || slave >= r.value().size() || r.value().slaves[slave].error()) {
    t.missed();
    return position_status::no_reading;
  }
  const slave_data& d = r.value().slaves[slave];
  return t.update(d.single_turn, d.multi_turn);
}

/// The link outcome of a BiSS-C frame: classify() for results that are not complete
/// (biss_no_ack, biss_no_start, an incomplete capture: timeouts; crc_mismatch: a CRC error);
/// a complete frame whose slave `slave` has nE or nW active is an alarm, else ok.
template <std::size_t N>
constexpr link_outcome outcome_of(const frame_result<N>& r, std::size_t slave = 0) noexcept {
  if (!r.is_complete()) {
    return classify(r);
  }
  if (slave >= r.value().size()) {
    return link_outcome::invalid;
  }
  const slave_data& d = r.value().slaves[slave];
  return d.error() || d.warning() ? link_outcome::alarm : link_outcome::ok;
}

/// Records one frame in `h` (outcome_of).
template <std::size_t N>
constexpr link_event record(link_health& h, const frame_result<N>& r,
                            std::size_t slave = 0) noexcept {
  return h.record(outcome_of(r, slave));
}

/// A frame's timing at a clock rate.
struct frame_timing {
  /// MA clocks to capture: the line delay allowance, the Ack allowance, Start, CDS and the
  /// chain's bits (the capture length to clock, e.g. the SPI transfer).
  std::size_t capture_bits = 0;
  /// capture_bits clocks, rounded up: a frame not complete by then is a timeout.
  std::uint32_t response_timeout_ns = 0;
  /// capture_bits plus the timeout's clocks: the earliest start of the next frame.
  std::uint32_t cycle_ns = 0;
  /// The decoder's bounds that go with it: a capture without an Ack within the line delay
  /// allowance is biss_no_ack, one without a Start within the Ack allowance biss_no_start.
  decode_options options{};
};

/// The whole clocks `ns` nanoseconds last at `clock_hz`, rounded up (a line delay measured in
/// time, as clocks; 0 for a clock of 0).
constexpr std::size_t clocks_for_ns(std::uint32_t ns, std::uint32_t clock_hz) noexcept {
  return clock_hz == 0U
             ? 0U
             : static_cast<std::size_t>((std::uint64_t{ns} * clock_hz + 999999999U) / 1000000000U);
}

/// The timing of frames of `chain` clocked at `clock_hz`, with the line delay measured in
/// whole clocks (`line_delay_bits`: chain_frame::line_delay of a good frame, or clocks_for_ns
/// of a measured delay), the slave's Ack (processing time) of at most `ack_bits` clocks (1 for
/// the ABSYS, Table 1 note 2) and a timeout of `timeout_bits` clocks. Choice: one clock is
/// added to the measured line delay (a delay measured in whole clocks may round either way),
/// so capture_bits = line_delay_bits + 1 + ack_bits + 2 + the chain's bits. Errors:
/// invalid_argument (clock 0, Ack 0, empty chain or longer than max_chain), biss_layout,
/// out_of_range (a count of 2^32 clocks or more, whatever the clock; a time above 2^32 - 1 ns).
constexpr result<frame_timing> frame_timing_for(span<const slave_layout> chain,
                                                std::uint32_t clock_hz, std::size_t line_delay_bits,
                                                std::size_t ack_bits,
                                                std::size_t timeout_bits) noexcept {
  if (clock_hz == 0U || ack_bits == 0U || chain.empty() || chain.size() > max_chain) {
    return errc::invalid_argument;
  }
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    if (chain[i].validate() != errc::ok) {
      return errc::biss_layout;
    }
    bits += chain[i].frame_bits();
  }
  // Counts of 2^32 clocks or more are refused: at 1 GHz or less they last 2^32 ns or more, and
  // the products below stay under 2^64 (compared as 64-bit values, whatever size_t's width).
  const auto too_long = [](std::uint64_t clocks) { return clocks >= (std::uint64_t{1} << 32U); };
  if (too_long(line_delay_bits) || too_long(ack_bits) || too_long(timeout_bits)) {
    return errc::out_of_range;
  }
  const std::uint64_t capture = line_delay_bits + 1U + ack_bits + 2U + bits;
  const auto ns = [clock_hz](std::uint64_t clocks) {
    return (clocks * 1000000000U + clock_hz - 1U) / clock_hz;  // clocks < 2^34: no overflow
  };
  const std::uint64_t response = ns(capture);
  const std::uint64_t cycle = ns(capture + timeout_bits);
  if (cycle > 0xFFFFFFFFU) {
    return errc::out_of_range;
  }
  frame_timing t;
  t.capture_bits = static_cast<std::size_t>(capture);
  t.response_timeout_ns = static_cast<std::uint32_t>(response);
  t.cycle_ns = static_cast<std::uint32_t>(cycle);
  t.options.max_line_delay = line_delay_bits + 1U;
  t.options.max_ack_bits = ack_bits;
  return t;
}

/// Single-slave form.
constexpr result<frame_timing> frame_timing_for(const slave_layout& layout, std::uint32_t clock_hz,
                                                std::size_t line_delay_bits, std::size_t ack_bits,
                                                std::size_t timeout_bits) noexcept {
  return frame_timing_for(span<const slave_layout>(&layout, 1), clock_hz, line_delay_bits, ack_bits,
                          timeout_bits);
}

}  // namespace biss
}  // namespace motionbus

#endif  // MOTIONBUS_BISS_POSITION_HPP
