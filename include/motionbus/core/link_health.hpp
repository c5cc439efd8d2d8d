// motionbus — the health of an encoder link, protocol-neutral and I/O-free: one record() per
// transaction (request sent, response decoded or its deadline passed), counters of frames, CRC
// failures, timeouts, alarms and other failures, and a link state with hysteresis ("lost"
// after lose_after consecutive failures, "restored" after restore_after consecutive successes).
// Adapters: tformat/position.hpp and biss/position.hpp classify their decode results and derive
// the response deadline from the protocol's timing (docs/position.md).
//
// Choices (documented in docs/position.md): a frame whose device reports an alarm (T-format
// SF ea0/ea1 or ALMC, BiSS nE/nW) is a success for the link and counted as an alarm: the
// line carried a good frame, the encoder reports its own state. The link starts lost: it is up
// only once restore_after consecutive successes have proven it (a link that never answered is
// never reported connected), and that first rise is reported as link_event::restored.
#ifndef MOTIONBUS_CORE_LINK_HEALTH_HPP
#define MOTIONBUS_CORE_LINK_HEALTH_HPP

#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"

namespace motionbus {

/// What one transaction came to. These enums' numbers are interface: firmware logs them.
enum class link_outcome : std::uint8_t {
  ok = 0,         ///< a good frame, no device alarm
  alarm = 1,      ///< a good frame whose device reports an alarm (a success for the link)
  crc_error = 2,  ///< a frame whose check value is wrong
  timeout = 3,    ///< no response, or an incomplete one, by the deadline
  invalid = 4,    ///< any other failure: framing, mismatch, a communication alarm
};

/// The link's state.
enum class link_state : std::uint8_t { up = 0, lost = 1 };

/// What a record() changed.
enum class link_event : std::uint8_t {
  none = 0,
  lost = 1,      ///< lose_after consecutive failures: the link went from up to lost
  restored = 2,  ///< restore_after consecutive successes: from lost back to up
};

constexpr const char* to_string(link_outcome o) noexcept {
  switch (o) {
    case link_outcome::ok: return "ok";
    case link_outcome::alarm: return "alarm";
    case link_outcome::crc_error: return "crc_error";
    case link_outcome::timeout: return "timeout";
    case link_outcome::invalid: return "invalid";
  }
  return "unknown";
}
constexpr const char* to_string(link_state s) noexcept {
  return s == link_state::up ? "up" : "lost";
}

/// The outcome of a transaction from the library's error code alone: ok; crc_mismatch a CRC
/// error; truncated, no_frame, biss_no_ack and biss_no_start a timeout (nothing, or not all of
/// a frame, arrived); every other code invalid. (An alarm needs the decoded frame: adapters.)
constexpr link_outcome classify(errc e) noexcept {
  switch (e) {
    case errc::ok: return link_outcome::ok;
    case errc::crc_mismatch: return link_outcome::crc_error;
    case errc::truncated:
    case errc::no_frame:
    case errc::biss_no_ack:
    case errc::biss_no_start: return link_outcome::timeout;
    default: return link_outcome::invalid;
  }
}

/// The outcome of a decode at the transaction's deadline: complete is ok, incomplete a timeout
/// (the frame had not all arrived), failed as classify(error()).
template <class T, input_unit Unit>
constexpr link_outcome classify(const decode_result<T, Unit>& r) noexcept {
  if (r.is_complete()) {
    return link_outcome::ok;
  }
  return r.is_incomplete() ? link_outcome::timeout : classify(r.error());
}

struct link_config {
  std::uint16_t lose_after = 3;     ///< consecutive failures that lose the link (0 acts as 1)
  std::uint16_t restore_after = 3;  ///< consecutive successes that restore it (0 acts as 1)
};

/// The counters; all saturate at their maximum rather than wrap.
struct link_counters {
  std::uint32_t frames = 0;      ///< transactions recorded
  std::uint32_t good = 0;        ///< ok and alarm outcomes
  std::uint32_t alarms = 0;      ///< alarm outcomes
  std::uint32_t crc_errors = 0;  ///< crc_error outcomes
  std::uint32_t timeouts = 0;    ///< timeout outcomes
  std::uint32_t invalid = 0;     ///< invalid outcomes
  std::uint32_t losses = 0;      ///< times the link was lost after being up
  std::uint16_t consecutive_failures = 0;
  std::uint16_t consecutive_successes = 0;
  constexpr std::uint32_t failures() const noexcept { return crc_errors + timeouts + invalid; }
};

/// The health of one link. One context calls record(); the accessors may run in the same one.
class link_health {
 public:
  constexpr explicit link_health(const link_config& cfg = {}) noexcept
      : lose_after_(cfg.lose_after == 0U ? 1U : cfg.lose_after),
        restore_after_(cfg.restore_after == 0U ? 1U : cfg.restore_after) {}

  /// Records one transaction; returns the state change it caused, if any.
  constexpr link_event record(link_outcome o) noexcept {
    bump(c_.frames);
    const bool success = o == link_outcome::ok || o == link_outcome::alarm;
    switch (o) {  // coverage-branch: gcc's edge for a value outside the enum's five
      case link_outcome::ok: break;
      case link_outcome::alarm: bump(c_.alarms); break;
      case link_outcome::crc_error: bump(c_.crc_errors); break;
      case link_outcome::timeout: bump(c_.timeouts); break;
      case link_outcome::invalid: bump(c_.invalid); break;
    }
    if (success) {
      bump(c_.good);
      c_.consecutive_failures = 0;
      bump16(c_.consecutive_successes);
      if (state_ == link_state::lost && c_.consecutive_successes >= restore_after_) {
        state_ = link_state::up;
        return link_event::restored;
      }
      return link_event::none;
    }
    c_.consecutive_successes = 0;
    bump16(c_.consecutive_failures);
    if (state_ == link_state::up && c_.consecutive_failures >= lose_after_) {
      state_ = link_state::lost;
      bump(c_.losses);
      return link_event::lost;
    }
    return link_event::none;
  }
  /// record(classify(e)).
  constexpr link_event record(errc e) noexcept { return record(classify(e)); }
  /// A transaction whose deadline passed without a response.
  constexpr link_event record_timeout() noexcept { return record(link_outcome::timeout); }

  constexpr link_state state() const noexcept { return state_; }
  constexpr bool lost() const noexcept { return state_ == link_state::lost; }
  constexpr const link_counters& counters() const noexcept { return c_; }
  /// Zeroes the counters (the state and the hysteresis are kept).
  constexpr void clear_counters() noexcept {
    const std::uint16_t f = c_.consecutive_failures;
    const std::uint16_t s = c_.consecutive_successes;
    c_ = link_counters{};
    c_.consecutive_failures = f;
    c_.consecutive_successes = s;
  }

 private:
  // coverage-branch: saturation, after 2^32 - 1 records (minutes of a test); bump16 is tested
  static constexpr void bump(std::uint32_t& n) noexcept { n += n != 0xFFFFFFFFU ? 1U : 0U; }
  static constexpr void bump16(std::uint16_t& n) noexcept {
    n = static_cast<std::uint16_t>(n + (n != 0xFFFFU ? 1U : 0U));
  }

  link_counters c_{};
  std::uint16_t lose_after_;
  std::uint16_t restore_after_;
  link_state state_ = link_state::lost;  // until proven (see the header)
};

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_LINK_HEALTH_HPP
