// motionbus — a continuous encoder position from successive absolute reads, protocol-neutral
// (adapters: tformat/position.hpp, biss/position.hpp; docs/position.md).
//
// A reading is the encoder's absolute value in 0..M-1, M = counts_per_turn x turns (turns = 1
// when only the single-turn value is read; 65536 for the TS5700N8500's multi-turn counter).
// Successive readings are unwrapped into a signed 64-bit count: the step between two readings
// is taken modulo M as the one of smallest magnitude, so the position runs on across the
// single-turn rollover and the multi-turn counter's wrap. A step larger than the axis can make
// (max_step per read period) is an error, reported as position_status::implausible_step: the
// position stays where it was (the choice: a glitch, a reset or a changed offset must not
// become revolutions), and the read still counts as an elapsed period, so that a reading that
// comes back after the glitch is accepted. reset() forgets the position (the next reading
// seeds it), e.g. after an encoder's zero reset.
//
// The count path (update, missed) is 64-bit integer additions and comparisons only (no
// multiplication, no division, no floating point; update(single, multi) adds one multiply).
// revolutions() and degrees() are helpers in double: on a core without an FPU (Cortex-M0+,
// Cortex-M3) they are software floating point (the compiler's library: a 64-bit integer to double
// conversion and a multiply or divide, some hundreds of cycles and one to two kilobytes of flash),
// and cost nothing unless called; turns(), within_turn() and millidegrees() are integer helpers.
#ifndef MOTIONBUS_CORE_POSITION_HPP
#define MOTIONBUS_CORE_POSITION_HPP

#include <cstdint>

namespace motionbus {

/// The limits of a reading: M = counts_per_turn x turns must be 4 .. 2^62.
inline constexpr std::uint64_t max_position_range = std::uint64_t{1} << 62U;

/// What a position tracker is told about its encoder.
struct position_config {
  /// Counts in one turn (2^17 on the TS5700N8500; SIP_CNT x 2^SIP_RES on a BiSS BP3 rotary).
  std::uint64_t counts_per_turn = std::uint64_t{1} << 17U;
  /// Range of the multi-turn counter in the reading (2^16 on the TS5700N8500); 1 when the
  /// reading is the single-turn value alone.
  std::uint64_t turns = 1;
  /// The largest plausible change of the reading in one read period, in counts (the axis's top
  /// speed times the read period, with margin). 0: the largest unwrapping can tell, (M - 1) / 2.
  std::uint64_t max_step = 0;

  /// M: the reading runs 0..M-1 (0 when the configuration is invalid).
  constexpr std::uint64_t range() const noexcept {
    if (counts_per_turn == 0U || turns == 0U || counts_per_turn > max_position_range / turns) {
      return 0;
    }
    const std::uint64_t m = counts_per_turn * turns;
    return m < 4U ? 0U : m;
  }
  /// The largest step unwrapping can tell from its opposite: (M - 1) / 2.
  constexpr std::uint64_t unambiguous_step() const noexcept { return (range() - 1U) / 2U; }
  /// Valid: a range of 4 .. 2^62 and max_step at most unambiguous_step().
  constexpr bool valid() const noexcept { return range() != 0U && max_step <= unambiguous_step(); }
  /// A reading of `single_turn_bits` + `multi_turn_bits` (0: single-turn only). Bits above 62 in
  /// total give an invalid configuration.
  static constexpr position_config from_bits(unsigned single_turn_bits, unsigned multi_turn_bits,
                                             std::uint64_t max_step = 0) noexcept {
    if (single_turn_bits > 62U || multi_turn_bits > 62U ||
        single_turn_bits + multi_turn_bits > 62U) {
      return {0, 0, max_step};
    }
    return {std::uint64_t{1} << single_turn_bits, std::uint64_t{1} << multi_turn_bits, max_step};
  }
};

/// What one update did. Its numbers are interface: firmware logs them.
enum class position_status : std::uint8_t {
  accepted = 0,          ///< the step was plausible: the position moved by it
  seeded = 1,            ///< the first reading (or the first after reset()): the position is it
  implausible_step = 2,  ///< the step exceeds max_step x periods: not applied, reported
  out_of_range = 3,      ///< a reading outside 0..M-1 or a field outside its range: a period missed
  invalid_config = 4,    ///< position_config::valid() is false: nothing is tracked
  no_reading = 5,        ///< (adapters) the transaction gave no reading: counted as missed()
};

/// snake_case name of a position_status (static storage).
constexpr const char* to_string(position_status s) noexcept {
  switch (s) {
    case position_status::accepted: return "accepted";
    case position_status::seeded: return "seeded";
    case position_status::implausible_step: return "implausible_step";
    case position_status::out_of_range: return "out_of_range";
    case position_status::invalid_config: return "invalid_config";
    case position_status::no_reading: return "no_reading";
  }
  return "unknown";
}

/// The continuous position of one encoder. Not thread-safe: one context calls update() and
/// missed(), once per read period; the accessors may run in the same context.
class position_tracker {
 public:
  constexpr explicit position_tracker(const position_config& cfg = {}) noexcept
      : range_(cfg.valid() ? cfg.range() : 0U),
        counts_per_turn_(cfg.valid() ? cfg.counts_per_turn : 1U),
        turns_(cfg.valid() ? cfg.turns : 1U),
        max_step_(cfg.max_step == 0U ? cfg.unambiguous_step() : cfg.max_step),
        limit_(cfg.unambiguous_step()),
        bound_(max_step_) {}

  /// One read period with reading `value` (0..M-1): seeds the position, applies a plausible
  /// step, or reports why not (the position is then unchanged).
  constexpr position_status update(std::uint64_t value) noexcept {
    if (range_ == 0U) {
      return position_status::invalid_config;
    }
    if (value >= range_) {
      missed();
      return position_status::out_of_range;
    }
    if (!seeded_) {
      seeded_ = true;
      reading_ = value;
      counts_ = static_cast<std::int64_t>(value);
      step_ = 0;
      periods_ = 1;
      bound_ = max_step_;
      return position_status::seeded;
    }
    // The step modulo M of smallest magnitude: value - reading_ folded into [-(M/2), M/2].
    std::uint64_t forward = value - reading_;  // modulo 2^64
    if (value < reading_) {
      forward += range_;  // now (value - reading_) mod M, in 0..M-1
    }
    const bool backward = forward > range_ / 2U;
    const std::uint64_t magnitude = backward ? range_ - forward : forward;
    // Plausible: within max_step per period elapsed since the last accepted reading (bound_).
    if (magnitude > bound_) {
      missed();
      ++implausible_;
      return position_status::implausible_step;
    }
    const auto signed_magnitude = static_cast<std::int64_t>(magnitude);
    step_ = backward ? -signed_magnitude : signed_magnitude;
    // Added modulo 2^64: hostile readings that keep stepping one way wrap the count (after
    // 2^63 counts) rather than overflow it.
    counts_ = static_cast<std::int64_t>(static_cast<std::uint64_t>(counts_) +
                                        static_cast<std::uint64_t>(step_));
    reading_ = value;
    periods_ = 1;
    bound_ = max_step_;
    return position_status::accepted;
  }
  /// update() from the two fields of a reading: `single_turn` in 0..counts_per_turn-1,
  /// `multi_turn` in 0..turns-1 (out_of_range otherwise).
  constexpr position_status update(std::uint64_t single_turn, std::uint64_t multi_turn) noexcept {
    if (range_ == 0U) {
      return position_status::invalid_config;
    }
    if (single_turn >= counts_per_turn_ || multi_turn >= turns_) {
      missed();
      return position_status::out_of_range;
    }
    return update(multi_turn * counts_per_turn_ + single_turn);
  }
  /// A read period without a reading (a failed transaction): the axis may have moved meanwhile,
  /// so the next step may be max_step larger.
  /// (The bound grows by max_step a period up to (M - 1) / 2, beyond which a step cannot be
  /// told from its opposite: after that many missed periods a step is no longer checked.)
  constexpr void missed() noexcept {
    // coverage-branch: saturation, after 2^32 - 1 missed periods in a row (minutes of a test)
    periods_ += periods_ != 0xFFFFFFFFU ? 1U : 0U;
    bound_ = limit_ - bound_ < max_step_ ? limit_ : bound_ + max_step_;
  }
  /// Forgets the position: the next reading seeds it; step(), periods(), plausible_step() as new.
  constexpr void reset() noexcept {
    seeded_ = false;
    step_ = 0;
    periods_ = 1;
    bound_ = max_step_;
  }

  /// A reading has seeded the position.
  constexpr bool has_position() const noexcept { return seeded_; }
  /// The continuous position in counts (the first reading, then every accepted step; modulo
  /// 2^64 in two's complement, should it ever pass 2^63).
  constexpr std::int64_t counts() const noexcept { return counts_; }
  /// The last accepted step in counts (0 after seeding): with a fixed read period, the speed.
  constexpr std::int64_t step() const noexcept { return step_; }
  /// The last accepted reading.
  constexpr std::uint64_t reading() const noexcept { return reading_; }
  /// Read periods since the last accepted reading (1 right after one).
  constexpr std::uint32_t periods() const noexcept { return periods_; }
  /// The largest step the next reading may make: max_step x periods(), at most (M - 1) / 2.
  constexpr std::uint64_t plausible_step() const noexcept { return bound_; }
  /// Implausible steps reported since construction.
  constexpr std::uint32_t implausible_steps() const noexcept { return implausible_; }
  /// The effective max_step (the configured one, or (M - 1) / 2 for 0).
  constexpr std::uint64_t max_step() const noexcept { return max_step_; }
  constexpr std::uint64_t counts_per_turn() const noexcept { return counts_per_turn_; }

  /// Whole turns, rounded towards minus infinity (a 64-bit division: a helper, not the count
  /// path).
  constexpr std::int64_t turns() const noexcept {
    const auto cpt = static_cast<std::int64_t>(counts_per_turn_);
    const std::int64_t q = counts_ / cpt;
    return (counts_ % cpt) < 0 ? q - 1 : q;
  }
  /// The counts within the current turn, 0..counts_per_turn-1.
  constexpr std::uint64_t within_turn() const noexcept {
    const auto cpt = static_cast<std::int64_t>(counts_per_turn_);
    const std::int64_t r = counts_ % cpt;
    return static_cast<std::uint64_t>(r < 0 ? r + cpt : r);
  }
  /// The angle in thousandths of a degree, rounded towards minus infinity (integer:
  /// turns() x 360000 + floor(within_turn() x 360000 / counts_per_turn), computed without
  /// overflow for every counts_per_turn; the sum wraps modulo 2^64 past 2^63 / 360000 turns).
  constexpr std::int64_t millidegrees() const noexcept {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(turns()) * 360000U +
                                     mul_div(within_turn(), 360000U, counts_per_turn_));
  }
  /// The position in revolutions (double: software floating point on cores without an FPU).
  constexpr double revolutions() const noexcept {
    return static_cast<double>(counts_) / static_cast<double>(counts_per_turn_);
  }
  /// The position in degrees (double, as revolutions()).
  constexpr double degrees() const noexcept { return revolutions() * 360.0; }

 private:
  // floor(x * k / d) for x < d <= 2^62 and k < 2^32, bit by bit over k (no 128-bit product):
  // the remainder stays below d, so 2r + x < 2^63.
  static constexpr std::uint64_t mul_div(std::uint64_t x, std::uint32_t k,
                                         std::uint64_t d) noexcept {
    std::uint64_t q = 0;
    std::uint64_t r = 0;
    for (unsigned b = 32; b-- > 0U;) {
      q <<= 1U;
      r <<= 1U;
      if (r >= d) {
        r -= d;
        ++q;
      }
      if (((k >> b) & 1U) != 0U) {
        r += x;
        if (r >= d) {
          r -= d;
          ++q;
        }
      }
    }
    return q;
  }

  std::uint64_t range_;
  std::uint64_t counts_per_turn_;
  std::uint64_t turns_;
  std::uint64_t max_step_;
  std::uint64_t limit_;
  std::uint64_t bound_;
  std::uint64_t reading_ = 0;
  std::int64_t counts_ = 0;
  std::int64_t step_ = 0;
  std::uint32_t periods_ = 1;
  std::uint32_t implausible_ = 0;
  bool seeded_ = false;
};

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_POSITION_HPP
