// motionbus — the CRC engine shared by every protocol.
//
// A CRC is described by the Williams ("Rocksoft") model: width (1..32), polynomial without its
// top term, initial register value, input/output reflection and final XOR. The engine works on
// bytes and on any number of bits (BiSS frames are not byte multiples), one-shot or
// incrementally, and is entirely constexpr. Lookup tables (256 or 16 entries) are built at
// compile time into constexpr arrays, i.e. read-only storage; `crc_table_size::bitwise` uses
// no table at all for the tightest flash budgets. One table serves every CRC sharing width,
// polynomial and reflection.
//
// Bit order: `update_bits(v, n)` feeds the low n bits of v in the CRC's own order — the most
// significant of them first for a non-reflected CRC (refin = false), the least significant
// first for a reflected one — so `update(byte)` equals `update_bits(byte, 8)`.
#ifndef MOTIONBUS_CORE_CRC_HPP
#define MOTIONBUS_CORE_CRC_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "motionbus/core/bits.hpp"
#include "motionbus/core/bytes.hpp"
#include "motionbus/core/config.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {

/// Table size used by a CRC engine: 256 entries (a byte at a time), 16 entries (a nibble at a
/// time) or none (a bit at a time).
/// `slice4` / `slice8` (4 or 8 x 256 entries) process four or eight bytes per step; they apply
/// to reflected CRCs of width 8..32 (CRC-16/MODBUS, CRC-32) and to the bit fields of MSB-first
/// CRCs of width 8 or less (`update_bits` on up to 32 / 64 bits: a BiSS frame's CRC6 in one
/// step), and fall back to the 256-entry table otherwise. Meant for hosts and large MCUs,
/// where flash is no concern.
enum class crc_table_size : std::uint16_t {
  bitwise = 0,
  nibble = 16,
  byte = 256,
  slice4 = 1024,
  slice8 = 2048
};

/// The table size used when none is given (configurable with MOTIONBUS_CRC_DEFAULT_TABLE).
inline constexpr crc_table_size default_crc_table =
    static_cast<crc_table_size>(MOTIONBUS_CRC_DEFAULT_TABLE);

namespace detail {

template <unsigned Bits>
using uint_least_bits_t =
    std::conditional_t<(Bits <= 8U), std::uint8_t,
                       std::conditional_t<(Bits <= 16U), std::uint16_t, std::uint32_t>>;

/// Arm cores whose halfword loads may be unaligned (Cortex-M3, M4, M7; A-profile), where the
/// byte-table CRC loads two bytes a step (crc::feed_pairs).
#if MOTIONBUS_DIRECT_LOADS && defined(__ARM_FEATURE_UNALIGNED)
inline constexpr bool unaligned_halfwords = true;
#else
inline constexpr bool unaligned_halfwords = false;
#endif

/// x86-64 hosts, where a reflected 16-bit CRC's byte table is read as two byte tables (its
/// entries' low and high bytes, the same table's bytes) by the range walk (crc::feed_split).
#if defined(__x86_64__)
inline constexpr bool split_halfword_table = true;
#else
inline constexpr bool split_halfword_table = false;
#endif

constexpr std::uint32_t low_mask32(unsigned width) noexcept {
  return width >= 32U ? 0xFFFFFFFFU : ((std::uint32_t{1} << width) - 1U);
}

constexpr std::uint32_t reflect32(std::uint32_t value, unsigned width) noexcept {
  return static_cast<std::uint32_t>(reverse_bits(value, width));
}

/// One bit into a normal (MSB-first) register of `reg_bits` bits whose CRC sits in the top
/// bits, `poly` aligned the same way. Shared by the compile-time kernel and dynamic_crc.
constexpr std::uint32_t crc_step_normal(std::uint32_t reg, std::uint32_t bit, std::uint32_t poly,
                                        unsigned reg_bits) noexcept {
  const bool feedback = (((reg >> (reg_bits - 1U)) ^ bit) & 1U) != 0U;
  reg = (reg << 1U) & low_mask32(reg_bits);
  return feedback ? (reg ^ poly) : reg;
}

/// One bit into a reflected (LSB-first) register, `poly` reflected.
constexpr std::uint32_t crc_step_reflected(std::uint32_t reg, std::uint32_t bit,
                                           std::uint32_t poly) noexcept {
  const bool feedback = ((reg ^ bit) & 1U) != 0U;
  reg >>= 1U;
  return feedback ? (reg ^ poly) : reg;
}

/// crc_step_reflected with bit 0 run backwards: the register before the step from the one
/// after it. The step's feedback shows in the top bit: `poly` reflected has it set (every CRC
/// polynomial has its x^0 term), a plain shift never does.
constexpr std::uint32_t crc_unstep_reflected(std::uint32_t reg, std::uint32_t poly,
                                             unsigned reg_bits) noexcept {
  const std::uint32_t feedback = (reg >> (reg_bits - 1U)) & 1U;
  return (((feedback != 0U ? reg ^ poly : reg) << 1U) | feedback) & low_mask32(reg_bits);
}

/// The register's starting value for `init` (register layout as in crc_kernel).
constexpr std::uint32_t crc_initial_register(std::uint32_t init, unsigned width, unsigned align,
                                             bool refin) noexcept {
  return refin ? reflect32(init, width) : (init << align);
}

/// The CRC value held by a register: reflection and final XOR applied.
constexpr std::uint32_t crc_register_value(std::uint32_t reg, unsigned width, unsigned align,
                                           bool refin, bool refout, std::uint32_t xorout) noexcept {
  std::uint32_t v = 0;
  if (refin) {
    v = refout ? reg : reflect32(reg, width);
  } else {
    const std::uint32_t r = reg >> align;
    v = refout ? reflect32(r, width) : r;
  }
  return (v ^ xorout) & low_mask32(width);
}

/// The register arithmetic of one polynomial in one direction.
///  Reflected: the register holds the CRC reflected, LSB-aligned; bits leave at bit 0.
///  Normal:    the register is reg_bits = max(width, 8) wide with the CRC in its top `width`
///             bits, so that byte and nibble steps work for widths below 8 as well.
template <unsigned Width, std::uint32_t Poly, bool Reflected>
struct crc_kernel {
  static_assert(Width >= 1U && Width <= 32U, "CRC width must be 1..32");
  static_assert((Poly & ~low_mask32(Width)) == 0U,
                "CRC polynomial must be given without its x^width term and fit the width");

  // A normal CRC narrower than 8 bits runs in an 8-bit register, its value aligned at the top.
  static constexpr unsigned register_width() noexcept {
    if (Reflected || Width >= 8U) {
      return Width;
    }
    return 8U;
  }
  static constexpr unsigned reg_bits = register_width();
  static constexpr unsigned align = reg_bits - Width;  // 0 when reflected
  static constexpr std::uint32_t reg_mask = low_mask32(reg_bits);
  static constexpr std::uint32_t poly = Reflected ? reflect32(Poly, Width) : (Poly << align);

  /// Feeds one bit (0/1).
  static constexpr std::uint32_t step_bit(std::uint32_t reg, std::uint32_t bit) noexcept {
    if constexpr (Reflected) {
      return crc_step_reflected(reg, bit, poly);
    } else {
      return crc_step_normal(reg, bit, poly, reg_bits);
    }
  }

  /// Table of the register change caused by each `ChunkBits`-bit chunk.
  template <unsigned ChunkBits>
  static constexpr std::array<uint_least_bits_t<reg_bits>, (1U << ChunkBits)>
  make_table() noexcept {
    std::array<uint_least_bits_t<reg_bits>, (1U << ChunkBits)> t{};
    for (std::uint32_t i = 0; i < (1U << ChunkBits); ++i) {
      std::uint32_t reg = Reflected ? i : (i << (reg_bits - ChunkBits));
      for (unsigned b = 0; b < ChunkBits; ++b) {
        reg = step_bit(reg, 0U);
      }
      t[i] = static_cast<uint_least_bits_t<reg_bits>>(reg);
    }
    return t;
  }

  /// True when every table entry equals its index (x^8 + 1 at width 8, the T-format CRC):
  /// a chunk step is then a plain XOR and the table is never referenced.
  template <unsigned ChunkBits>
  static constexpr bool identity_table() noexcept {
    const auto t = make_table<ChunkBits>();
    for (std::uint32_t i = 0; i < t.size(); ++i) {
      if (t[i] != i) {
        return false;
      }
    }
    return true;
  }

  /// Slice tables: t[k][i] = register change of byte i followed by k zero bytes (reflected).
  template <std::size_t N>
  static constexpr std::array<std::array<uint_least_bits_t<reg_bits>, 256>, N>
  make_slices() noexcept {
    std::array<std::array<uint_least_bits_t<reg_bits>, 256>, N> t{};
    t[0] = make_table<8>();
    for (std::size_t k = 1; k < N; ++k) {
      for (std::uint32_t i = 0; i < 256U; ++i) {
        const std::uint32_t prev = t[k - 1U][i];
        const std::uint32_t rest = reg_bits > 8U ? (prev >> 8U) : 0U;
        t[k][i] = static_cast<uint_least_bits_t<reg_bits>>(rest ^ t[0][prev & 0xFFU]);
      }
    }
    return t;
  }
  template <std::size_t N>
  struct slice_holder {
    static constexpr std::array<std::array<uint_least_bits_t<reg_bits>, 256>, N> tables =
        make_slices<N>();
  };
  static constexpr bool can_slice = Reflected && Width >= 8U;
  /// MSB-first CRCs of width 8 or less (BiSS CRC6/CRC4) slice bit fields instead: the register
  /// is one byte, so t[k][b] (byte b, then k zero bytes, from a zero register) is the same
  /// recurrence as above, and a field of up to 8 * N bits is N independent lookups.
  static constexpr bool can_slice_bits = !Reflected && reg_bits == 8U;

  /// Feeds `count` (8 .. 8N) bits, MSB first, from `reg`: the register is folded into the top
  /// byte of the field (feeding M into R equals feeding M ^ (R << (count - 8)) into 0), then
  /// the N bytes are looked up independently (no dependency chain between them).
  template <std::size_t N>
  static constexpr std::uint32_t feed_sliced_bits(std::uint32_t reg, std::uint64_t bits,
                                                  unsigned count) noexcept {
    const std::uint64_t v = bits ^ (static_cast<std::uint64_t>(reg) << (count - 8U));
    const auto& t = slice_holder<N>::tables;
    std::uint32_t r = 0;
    for (std::size_t k = 0; k < N; ++k) {
      r ^= t[k][(v >> (8U * k)) & 0xFFU];
    }
    return r;
  }

  /// Feeds four bytes b0..b3 (b0 first) with the slice tables (reflected, width 8..32).
  static constexpr std::uint32_t step_slice4(std::uint32_t reg, std::uint32_t word) noexcept {
    const auto& t = slice_holder<4>::tables;
    const std::uint32_t x = reg ^ word;
    return static_cast<std::uint32_t>(t[3][x & 0xFFU]) ^ t[2][(x >> 8U) & 0xFFU] ^
           t[1][(x >> 16U) & 0xFFU] ^ t[0][x >> 24U];
  }

  /// Feeds eight bytes: `lo` holds b0..b3, `hi` b4..b7 (b0 first).
  static constexpr std::uint32_t step_slice8(std::uint32_t reg, std::uint32_t lo,
                                             std::uint32_t hi) noexcept {
    const auto& t = slice_holder<8>::tables;
    const std::uint32_t x = reg ^ lo;
    return static_cast<std::uint32_t>(t[7][x & 0xFFU]) ^ t[6][(x >> 8U) & 0xFFU] ^
           t[5][(x >> 16U) & 0xFFU] ^ t[4][x >> 24U] ^ t[3][hi & 0xFFU] ^ t[2][(hi >> 8U) & 0xFFU] ^
           t[1][(hi >> 16U) & 0xFFU] ^ t[0][hi >> 24U];
  }

  template <unsigned ChunkBits>
  struct table_holder {
    static constexpr std::array<uint_least_bits_t<reg_bits>, (1U << ChunkBits)> table =
        make_table<ChunkBits>();
  };

  /// The byte table's entries as two tables of their low and high bytes (16-bit registers).
  static constexpr std::array<std::array<std::uint8_t, 256>, 2> make_split_tables() noexcept {
    std::array<std::array<std::uint8_t, 256>, 2> split{};
    const auto& table = table_holder<8>::table;
    for (std::size_t i = 0; i < 256U; ++i) {
      split[0][i] = static_cast<std::uint8_t>(table[i] & 0xFFU);
      split[1][i] = static_cast<std::uint8_t>(table[i] >> 8U);
    }
    return split;
  }
  struct split_holder {
    static constexpr std::array<std::array<std::uint8_t, 256>, 2> tables = make_split_tables();
  };

  /// Feeds a whole chunk of ChunkBits bits (8 or 4), given in the CRC's bit order.
  template <unsigned ChunkBits>
  static constexpr std::uint32_t step_chunk(std::uint32_t reg, std::uint32_t chunk) noexcept {
    constexpr std::uint32_t chunk_mask = (1U << ChunkBits) - 1U;
    if constexpr (identity_table<ChunkBits>()) {
      if constexpr (Reflected) {
        const std::uint32_t rest = reg_bits > ChunkBits ? (reg >> ChunkBits) : 0U;
        return rest ^ ((reg ^ chunk) & chunk_mask);
      } else {
        return ((reg << ChunkBits) & reg_mask) ^
               (((reg >> (reg_bits - ChunkBits)) ^ chunk) & chunk_mask);
      }
    } else {
      const auto& table = table_holder<ChunkBits>::table;
      if constexpr (Reflected) {
        const std::uint32_t rest = reg_bits > ChunkBits ? (reg >> ChunkBits) : 0U;
        return rest ^ table[(reg ^ chunk) & chunk_mask];
      } else {
        return ((reg << ChunkBits) & reg_mask) ^
               table[((reg >> (reg_bits - ChunkBits)) ^ chunk) & chunk_mask];
      }
    }
  }

  /// Feeds `count` (<= 64) bits of `bits` in the CRC's order, using chunks of Chunk bits
  /// (Chunk = 8, 4, or 1 for bitwise).
  template <unsigned Chunk>
  static constexpr std::uint32_t feed(std::uint32_t reg, std::uint64_t bits,
                                      unsigned count) noexcept {
    if constexpr (Chunk == 8U && can_slice_bits) {
      if (count >= 8U) {
        // Byte steps only, no bit steps: the register folded into the top byte of the field,
        // which is then fed from a zero register rounded up to whole bytes (crc::update_bits).
        const unsigned bytes = (count + 7U) / 8U;
        std::uint64_t m = (bits ^ (static_cast<std::uint64_t>(reg) << (count - 8U)))
                          << (64U - 8U * bytes);
        std::uint32_t r = 0;
        for (unsigned k = 0; k < bytes; ++k) {
          r = step_chunk<8>(r, static_cast<std::uint32_t>(m >> 56U));
          m <<= 8U;
        }
        return r;
      }
    }
    if constexpr (Chunk > 1U) {
      while (count >= Chunk) {
        std::uint32_t chunk = 0;
        if constexpr (Reflected) {
          chunk = static_cast<std::uint32_t>(bits & ((1U << Chunk) - 1U));
          bits >>= Chunk;
        } else {
          chunk = static_cast<std::uint32_t>((bits >> (count - Chunk)) & ((1U << Chunk) - 1U));
        }
        reg = step_chunk<Chunk>(reg, chunk);
        count -= Chunk;
      }
    }
    for (unsigned i = 0; i < count; ++i) {
      const std::uint32_t bit = Reflected
                                    ? static_cast<std::uint32_t>((bits >> i) & 1U)
                                    : static_cast<std::uint32_t>((bits >> (count - 1U - i)) & 1U);
      reg = step_bit(reg, bit);
    }
    return reg;
  }
};

}  // namespace detail

/// A CRC in the Williams model. `Poly` excludes the x^Width term (x^6 + x + 1 is 0x03);
/// `Init` and `XorOut` are given unreflected, as in the published catalogues.
template <unsigned Width, std::uint32_t Poly, std::uint32_t Init, bool RefIn, bool RefOut,
          std::uint32_t XorOut>
struct crc_spec {
  static_assert(Width >= 1U && Width <= 32U, "CRC width must be 1..32");
  static_assert((Init & ~detail::low_mask32(Width)) == 0U, "CRC init must fit the width");
  static_assert((XorOut & ~detail::low_mask32(Width)) == 0U, "CRC xorout must fit the width");
  static constexpr unsigned width = Width;
  static constexpr std::uint32_t poly = Poly;
  static constexpr std::uint32_t init = Init;
  static constexpr bool refin = RefIn;
  static constexpr bool refout = RefOut;
  static constexpr std::uint32_t xorout = XorOut;
  /// Smallest unsigned type holding the CRC value.
  using value_type = detail::uint_least_bits_t<Width>;
};

/// A CRC computation. Cheap to copy (one register); all members are constexpr.
template <class Spec, crc_table_size Table = default_crc_table>
class crc {
  using kernel = detail::crc_kernel<Spec::width, Spec::poly, Spec::refin>;
  static constexpr bool sliced = Table == crc_table_size::slice4 || Table == crc_table_size::slice8;
  static constexpr unsigned chunk_bits =
      (Table == crc_table_size::byte || sliced) ? 8U : (Table == crc_table_size::nibble ? 4U : 1U);
  static_assert(Table == crc_table_size::byte || Table == crc_table_size::nibble ||
                    Table == crc_table_size::bitwise || sliced,
                "unknown CRC table size");

  static constexpr std::uint32_t le32(byte_view data, std::size_t i) noexcept {
    return static_cast<std::uint32_t>(load_le<4>(data, i));
  }

 public:
  using spec = Spec;
  using value_type = typename Spec::value_type;
  static constexpr crc_table_size table_size = Table;
  static constexpr unsigned width = Spec::width;

  constexpr crc() noexcept = default;

  /// Restarts from the initial value.
  constexpr void reset() noexcept { reg_ = initial_register(); }

  constexpr crc& update(std::uint8_t byte) noexcept {
    reg_ = kernel::template feed<chunk_bits>(reg_, byte, 8U);
    return *this;
  }

  constexpr crc& update(byte_view data) noexcept {
    reg_ = feed_range(reg_, data.data(), data.size());
    return *this;
  }

 private:
  // How feed_range walks the bytes: one named walk per target, chosen here and nowhere else.
  enum class byte_walk { xor_fold, sliced, split, pairs, counted, indexed };
  static constexpr byte_walk walk =
      (chunk_bits == 8U && kernel::reg_bits == 8U && kernel::template identity_table<8>())
          ? byte_walk::xor_fold
      : (sliced && kernel::can_slice) ? byte_walk::sliced
      : (Table == crc_table_size::byte && Spec::refin && kernel::reg_bits == 16U &&
         detail::split_halfword_table)
          ? byte_walk::split
      : (chunk_bits == 8U && detail::unaligned_halfwords) ? byte_walk::pairs
      : MOTIONBUS_SMALL_CODE                              ? byte_walk::counted
                                                          : byte_walk::indexed;

  // The register after feeding `size` bytes from `at` to `reg` (static, pointer and count: a
  // one-shot CRC keeps its register and arguments in registers, no view on the stack).
  static constexpr std::uint32_t feed_range(std::uint32_t reg, const std::uint8_t* at,
                                            std::size_t size) noexcept {
    if constexpr (walk == byte_walk::xor_fold) {
      return reg ^ xor_fold(at, size);
    } else if constexpr (walk == byte_walk::sliced) {
      return feed_sliced(reg, at, size);
    } else if constexpr (walk == byte_walk::split) {
      return feed_split(reg, at, size);
    } else if constexpr (walk == byte_walk::pairs) {
      return feed_pairs(reg, at, size);
    } else if constexpr (walk == byte_walk::counted) {
      return feed_counted(reg, at, size);
    } else {
      return feed_indexed(reg, at, size);
    }
  }

  // x^8 + 1 at width 8 makes each byte step reg ^= byte: the CRC is the XOR of the bytes,
  // folded eight at a time from one 64-bit load.
  static constexpr std::uint32_t xor_fold(const std::uint8_t* at, std::size_t size) noexcept {
    const byte_view data(at, size);
    std::uint64_t acc = 0;
    std::size_t i = 0;
    for (; i + 8U <= size; i += 8U) {
      acc ^= load_le<8>(data, i);
    }
    for (; i < size; ++i) {
      acc ^= data[i];
    }
    acc ^= acc >> 32U;
    acc ^= acc >> 16U;
    acc ^= acc >> 8U;
    return static_cast<std::uint32_t>(acc & 0xFFU);
  }

  // Slice tables take four or eight bytes per step with independent lookups (hosts).
  static constexpr std::uint32_t feed_sliced(std::uint32_t reg, const std::uint8_t* at,
                                             std::size_t size) noexcept {
    const byte_view data(at, size);
    std::size_t i = 0;
    if constexpr (Table == crc_table_size::slice8) {
      for (; i + 8U <= size; i += 8U) {
        reg = kernel::step_slice8(reg, le32(data, i), le32(data, i + 4U));
      }
    }
    for (; i + 4U <= size; i += 4U) {
      reg = kernel::step_slice4(reg, le32(data, i));
    }
    return feed_indexed(reg, at + i, size - i);
  }

  // x86-64, reflected 16-bit CRCs: the register as two bytes and the table as two byte tables,
  // so that each byte's step has a byte load on the loop-carried chain, not a scaled halfword
  // load (the table layout of Modbus over Serial Line V1.02 §6.2.2).
  static constexpr std::uint32_t feed_split(std::uint32_t reg, const std::uint8_t* at,
                                            std::size_t size) noexcept {
    const auto& tables = kernel::split_holder::tables;
    std::uint32_t lo = reg & 0xFFU;
    std::uint32_t hi = reg >> 8U;
    for (std::size_t i = 0; i < size; ++i) {
      const std::uint32_t k = lo ^ at[i];
      lo = hi ^ tables[0][k];
      hi = tables[1][k];
    }
    return lo | (hi << 8U);
  }

  // Arm cores with unaligned halfword loads: one load and one loop test for two table steps.
  static constexpr std::uint32_t feed_pairs(std::uint32_t reg, const std::uint8_t* at,
                                            std::size_t size) noexcept {
    std::size_t pairs = size / 2U;
    if (pairs != 0U) {
      do {  // the test at the end, as in feed_counted
        const std::uint32_t w = load_le16(byte_view(at, 2U), 0U);
        reg = step_byte(step_byte(reg, w & 0xFFU), w >> 8U);
        at += 2;
      } while (--pairs != 0U);
    }
    return (size & 1U) != 0U ? step_byte(reg, *at) : reg;
  }

  // One step a byte, the loop test at the end: one branch a byte where -Os does not rotate
  // loops.
  static constexpr std::uint32_t feed_counted(std::uint32_t reg, const std::uint8_t* at,
                                              std::size_t size) noexcept {
    if (size != 0U) {
      do {
        reg = step_byte(reg, *at++);
      } while (--size != 0U);
    }
    return reg;
  }

  // One step a byte, an index loop: the form a host's optimiser unrolls.
  static constexpr std::uint32_t feed_indexed(std::uint32_t reg, const std::uint8_t* at,
                                              std::size_t size) noexcept {
    for (std::size_t i = 0; i < size; ++i) {
      reg = step_byte(reg, at[i]);
    }
    return reg;
  }

  // One table, nibble or bit step for one byte.
  static constexpr std::uint32_t step_byte(std::uint32_t reg, std::uint32_t byte) noexcept {
    if constexpr (chunk_bits == 8U) {
      return kernel::template step_chunk<8>(reg, byte);
    } else {
      return kernel::template feed<chunk_bits>(reg, byte, 8U);
    }
  }

 public:
  /// Feeds the low `count` bits of `bits` in the CRC's bit order (see the file comment).
  /// A count above 64 is treated as 64.
  // inline: MOTIONBUS_CONSTANT_P then sees a count the caller fixes (a BiSS-C frame's CRC).
  MOTIONBUS_INLINE constexpr crc& update_bits(std::uint64_t bits, unsigned count) noexcept {
    const unsigned n = count > 64U ? 64U : count;
    const std::uint64_t v = bits & detail::low_mask64(n);
    if constexpr (sliced && kernel::can_slice_bits) {
      constexpr unsigned slice_bits = Table == crc_table_size::slice8 ? 64U : 32U;
      if (n >= 8U && n <= slice_bits) {
        reg_ = kernel::template feed_sliced_bits<slice_bits / 8U>(reg_, v, n);
        return *this;
      }
    }
    if constexpr (chunk_bits == 8U && kernel::can_slice_bits) {
      if (MOTIONBUS_CONSTANT_P(n) && n >= 8U) {
        // A count known at compile time (a BiSS-C frame's CRC): byte steps only, unrolled into
        // straight-line code. The register is folded into the top byte of the field (as in
        // feed_sliced_bits) and the field fed from a zero register, which leading zero bits
        // leave at zero: the field rounded up to whole bytes is the same message, kept
        // left-aligned so that each step takes its top byte (constant shifts only). A count
        // known only at run time calls the shared kernel (smaller where inlined often).
        // coverage-begin: taken where the optimiser folds the count (-O1 and up, constant
        // evaluation), never at the coverage build's -O0; tests/core/crc_test.cpp checks it at
        // -O2 for every count 8..64 and tests/static/core_static.cpp in constant evaluation
        const unsigned bytes = (n + 7U) / 8U;
        std::uint64_t m = (v ^ (static_cast<std::uint64_t>(reg_) << (n - 8U)))
                          << (64U - 8U * bytes);
        std::uint32_t r = 0;
        MOTIONBUS_UNROLL(8)
        for (unsigned k = 0; k < bytes; ++k) {
          r = kernel::template step_chunk<8>(r, static_cast<std::uint32_t>(m >> 56U));
          m <<= 8U;
        }
        reg_ = r;
        return *this;
        // coverage-end
      }
    }
    reg_ = kernel::template feed<chunk_bits>(reg_, v, n);
    return *this;
  }

  /// Feeds `bit_count` bits of a bit stream stored in `words` (any length), starting at stream
  /// bit `bit_offset`, in stream order: the first stream bit is fed first whatever the CRC's
  /// reflection. errc::truncated (nothing fed) if the stream holds fewer bits.
  template <class Word>
  constexpr errc update_stream(span<const Word> words, bit_order order, std::size_t bit_offset,
                               std::size_t bit_count) noexcept {
    basic_bit_reader<Word> reader(words, order, bit_offset);
    if (bit_offset > reader.size() || bit_count > reader.remaining()) {
      return errc::truncated;
    }
    // The reader returns a chunk's first stream bit as its MSB (msb_first) or LSB (lsb_first);
    // the kernel wants it where the CRC's order puts the first bit.
    const bool flip = (order == bit_order::msb_first) == Spec::refin;
    std::size_t left = bit_count;
    std::uint32_t reg = reg_;
    while (left > 0U) {
      const unsigned n = left >= 64U ? 64U : static_cast<unsigned>(left);
      const std::uint64_t chunk = reader.read(n).value();
      reg = kernel::template feed<chunk_bits>(reg, flip ? reverse_bits(chunk, n) : chunk, n);
      left -= n;
    }
    reg_ = reg;
    return errc::ok;
  }

  /// The CRC of everything fed so far (reflection and final XOR applied). Feeding may go on.
  constexpr value_type value() const noexcept { return value_of(reg_); }

  /// One-shot CRC of `data`.
  // inline: the walk gets the view's pointer and size in registers, not through the stack.
  MOTIONBUS_INLINE static constexpr value_type compute(byte_view data) noexcept {
    return value_of(feed_range(initial_register(), data.data(), data.size()));
  }

  /// One-shot CRC of the low `count` (<= 64) bits of `bits`, fed in the CRC's bit order.
  static constexpr value_type compute_bits(std::uint64_t bits, unsigned count) noexcept {
    return crc().update_bits(bits, count).value();
  }

  /// For a reflected CRC of 8 bits or more with no final XOR (CRC-16/MODBUS): the CRC of a
  /// message from the CRC of that message followed by `last_byte`: the byte's step run
  /// backwards, eight shifts and XORs (no table). A message followed by its CRC, low byte first,
  /// has the CRC 0, and the empty message has Spec::init; so the values before the last bytes of a
  /// buffer, taken back from 0, show where a CRC-valid message starts that ends at the buffer's
  /// end: wherever the value reached is Spec::init. One pass for every start (the RTU framer's
  /// idle()).
  static constexpr value_type value_before(std::uint32_t value_after,
                                           std::uint8_t last_byte) noexcept {
    // a register of 8 bits or more takes a byte whole; an odd polynomial (its x^0 term) shows
    // the step's feedback in the register's top bit
    static_assert(Spec::refin && Spec::refout && Spec::xorout == 0U && Spec::width >= 8U &&
                      (Spec::poly & 1U) != 0U,
                  "value_before() is for reflected CRCs of 8 bits or more, no final XOR");
    std::uint32_t reg = value_after;  // reflected, no final XOR: the register is the value
    for (unsigned k = 0; k < 8U; ++k) {
      reg = detail::crc_unstep_reflected(reg, kernel::poly, kernel::reg_bits);
    }
    return static_cast<value_type>(reg ^ last_byte);
  }

  /// Entries of the tables this engine uses (0 for bitwise). Exposed for size reports and tests.
  static constexpr std::size_t table_entries() noexcept {
    return sliced && !kernel::can_slice && !kernel::can_slice_bits
               ? 256U
               : static_cast<std::size_t>(Table);
  }

 private:
  static constexpr value_type value_of(std::uint32_t reg) noexcept {
    return static_cast<value_type>(detail::crc_register_value(
        reg, Spec::width, kernel::align, Spec::refin, Spec::refout, Spec::xorout));
  }
  static constexpr std::uint32_t initial_register() noexcept {
    return detail::crc_initial_register(Spec::init, Spec::width, kernel::align, Spec::refin);
  }

  std::uint32_t reg_ = initial_register();
};

// ---------------------------------------------------------------------------------------------
// Run-time parameters.

/// CRC parameters known only at run time (read from a device's data sheet in memory, given on
/// a command line): the same Williams model as crc_spec, `poly` without its x^width term.
struct crc_parameters {
  unsigned width = 8;
  std::uint32_t poly = 0x07;
  std::uint32_t init = 0;
  bool refin = false;
  bool refout = false;
  std::uint32_t xorout = 0;

  /// Width 1..32 and every value within it.
  constexpr bool valid() const noexcept {
    const std::uint32_t m = detail::low_mask32(width);
    return width >= 1U && width <= 32U && (poly & ~m) == 0U && (init & ~m) == 0U &&
           (xorout & ~m) == 0U;
  }
  friend constexpr bool operator==(const crc_parameters& a, const crc_parameters& b) noexcept {
    return a.width == b.width && a.poly == b.poly && a.init == b.init && a.refin == b.refin &&
           a.refout == b.refout && a.xorout == b.xorout;
  }
  friend constexpr bool operator!=(const crc_parameters& a, const crc_parameters& b) noexcept {
    return !(a == b);
  }
};

/// The parameters of a compile-time spec, for comparison with run-time ones.
template <class Spec>
constexpr crc_parameters parameters_of() noexcept {
  return {Spec::width, Spec::poly, Spec::init, Spec::refin, Spec::refout, Spec::xorout};
}

/// A CRC from run-time parameters, computed bit by bit with the engine's own register
/// arithmetic (the same step functions as crc<Spec, crc_table_size::bitwise>, which gives the
/// same values). Invalid parameters (see crc_parameters::valid) are clamped to a 1-bit CRC of
/// polynomial 1; check valid() first. No table, no state beyond the register.
class dynamic_crc {
 public:
  constexpr explicit dynamic_crc(const crc_parameters& p) noexcept
      : p_(p.valid() ? p : crc_parameters{1, 1, 0, false, false, 0}),
        reg_bits_(p_.refin ? p_.width : (p_.width < 8U ? 8U : p_.width)),
        align_(reg_bits_ - p_.width),
        poly_(p_.refin ? detail::reflect32(p_.poly, p_.width) : (p_.poly << align_)),
        reg_(detail::crc_initial_register(p_.init, p_.width, align_, p_.refin)) {}

  constexpr const crc_parameters& parameters() const noexcept { return p_; }

  /// Feeds the low `count` (<= 64) bits of `bits` in the CRC's bit order (as crc::update_bits).
  constexpr dynamic_crc& update_bits(std::uint64_t bits, unsigned count) noexcept {
    const unsigned n = count > 64U ? 64U : count;
    for (unsigned i = 0; i < n; ++i) {
      const auto bit =
          static_cast<std::uint32_t>(p_.refin ? ((bits >> i) & 1U) : ((bits >> (n - 1U - i)) & 1U));
      reg_ = p_.refin ? detail::crc_step_reflected(reg_, bit, poly_)
                      : detail::crc_step_normal(reg_, bit, poly_, reg_bits_);
    }
    return *this;
  }

  constexpr dynamic_crc& update(byte_view data) noexcept {
    for (std::size_t i = 0; i < data.size(); ++i) {
      update_bits(data[i], 8U);
    }
    return *this;
  }

  constexpr std::uint32_t value() const noexcept {
    return detail::crc_register_value(reg_, p_.width, align_, p_.refin, p_.refout, p_.xorout);
  }

 private:
  crc_parameters p_;
  unsigned reg_bits_;
  unsigned align_;
  std::uint32_t poly_;
  std::uint32_t reg_;
};

// ---------------------------------------------------------------------------------------------
// The protocols' CRCs.

/// T-format CRC: G(X) = X^8 + 1 over every field byte before the CRC field, start and delimiter
/// bits excluded (T-format spec §6.3.4). With this generator the CRC is the XOR of those bytes,
/// whichever bit order is used; it is declared reflected because the wire sends bytes LSB first.
using crc8_tformat_spec = crc_spec<8, 0x01, 0x00, true, true, 0x00>;
/// CRC-16/MODBUS: poly 0x8005 reflected, init 0xFFFF, no final XOR (Modbus over Serial Line
/// V1.02 §6.2.2). Sent low byte first.
using crc16_modbus_spec = crc_spec<16, 0x8005, 0xFFFF, true, true, 0x0000>;
/// BiSS CRC6: x^6 + x + 1 (written 0x43 in BiSS documents), start 0, MSB first, sent inverted.
using crc6_biss_spec = crc_spec<6, 0x03, 0x00, false, false, 0x3F>;
/// BiSS CRC4 (control communication): x^4 + x + 1 (0x13), start 0, MSB first, sent inverted.
using crc4_biss_spec = crc_spec<4, 0x03, 0x00, false, false, 0x0F>;

template <crc_table_size Table = default_crc_table>
using crc8_tformat = crc<crc8_tformat_spec, Table>;
template <crc_table_size Table = default_crc_table>
using crc16_modbus = crc<crc16_modbus_spec, Table>;
template <crc_table_size Table = default_crc_table>
using crc6_biss = crc<crc6_biss_spec, Table>;
template <crc_table_size Table = default_crc_table>
using crc4_biss = crc<crc4_biss_spec, Table>;

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_CRC_HPP
