// motionbus — the BiSS electronic data sheet (EDS): the common part and the standard encoder
// profile BP3, each one 64-byte register bank read through control communication. Layouts as
// the AMO ABSYS interface text §2.8 and §2.9 list them; multi-byte values are big-endian.
//
// The checksum in byte 0x3F of each bank is not specified by the vendor text. This library
// writes, and optionally verifies, the low byte of the sum of bytes 0x00..0x3E (an assumption,
// stated here and tested; verification is off by default so that a device using another rule
// still parses).
#ifndef MOTIONBUS_BISS_EDS_HPP
#define MOTIONBUS_BISS_EDS_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "motionbus/biss/frame.hpp"
#include "motionbus/core/bytes.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {
namespace biss {

/// Bytes per register bank (addresses 0x00..0x3F of the bank window).
inline constexpr std::size_t bank_size = 64;

/// EDS common part (bank 0x80 on ABSYS), §2.8.
struct eds_common {
  std::uint8_t version = 0x01;          ///< 0x00
  std::uint8_t length = 0x02;           ///< 0x01: banks of the whole EDS
  std::uint8_t user_bank_start = 0x84;  ///< 0x02
  std::uint8_t user_bank_end = 0x84;    ///< 0x03
  std::uint8_t channels = 0x01;         ///< 0x10: data channels in the device
  std::uint8_t validity = 0x01;         ///< 0x11: area of validity of this EDS
  std::uint8_t location = 0x80;         ///< 0x12: memory location of this EDS
  std::uint8_t profile_bank = 0x81;     ///< 0x14: bank of channel 1's content description (BP3)
  std::uint8_t data_length = 0x20;      ///< 0x15: channel 1 data length in bits
  std::uint8_t data_format = 0x00;      ///< 0x16
  std::uint8_t crc_poly = 0x21;         ///< 0x17: channel 1 CRC polynomial, bits (8:1)

  friend constexpr bool operator==(const eds_common& a, const eds_common& b) noexcept {
    return a.version == b.version && a.length == b.length &&
           a.user_bank_start == b.user_bank_start && a.user_bank_end == b.user_bank_end &&
           a.channels == b.channels && a.validity == b.validity && a.location == b.location &&
           a.profile_bank == b.profile_bank && a.data_length == b.data_length &&
           a.data_format == b.data_format && a.crc_poly == b.crc_poly;
  }
};

enum class encoder_type : std::uint8_t { rotary = 0x00, linear = 0x01 };

/// Standard encoder profile BP3 (bank 0x81 on ABSYS), §2.9.
struct bp3_profile {
  std::uint8_t version = 0x03;               ///< 0x00 BP_VER (0x02 and 0x03 are described)
  std::uint8_t length = 0x01;                ///< 0x01 BP_LEN, banks
  std::uint16_t profile_id = 0x6320;         ///< 0x02..0x03 BP_ID
  std::uint8_t feedback1 = 0x01;             ///< 0x04 FB1 (error = 1, warning = 2)
  std::uint8_t feedback2 = 0x02;             ///< 0x05 FB2
  std::uint8_t power_on_delay_ms = 0xFF;     ///< 0x06 PON_DLY
  encoder_type type = encoder_type::rotary;  ///< 0x08 EN_TYP
  std::uint8_t positions = 0x01;             ///< 0x09 POS_NUM
  std::uint8_t mt_length = 0;                ///< 0x0A MT_LEN, bits
  std::uint8_t mt_format = 0;                ///< 0x0B
  std::uint8_t coarse_length = 0;            ///< 0x0C CO_LEN
  std::uint8_t coarse_format = 0;            ///< 0x0D
  std::uint8_t fine_length = 0x20;           ///< 0x0E FI_LEN
  std::uint8_t fine_format = 0;              ///< 0x0F
  std::uint32_t mt_count = 0;                ///< 0x10..0x13 MT_CNT
  std::uint32_t sip_count = 0;               ///< 0x14..0x17 SIP_CNT: nm (linear) / periods per rev
  std::uint32_t sip_resolution = 0;          ///< 0x18..0x1B SIP_RES: 0..20
  std::uint32_t crc_poly = 0x21;             ///< 0x1C..0x1F CPOLY, bits (31:1)
  std::uint32_t crc_start = 0;               ///< 0x20..0x23 CSTART

  /// Rotary: pulses per revolution = SIP_CNT x 2^SIP_RES (0 when it does not fit 64 bits).
  constexpr std::uint64_t pulses_per_revolution() const noexcept {
    return sip_resolution > 31U ? 0U : (static_cast<std::uint64_t>(sip_count) << sip_resolution);
  }
  /// Linear: one LSB in nanometres = SIP_CNT / 2^SIP_RES.
  constexpr double lsb_nm() const noexcept {
    return sip_resolution > 31U ? 0.0
                                : static_cast<double>(sip_count) /
                                      static_cast<double>(std::uint64_t{1} << sip_resolution);
  }
  /// The sensor-data layout this profile announces (multi-turn + coarse + fine data bits, nE,
  /// nW, the CRC from CPOLY and CSTART, inverted).
  constexpr slave_layout layout() const noexcept {
    slave_layout l;
    l.multi_turn_bits = mt_length;
    l.single_turn_bits = static_cast<unsigned>(coarse_length) + fine_length;
    l.alignment_bits = 0;
    l.crc = crc_from_eds(crc_poly, crc_start);
    return l;
  }

  friend constexpr bool operator==(const bp3_profile& a, const bp3_profile& b) noexcept {
    return a.version == b.version && a.length == b.length && a.profile_id == b.profile_id &&
           a.feedback1 == b.feedback1 && a.feedback2 == b.feedback2 &&
           a.power_on_delay_ms == b.power_on_delay_ms && a.type == b.type &&
           a.positions == b.positions && a.mt_length == b.mt_length && a.mt_format == b.mt_format &&
           a.coarse_length == b.coarse_length && a.coarse_format == b.coarse_format &&
           a.fine_length == b.fine_length && a.fine_format == b.fine_format &&
           a.mt_count == b.mt_count && a.sip_count == b.sip_count &&
           a.sip_resolution == b.sip_resolution && a.crc_poly == b.crc_poly &&
           a.crc_start == b.crc_start;
  }
};

/// This library's bank checksum: the low byte of the sum of bytes 0x00..0x3E.
constexpr std::uint8_t bank_checksum(byte_view bank) noexcept {
  unsigned sum = 0;
  for (std::size_t i = 0; i + 1U < bank_size && i < bank.size(); ++i) {
    sum += bank[i];
  }
  return static_cast<std::uint8_t>(sum & 0xFFU);
}

struct eds_options {
  bool verify_checksum = false;  ///< see the file comment
};

namespace detail {

// A bank is written whole: zeros where nothing is defined, the checksum last.
constexpr void clear_bank(mutable_byte_view b) noexcept {
  for (std::size_t i = 0; i < bank_size; ++i) {
    b[i] = 0;
  }
}
constexpr void seal_bank(mutable_byte_view b) noexcept {
  b[bank_size - 1U] = bank_checksum(byte_view(b.data(), b.size()));
}

// Each bank's fields, offset and member, stated once: decoding reads them all through
// field_reader, encoding writes them all through field_writer (big-endian, as wide as the
// member). `E` is the struct, const when encoding.
template <class E, class F>
constexpr void common_fields(E& e, F&& field) noexcept {
  field(0x00, e.version);
  field(0x01, e.length);
  field(0x02, e.user_bank_start);
  field(0x03, e.user_bank_end);
  field(0x10, e.channels);
  field(0x11, e.validity);
  field(0x12, e.location);
  field(0x14, e.profile_bank);
  field(0x15, e.data_length);
  field(0x16, e.data_format);
  field(0x17, e.crc_poly);
}
template <class P, class F>
constexpr void bp3_fields(P& p, F&& field) noexcept {
  field(0x00, p.version);
  field(0x01, p.length);
  field(0x02, p.profile_id);
  field(0x04, p.feedback1);
  field(0x05, p.feedback2);
  field(0x06, p.power_on_delay_ms);
  field(0x08, p.type);
  field(0x09, p.positions);
  field(0x0A, p.mt_length);
  field(0x0B, p.mt_format);
  field(0x0C, p.coarse_length);
  field(0x0D, p.coarse_format);
  field(0x0E, p.fine_length);
  field(0x0F, p.fine_format);
  field(0x10, p.mt_count);
  field(0x14, p.sip_count);
  field(0x18, p.sip_resolution);
  field(0x1C, p.crc_poly);
  field(0x20, p.crc_start);
}

struct field_reader {
  byte_view bank;
  template <class T>
  constexpr void operator()(std::size_t at, T& v) const noexcept {
    v = static_cast<T>(load_be<sizeof(T)>(bank, at));
  }
};
struct field_writer {
  mutable_byte_view bank;
  template <class T>
  constexpr void operator()(std::size_t at, const T& v) const noexcept {
    std::uint32_t x = 0;
    if constexpr (std::is_enum<T>::value) {
      x = static_cast<std::underlying_type_t<T>>(v);
    } else {
      x = v;
    }
    for (std::size_t k = 0; k < sizeof(T); ++k) {
      bank[at + k] = static_cast<std::uint8_t>((x >> (8U * (sizeof(T) - 1U - k))) & 0xFFU);
    }
  }
};

}  // namespace detail

namespace detail {
// A bank parsed by `fields` into a T, then `valid(T)`: incomplete below 64 bytes, biss_eds
// for a value `valid` refuses or (when verified) a checksum that does not match, with the
// checksum computed as expected() and the one in 0x3F as received().
template <class T, class Fields, class Valid>
constexpr decode_result<T> decode_bank(byte_view bank, const eds_options& opt, Fields fields,
                                       Valid valid) noexcept {
  if (bank.size() < bank_size) {
    return need_input{bank_size - bank.size()};
  }
  T v;
  fields(v, field_reader{bank});
  if (!valid(v)) {
    return decode_failure{errc::biss_eds, bank_size};
  }
  const std::uint8_t sum = bank_checksum(bank);
  if (opt.verify_checksum && bank[0x3F] != sum) {
    return decode_failure{errc::biss_eds, bank_size, sum, bank[0x3F]};
  }
  return decode_result<T>::complete(v, bank_size);
}
}  // namespace detail

/// Parses the common part from one 64-byte bank. Complete: consumed() = 64. Incomplete: fewer
/// than 64 bytes (needed() the rest). Failed: biss_eds (EDS length 0, no data channel, data
/// length 0 or above 64 bits, a zero CRC polynomial, or a bad checksum when verified: the
/// computed and stored checksums as expected() and received()).
constexpr decode_result<eds_common> decode_eds_common(byte_view bank,
                                                      const eds_options& opt = {}) noexcept {
  return detail::decode_bank<eds_common>(
      bank, opt, [](eds_common& v, auto r) { detail::common_fields(v, r); },
      [](const eds_common& e) {
        return e.length != 0U && e.channels != 0U && e.data_length != 0U &&
               e.data_length <= max_data_bits && e.crc_poly != 0U;
      });
}

/// Parses the BP3 profile from one 64-byte bank. Complete, incomplete and a bad checksum as
/// decode_eds_common; biss_eds also for a version other than 2 or 3, an encoder type other
/// than rotary/linear, SIP_RES above 20, data lengths summing to 0 or above 64 bits, a CRC
/// polynomial wider than 16 bits or zero, a start value that does not fit it.
constexpr decode_result<bp3_profile> decode_bp3(byte_view bank,
                                                const eds_options& opt = {}) noexcept {
  return detail::decode_bank<bp3_profile>(
      bank, opt, [](bp3_profile& v, auto r) { detail::bp3_fields(v, r); },
      [bank](const bp3_profile& p) {
        const unsigned bits = static_cast<unsigned>(p.mt_length) + p.coarse_length + p.fine_length;
        return bank[0x08] <= 0x01U &&  // EN_TYP: rotary or linear
               (p.version == 0x02U || p.version == 0x03U) && p.sip_resolution <= 20U &&
               bits != 0U && bits <= max_data_bits && p.crc_poly != 0U &&
               p.crc_poly < (1U << max_crc_bits) &&
               (p.crc_start >> crc_from_eds(p.crc_poly, 0).width) == 0U;
      });
}

namespace detail {
// A bank written whole: zeros where nothing is defined, the fields, the checksum last.
template <class T, class Fields>
constexpr errc encode_bank(const T& value, Fields fields, mutable_byte_view bank) noexcept {
  if (bank.size() < bank_size) {
    return errc::buffer_too_small;
  }
  clear_bank(bank);
  fields(value, field_writer{bank});
  seal_bank(bank);
  return errc::ok;
}
}  // namespace detail

/// Writes the common part into a 64-byte bank (undefined bytes 0, checksum in 0x3F).
constexpr errc encode_eds_common(const eds_common& e, mutable_byte_view bank) noexcept {
  return detail::encode_bank(
      e, [](const eds_common& v, auto w) { detail::common_fields(v, w); }, bank);
}

/// Writes the BP3 profile into a 64-byte bank (undefined bytes 0, checksum in 0x3F).
constexpr errc encode_bp3(const bp3_profile& p, mutable_byte_view bank) noexcept {
  return detail::encode_bank(
      p, [](const bp3_profile& v, auto w) { detail::bp3_fields(v, w); }, bank);
}

}  // namespace biss
}  // namespace motionbus

#endif  // MOTIONBUS_BISS_EDS_HPP
