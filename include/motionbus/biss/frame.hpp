// motionbus — BiSS-C cyclic sensor data frames: layouts and decoded values.
//
// On SL, as a master samples it from its first clock (ABSYS document Figure 1; docs/biss.md §1,
// §5):
//
//   idle 1…1 | Ack 0…0 | Start 1 | CDS | slave 1: data, nE, nW, CRC | slave 2: … | timeout 0…
//
// The idle samples before the Ack are the line delay in whole bits (the clocks before the
// slave's answer reaches the master: a master measures it from its first clock to the Ack's
// falling edge); the Ack lasts at least one clock, more when the slave asks for processing
// time (ABSYS document, Table 1 note 2: the slave "can request this by delaying the start
// bit"). CDS is the slave's control-data bit and may be 1. Data goes MSB first, multi-turn bits
// before single-turn bits before alignment bits; nE and nW are active low; each slave's CRC covers
// its data, nE and nW (not Ack, Start or CDS), MSB first, and is sent inverted (the usual BiSS
// choice, a parameter here). A chain of slaves shares one Ack, Start and CDS (the CDS is the first
// bit after the Start bit; the chain addresses slaves by ID during control communication), then
// carries each slave's fields in chain order, slave 1 (nearest the master) first.
#ifndef MOTIONBUS_BISS_FRAME_HPP
#define MOTIONBUS_BISS_FRAME_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/config.hpp"
#include "motionbus/core/crc.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"

namespace motionbus {
namespace biss {

/// The CRC protecting one slave's sensor data: non-reflected, MSB first, over data + nE + nW.
/// `poly` is given without its x^width term (x^6 + x + 1, written 0x43 in BiSS documents, is
/// width 6, poly 0x03); crc_from_biss_notation converts. Width 0 means no CRC.
struct crc_format {
  unsigned width = 6;
  std::uint32_t poly = 0x03;
  std::uint32_t start = 0;
  bool inverted = true;  ///< sent inverted on the wire (BiSS default)

  /// The Williams-model parameters of the value as sent on the wire.
  constexpr crc_parameters parameters() const noexcept {
    const std::uint32_t mask = width >= 32U ? 0xFFFFFFFFU : ((std::uint32_t{1} << width) - 1U);
    return {width, poly, start, false, false, inverted ? mask : 0U};
  }
  friend constexpr bool operator==(const crc_format& a, const crc_format& b) noexcept {
    return a.width == b.width && a.poly == b.poly && a.start == b.start && a.inverted == b.inverted;
  }
  friend constexpr bool operator!=(const crc_format& a, const crc_format& b) noexcept {
    return !(a == b);
  }
};

/// How a CRC goes on the wire: inverted (the BiSS default) or as computed.
enum class crc_output : std::uint8_t { inverted = 0, plain = 1 };

/// A crc_format from the BiSS notation, which includes the x^width term (0x43 = x^6 + x + 1;
/// 0x13 = x^4 + x + 1; 0x25 = x^5 + x^2 + 1; 0x97 = x^7 + x^4 + x^2 + x + 1): the width is the
/// position of the highest set bit. 0 or 1 gives width 0 (no CRC).
constexpr crc_format crc_from_biss_notation(std::uint32_t poly, std::uint32_t start = 0,
                                            crc_output output = crc_output::inverted) noexcept {
  const bool inverted = output == crc_output::inverted;
  unsigned width = 0;
  for (unsigned b = 31; b > 0; --b) {
    if (((poly >> b) & 1U) != 0U) {
      width = b;
      break;
    }
  }
  const std::uint32_t mask = width == 0U ? 0U : ((std::uint32_t{1} << width) - 1U);
  return {width, poly & mask, start, inverted};
}

/// A polynomial as stored in a BiSS electronic data sheet: bits (n:1) of the BiSS notation, the
/// x^0 term implied (CPOLY 0x21 is 0x43).
constexpr crc_format crc_from_eds(std::uint32_t cpoly, std::uint32_t start = 0) noexcept {
  return crc_from_biss_notation((cpoly << 1U) | 1U, start);
}

/// The CRC6 of BiSS sensor data (x^6 + x + 1, start 0, inverted): AMO ABSYS and most encoders.
inline constexpr crc_format crc6_43{6, 0x03, 0, true};

/// Limits: data fields up to 64 bits; CRCs up to 16 bits (BiSS uses 4..16).
inline constexpr unsigned max_data_bits = 64;
inline constexpr unsigned max_crc_bits = 16;
/// Chains of up to 8 slaves (IDs 0..7 in control communication).
inline constexpr std::size_t max_chain = 8;

/// The fields one slave sends. Default: the AMO ABSYS layout (32-bit position, nE, nW, CRC6
/// 0x43 inverted: 40 bits after the CDS bit, frame_bits(); ABSYS interface text §1, Table 1).
struct slave_layout {
  unsigned multi_turn_bits = 0;
  unsigned single_turn_bits = 32;
  unsigned alignment_bits = 0;  ///< low-order filler bits after the single-turn value
  bool has_error = true;        ///< nE present
  bool has_warning = true;      ///< nW present
  crc_format crc = crc6_43;

  // inline (the accessors and validate()): a decoder called with a constant layout folds them
  // away (and its CRC to byte steps), whatever else the program calls them from.
  MOTIONBUS_INLINE constexpr unsigned data_bits() const noexcept {
    return multi_turn_bits + single_turn_bits + alignment_bits;
  }
  // inline: as data_bits().
  MOTIONBUS_INLINE constexpr unsigned status_bits() const noexcept {
    return (has_error ? 1U : 0U) + (has_warning ? 1U : 0U);
  }
  /// Bits this slave puts on SL after the CDS bit (data, nE, nW, CRC).
  // inline: as data_bits().
  MOTIONBUS_INLINE constexpr unsigned frame_bits() const noexcept {
    return data_bits() + status_bits() + crc.width;
  }
  /// ok, or errc::biss_layout: 1..64 data bits, a CRC of at most 16 bits whose polynomial,
  /// start value fit its width (the widths are checked one by one first: no overflow).
  // inline: as data_bits().
  MOTIONBUS_INLINE constexpr errc validate() const noexcept {
    if (multi_turn_bits > max_data_bits || single_turn_bits > max_data_bits ||
        alignment_bits > max_data_bits || data_bits() == 0U || data_bits() > max_data_bits ||
        crc.width > max_crc_bits) {
      return errc::biss_layout;
    }
    const std::uint32_t mask = (std::uint32_t{1} << crc.width) - 1U;
    if ((crc.poly & ~mask) != 0U || (crc.start & ~mask) != 0U) {
      return errc::biss_layout;
    }
    return errc::ok;
  }
};

/// The AMO ABSYS layout (also slave_layout{}).
inline constexpr slave_layout absys_layout{};

/// One slave's decoded sensor data.
struct slave_data {
  std::uint64_t data = 0;         ///< the whole data field as sent (all its bits)
  std::uint64_t multi_turn = 0;   ///< the multi-turn bits
  std::uint64_t single_turn = 0;  ///< the single-turn bits (alignment bits removed)
  bool ne = true;                 ///< nE line level: 0 = error active (1 when the layout has no nE)
  bool nw = true;         ///< nW line level: 0 = warning active (1 when the layout has no nW)
  std::uint32_t crc = 0;  ///< the CRC as received (wire value)
  std::uint32_t crc_computed = 0;  ///< the wire value the received data calls for

  constexpr bool crc_ok() const noexcept { return crc == crc_computed; }
  constexpr bool error() const noexcept { return !ne; }
  constexpr bool warning() const noexcept { return !nw; }
};

/// A decoded frame of a chain of at most N slaves: where it lies in the capture, what the
/// chain shares, and each slave's data in chain order (size() of them, slave 1 first; the
/// rest value-initialised). decode_frame returns chain_frame<1> for one layout and
/// chain_frame<max_chain> for a chain. (The end of the frame, just past the last CRC, is the
/// decode result's consumed_bits().)
namespace detail {
// The number of slaves a chain_frame holds: stored for a chain, the constant 1 for one slave
// (one store fewer on the single-slave path, which the meter counts).
template <std::size_t N>
struct slave_count {
  std::size_t count = 0;  ///< slaves decoded: the chain's length
};
template <>
struct slave_count<1> {
  static constexpr std::size_t count = 1;
};
}  // namespace detail

template <std::size_t N>
struct chain_frame : detail::slave_count<N> {
  static_assert(N >= 1U && N <= max_chain, "a BiSS chain has 1 to max_chain slaves");
  /// The line delay in whole bits: the idle samples before the Ack, which is the index of
  /// the first Ack bit.
  std::size_t line_delay = 0;
  /// Index of the Start bit: line delay + Ack length.
  std::size_t start = 0;
  bool cds = false;      ///< the CDS bit
  slave_data slaves[N];  ///< each default-initialised (slave_data's own initialisers)

  /// Clocks of Ack (at least 1; more for the slave's processing time).
  constexpr std::size_t ack_bits() const noexcept { return start - line_delay; }
  /// Slaves decoded: the chain's length (`count`).
  constexpr std::size_t size() const noexcept { return this->count; }
  constexpr const slave_data& operator[](std::size_t i) const noexcept { return slaves[i]; }
  constexpr const slave_data* begin() const noexcept { return slaves; }
  constexpr const slave_data* end() const noexcept { return slaves + this->count; }
};

/// The frame of one slave (decode_frame with a single layout): its data is `slaves[0]`.
using single_frame = chain_frame<1>;

/// What decode_frame returns: counted in bits of the capture (consumed_bits(), needed_bits()).
template <std::size_t N>
using frame_result = decode_result<chain_frame<N>, input_unit::bits>;

}  // namespace biss
}  // namespace motionbus

#endif  // MOTIONBUS_BISS_FRAME_HPP
