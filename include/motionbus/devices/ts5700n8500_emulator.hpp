// motionbus — an emulator of the Tamagawa TS5700N8500 T-format encoder (the encoder side of the
// line), for bench emulators, FPGA test benches and hardware-in-the-loop rigs, beside the other
// device emulators (devices/sm_unit_emulator.hpp, devices/absys_emulator.hpp). Give it each
// received request (the bytes up to the line's idle) with the current time; it returns the reply
// the encoder would send.
//
// Modelled (TS5700N8500 specification §6.1.1, §6.3, §6.5, §7–§10; docs/tformat.md §7):
//  - position and turns, with single-turn resolution and ENID from the config;
//  - ALMC flags: latched (OS, OF, OH, ME, BE) until an ID7/IDC reset while their condition is
//    gone, non-latched (FS, BA) following their condition; CE by the shaft speed
//    (set_speed_rpm, signed, its magnitude counts): case I at 100 min^-1 or more follows its
//    condition (the condition the caller clears stands for the 45° check finding the
//    deviation gone), case II below latches, also when the shaft slows below 100 min^-1 with
//    the error present;
//  - abnormal requests: bad sync code → no reply; parity error → ID3 data with ca0; delimiter
//    error (reported by the caller's UART or line decoder) → ID3 data with ca1; unknown Data ID,
//    bad EEPROM CRC or a closed EEPROM address → ID3 data (spec Tables 5, 6);
//  - EEPROM: pages 0..5 of 127 bytes (0..126), page select by writing address 127, page 7 with
//    the over-heat threshold (address 4, read/write) and the substrate temperature (address 5,
//    read only); busy for 18 ms after a write or a page change (reply busy, EDF 00); a read
//    returns the page as it was when the page was last specified (or at power-on): a written
//    value is read back only after the page is specified again (spec §10, "Access to EEPROM":
//    "For confirming the data, turn off and on the main power supply or page is specified
//    again");
//  - resets 7, 8, C act on the 10th consecutive request of the same ID, each at least 40 µs after
//    the previous one (spec §10), after the reply to it (which carries the data as received);
//    ID8 then writes EEPROM (busy 18 ms). Spec §10 has the 10 requests sent "at stationary of
//    the shaft" and does not say what the encoder does with one sent while it turns: the
//    emulator counts a reset request only while set_speed_rpm() is 0; one sent at any other
//    speed is answered but restarts the count, so a master that resets a turning shaft sees
//    its reset not happen.
// Choices where the spec is silent (documented and tested): the reply to an abnormal request
// carries the ID3 control field 0x1A; reading address 127 returns the current page; a write to a
// closed address or an invalid page number gets ID3 data; the over-heat flag is raised when
// the temperature exceeds the threshold (threshold byte bit 7 set, °C = byte - 128).
//
// Firmware contract (Cortex-M4; sizes checked by the test command, stack and instructions by
// the meter at -Os: docs/footprint.md):
//   emulator size: 932 bytes (six EEPROM pages of 127 bytes and page 7, the alarm state). A
//     default-constructed `static` one (the TS5700N8500's settings) is all zeros: .bss.
//   respond(): 294 instructions and 288 bytes of stack for an ID3 request, 372 and 328 for an
//     EEPROM write (ID6: the costliest request measured). It runs where the request's idle
//     line is seen (a receive or idle interrupt); set_position(), rotate(), set_condition()
//     and the other setters must not run while it does.
#ifndef MOTIONBUS_DEVICES_TS5700N8500_EMULATOR_HPP
#define MOTIONBUS_DEVICES_TS5700N8500_EMULATOR_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/devices/ts5700n8500.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/frame.hpp"

namespace motionbus {
namespace devices {
namespace ts5700n8500 {

/// A reply frame (size 0: the encoder stays silent).
struct reply {
  std::uint8_t bytes[tformat::max_response_size] = {};
  std::size_t size = 0;
  constexpr byte_view view() const noexcept { return byte_view(bytes, size); }
};

/// ALMC bits that latch until reset whatever the speed (OS, OF, OH, ME, BE; spec §6.5).
inline constexpr std::uint8_t latched_alarms = alarm_mask(latch_rule::latched);
/// ALMC bits that latch only below 100 min^-1 (CE case II; case I is non-latched).
inline constexpr std::uint8_t speed_latched_alarms = alarm_mask(latch_rule::by_speed);

/// What the UART or line decoder saw of a request's delimiter (stop) bits.
enum class request_line : std::uint8_t {
  ok = 0,
  delimiter_error = 1,  ///< a bad delimiter: the encoder answers with ID3 data, ca1 set
};

/// The emulated encoder's settings: the TS5700N8500's by default (ENID 0x11, 17 + 16 bits, an
/// over-heat threshold of 90 °C: 0xDA = 90 + 128, bit 7 enabling the check).
struct emulator_config {
  tformat::resolution res = ts5700n8500::resolution;
  std::uint8_t enid = ts5700n8500::enid;
  std::uint8_t overheat_threshold = overheat_factory;
};

class emulator {
 public:
  /// A default-constructed model (the default config) is all zeros: its settings are stored
  /// relative to the defaults, so that a `static` one lands in .bss, not .data.
  constexpr emulator() noexcept = default;
  constexpr explicit emulator(const emulator_config& cfg) noexcept
      : single_x_(static_cast<std::uint8_t>(cfg.res.single_turn_bits ^
                                            ts5700n8500::resolution.single_turn_bits)),
        multi_x_(static_cast<std::uint8_t>(cfg.res.multi_turn_bits ^
                                           ts5700n8500::resolution.multi_turn_bits)),
        enid_x_(static_cast<std::uint8_t>(cfg.enid ^ ts5700n8500::enid)),
        threshold_x_(static_cast<std::uint8_t>(cfg.overheat_threshold ^ overheat_factory)),
        loaded_threshold_x_(threshold_x_) {}

  // --- the physical world ------------------------------------------------------------------
  /// Sets the raw single-turn reading (before any ID8 zero offset) and the turn count.
  constexpr void set_position(std::uint32_t raw_single_turn, std::uint32_t turns) noexcept {
    raw_ = raw_single_turn & single_mask();
    turns_ = turns & multi_mask();
  }
  /// Rotates by `counts` single-turn steps (negative: the other way); turns follow, and the
  /// counter overflow flag OF latches when the turn count wraps.
  constexpr void rotate(std::int64_t counts) noexcept {
    const std::int64_t per_turn = std::int64_t{1} << single_turn_bits();
    const std::int64_t total = static_cast<std::int64_t>(raw_) + counts;
    std::int64_t turns = total / per_turn;
    std::int64_t raw = total % per_turn;
    if (raw < 0) {
      raw += per_turn;
      turns -= 1;
    }
    const std::int64_t new_turns = static_cast<std::int64_t>(turns_) + turns;
    const std::int64_t range = std::int64_t{1} << multi_turn_bits();
    if (new_turns < 0 || new_turns >= range) {
      latched_ =
          static_cast<std::uint8_t>(latched_ | static_cast<std::uint8_t>(tformat::almc_bit::of));
    }
    raw_ = static_cast<std::uint32_t>(raw);
    turns_ = static_cast<std::uint32_t>(((new_turns % range) + range) % range);
  }
  /// Sets whether the condition behind an alarm is present now. Latched alarms stay set after
  /// the condition goes until a reset; non-latched ones follow it; CE latches below 100 min^-1.
  constexpr void set_condition(tformat::almc_bit a, bool present) noexcept {
    const auto bit = static_cast<std::uint8_t>(a);
    conditions_ = present ? static_cast<std::uint8_t>(conditions_ | bit)
                          : static_cast<std::uint8_t>(conditions_ & ~bit);
    latch_present();
  }
  /// The shaft speed in min^-1, negative the other way (0 at construction). Its magnitude
  /// decides the case of a counting error (spec §6.5); resets count only at 0 (spec §10).
  constexpr void set_speed_rpm(std::int32_t rpm) noexcept {
    fast_ = speed_magnitude(rpm) >= counting_error_case_i_rpm;
    turning_ = rpm != 0;
    latch_present();
  }
  /// Substrate temperature in °C (page 7 address 5); may raise over-heat.
  constexpr void set_temperature(std::int8_t celsius) noexcept {
    temperature_x_ =
        static_cast<std::uint8_t>(static_cast<std::uint8_t>(celsius) ^ default_celsius);
    update_overheat();
  }

  // --- what the encoder reports ------------------------------------------------------------
  constexpr std::uint32_t abs() const noexcept { return (raw_ - offset_) & single_mask(); }
  constexpr std::uint32_t abm() const noexcept { return turns_; }
  constexpr std::uint8_t almc() const noexcept {
    return static_cast<std::uint8_t>(latched_ |
                                     (conditions_ & static_cast<std::uint8_t>(~latched_alarms)));
  }  // (a present CE shows through the second term in either case)
  constexpr std::uint8_t page() const noexcept { return page_; }
  constexpr std::uint8_t overheat_threshold() const noexcept { return threshold(); }
  /// EEPROM byte of a user page (0..5, address 0..126); 0 outside.
  constexpr std::uint8_t eeprom(std::uint8_t page, std::uint8_t address) const noexcept {
    return page < user_pages && address < page_size ? eeprom_[cell(page, address)] : 0U;
  }
  constexpr bool busy(std::uint32_t now_us) const noexcept {
    return busy_ && static_cast<std::int32_t>(now_us - busy_until_) < 0;
  }

  // --- the protocol --------------------------------------------------------------------------
  /// The reply to a received request frame (`frame`: the bytes up to the line's idle) at time
  /// `now_us` (a free-running microsecond clock; wrap-around is handled). `line`: what the
  /// UART or line decoder saw of the request's delimiter (stop) bits.
  constexpr reply respond(byte_view frame, std::uint32_t now_us,
                          request_line line = request_line::ok) noexcept {
    if (frame.empty() || !tformat::sync_ok(frame[0])) {
      return reply{};  // bad sync code: no reply (spec §8.4 No.1)
    }
    if (line == request_line::delimiter_error) {
      return abnormal(false, true);
    }
    const decode_result<tformat::request> d = tformat::decode_request(frame);
    if (d.is_failed()) {
      return abnormal(d.error() == errc::tformat_parity, false);
    }
    if (d.is_incomplete()) {
      return abnormal(false, false);  // EEPROM request cut short: its CRC is missing
    }
    const tformat::request& q = d.value();
    switch (q.id) {
      case tformat::data_id::eeprom_write: reset_count_ = 0; return eeprom_write(q, now_us);
      case tformat::data_id::eeprom_read: reset_count_ = 0; return eeprom_read(q, now_us);
      default: break;
    }
    // The reply carries the data of the moment the request arrived; a reset acts after it
    // (spec §10, note *).
    const reply out = data_reply(q.id, 0);
    count_reset(q.id, now_us);
    return out;
  }

 private:
  static constexpr std::uint8_t user_pages = 6;
  static constexpr std::uint8_t page_size = 127;

  static constexpr std::size_t cell(std::uint8_t page, std::uint8_t address) noexcept {
    return static_cast<std::size_t>(page) * page_size + address;
  }

  constexpr std::uint32_t single_mask() const noexcept {
    return single_turn_bits() >= 32U ? 0xFFFFFFFFU
                                     : ((std::uint32_t{1} << single_turn_bits()) - 1U);
  }
  constexpr std::uint32_t multi_mask() const noexcept {
    return multi_turn_bits() >= 32U ? 0xFFFFFFFFU : ((std::uint32_t{1} << multi_turn_bits()) - 1U);
  }

  constexpr void update_overheat() noexcept {
    const std::uint8_t t = threshold();
    const bool enabled = (t & 0x80U) != 0U;
    const int limit = static_cast<int>(t) - 128;
    set_condition(tformat::almc_bit::oh, enabled && temperature() > limit);
  }

  constexpr reply data_reply(tformat::data_id id, std::uint8_t extra_sf) const noexcept {
    tformat::response r;
    r.id = id;
    r.sf = static_cast<std::uint8_t>(tformat::status_field(almc()) | extra_sf);
    r.abs = abs();
    r.abm = abm();
    r.enid = static_cast<std::uint8_t>(enid_x_ ^ ts5700n8500::enid);
    r.almc = almc();
    reply out;
    out.size = tformat::encode_response(r, mutable_byte_view(out.bytes, tformat::max_response_size))
                   .value_or(0);
    return out;
  }

  constexpr reply abnormal(bool ca0, bool ca1) noexcept {
    reset_count_ = 0;
    return data_reply(
        tformat::data_id::read_all,
        static_cast<std::uint8_t>((ca0 ? tformat::sf::ca0 : 0U) | (ca1 ? tformat::sf::ca1 : 0U)));
  }

  constexpr reply eeprom_reply(tformat::data_id id, std::uint8_t address, bool busy,
                               std::uint8_t edf) const noexcept {
    tformat::response r;
    r.id = id;
    r.address = address;
    r.busy = busy;
    r.edf = edf;
    reply out;
    out.size = tformat::encode_response(r, mutable_byte_view(out.bytes, tformat::max_response_size))
                   .value_or(0);
    return out;
  }

  constexpr void start_busy(std::uint32_t now_us) noexcept {
    busy_ = true;
    busy_until_ = now_us + eeprom_write_us;
  }

  constexpr reply eeprom_write(const tformat::request& q, std::uint32_t now_us) noexcept {
    if (busy(now_us)) {
      return eeprom_reply(q.id, q.address, true, 0);
    }
    if (q.address == tformat::page_select_address) {
      if (q.edf >= user_pages && q.edf != 7U) {
        return abnormal(false, false);
      }
      page_ = q.edf;
      load_page();
    } else if (page_ < user_pages) {
      eeprom_[cell(page_, q.address)] = q.edf;
      // coverage-branch: page_ is 0..5 or 7 (the page select refuses 6 and above 7): 7 here
    } else if (page_ == 7U && q.address == 4U) {
      threshold_x_ = static_cast<std::uint8_t>(q.edf ^ overheat_factory);
      update_overheat();
    } else {
      return abnormal(false, false);  // closed address
    }
    start_busy(now_us);
    return eeprom_reply(q.id, q.address, false, q.edf);
  }

  constexpr reply eeprom_read(const tformat::request& q, std::uint32_t now_us) noexcept {
    if (busy(now_us)) {
      return eeprom_reply(q.id, q.address, true, 0);
    }
    std::uint8_t value = 0;
    if (q.address == tformat::page_select_address) {
      value = page_;
    } else if (page_ < user_pages) {
      value = loaded_[q.address];
      // coverage-branch: page_ is 0..5 or 7 (the page select refuses 6 and above 7): 7 here
    } else if (page_ == 7U && q.address == 4U) {
      value = static_cast<std::uint8_t>(loaded_threshold_x_ ^ overheat_factory);
      // coverage-branch: page_ is 7 here, as above
    } else if (page_ == 7U && q.address == 5U) {
      value = static_cast<std::uint8_t>(temperature());
    } else {
      return abnormal(false, false);
    }
    return eeprom_reply(q.id, q.address, false, value);
  }

  // Specifying a page makes what was written to it readable (see the header).
  constexpr void load_page() noexcept {
    if (page_ < user_pages) {
      for (std::uint8_t a = 0; a < page_size; ++a) {
        loaded_[a] = eeprom_[cell(page_, a)];
      }
    } else {
      loaded_threshold_x_ = threshold_x_;
    }
  }

  constexpr void count_reset(tformat::data_id id, std::uint32_t now_us) noexcept {
    const bool is_reset = id == tformat::data_id::reset_errors ||
                          id == tformat::data_id::reset_single_turn ||
                          id == tformat::data_id::reset_multi_turn;
    if (!is_reset) {
      reset_count_ = 0;
      return;
    }
    if (turning_) {
      reset_count_ = 0;  // a reset request counts only with the shaft still (header, spec §10)
      return;
    }
    if (reset_count_ > 0U && id == reset_id_) {
      if (now_us - last_reset_us_ < reset_interval_us) {
        return;  // too soon: this request does not count
      }
      ++reset_count_;
    } else {
      reset_id_ = id;
      reset_count_ = 1;
    }
    last_reset_us_ = now_us;
    if (reset_count_ < reset_repeat) {
      return;
    }
    reset_count_ = 0;
    if (id == tformat::data_id::reset_single_turn) {
      offset_ = raw_;
      start_busy(now_us);  // the zero point is written to EEPROM (spec §10)
      return;
    }
    if (id == tformat::data_id::reset_multi_turn) {
      turns_ = 0;
    }
    latched_ = static_cast<std::uint8_t>(conditions_ & latching());  // reset what is gone
  }

  // The alarms a present condition latches now: CE only below 100 min^-1 (case II).
  constexpr std::uint8_t latching() const noexcept {
    return fast_ ? latched_alarms
                 : static_cast<std::uint8_t>(latched_alarms | speed_latched_alarms);
  }
  constexpr void latch_present() noexcept {
    latched_ = static_cast<std::uint8_t>(latched_ | (conditions_ & latching()));
  }

  static constexpr std::uint8_t default_celsius = 25;
  constexpr unsigned single_turn_bits() const noexcept {
    return static_cast<std::uint8_t>(single_x_ ^ ts5700n8500::resolution.single_turn_bits);
  }
  constexpr unsigned multi_turn_bits() const noexcept {
    return static_cast<std::uint8_t>(multi_x_ ^ ts5700n8500::resolution.multi_turn_bits);
  }
  constexpr std::uint8_t threshold() const noexcept {
    return static_cast<std::uint8_t>(threshold_x_ ^ overheat_factory);
  }
  constexpr int temperature() const noexcept {
    return static_cast<std::int8_t>(static_cast<std::uint8_t>(temperature_x_ ^ default_celsius));
  }

  // Settings stored as XOR their defaults: a default model is all zeros.
  std::uint8_t single_x_ = 0;
  std::uint8_t multi_x_ = 0;
  std::uint8_t enid_x_ = 0;
  std::uint8_t threshold_x_ = 0;
  std::uint8_t loaded_threshold_x_ = 0;
  std::uint8_t temperature_x_ = 0;  // 25 °C
  std::uint32_t raw_ = 0;
  std::uint32_t offset_ = 0;
  std::uint32_t turns_ = 0;
  std::uint8_t conditions_ = 0;
  std::uint8_t latched_ = 0;
  std::uint8_t page_ = 0;
  std::uint8_t eeprom_[user_pages * page_size] = {};
  std::uint8_t loaded_[page_size] = {};  // the current page as last specified
  bool busy_ = false;
  bool fast_ = false;     // shaft at 100 min^-1 or more
  bool turning_ = false;  // shaft speed not 0: resets do not count
  std::uint32_t busy_until_ = 0;
  tformat::data_id reset_id_ = tformat::data_id::read_abs;  // meaningful while reset_count_ > 0
  unsigned reset_count_ = 0;
  std::uint32_t last_reset_us_ = 0;
};

}  // namespace ts5700n8500
}  // namespace devices
}  // namespace motionbus

#endif  // MOTIONBUS_DEVICES_TS5700N8500_EMULATOR_HPP
