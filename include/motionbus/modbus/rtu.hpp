// motionbus — Modbus RTU ADU: slave address + PDU + CRC-16/MODBUS (low byte first)
// (Modbus over Serial Line V1.02 §2.5.1, §6.2.2; docs/modbus.md §4).
#ifndef MOTIONBUS_MODBUS_RTU_HPP
#define MOTIONBUS_MODBUS_RTU_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/bytes.hpp"
#include "motionbus/core/crc.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu.hpp"

namespace motionbus {
namespace modbus {

inline constexpr std::size_t max_rtu_size = 256;
inline constexpr std::size_t min_rtu_size = 4;
inline constexpr std::uint8_t broadcast_address = 0;
inline constexpr std::uint8_t max_unicast_address = 247;

using crc16 = crc16_modbus<>;

/// An RTU frame as decoded: the slave address and a view of the PDU inside the input.
struct rtu_frame {
  std::uint8_t slave = 0;
  byte_view pdu{};
  std::uint16_t crc = 0;  ///< as received (low byte first on the wire)
  constexpr bool broadcast() const noexcept { return slave == broadcast_address; }
};

/// Wraps `pdu` for `slave` (0 broadcast, 1..247). Errors: modbus_slave_address (248..255),
/// modbus_pdu_length (empty or > 253), buffer_too_small. Nothing is written on error.
/// `Table` selects the CRC table (e.g. crc_table_size::slice4 on hosts, bitwise for flash).
template <crc_table_size Table = default_crc_table>
constexpr result<std::size_t> encode_rtu(std::uint8_t slave, byte_view pdu,
                                         mutable_byte_view out) noexcept {
  if (slave > max_unicast_address) {
    return errc::modbus_slave_address;
  }
  if (!pdu_size_ok(pdu.size())) {
    return errc::modbus_pdu_length;
  }
  const std::size_t n = pdu.size() + 3U;
  if (out.size() < n) {
    return errc::buffer_too_small;
  }
  out[0] = slave;
  std::size_t copied = 0;
#if defined(__x86_64__) || defined(__aarch64__)
  // Hosts, at run time: the C library's memmove (the views may overlap). g++ -O2 neither
  // vectorises the loop below nor makes it a memcpy, which it cannot, for that overlap: a
  // long PDU was slower than libmodbus's memcpy (bench/RESULTS.md, session 12).
  // coverage-branch: false in constant evaluation only, which gcov does not count
  if (!MOTIONBUS_CONSTANT_EVALUATED()) {
    __builtin_memmove(out.data() + 1, pdu.data(), pdu.size());
    copied = pdu.size();
  }
#endif
  // coverage-branch: on x86-64 at run time the memmove above copied all: the loop never runs
  for (std::size_t i = copied; i < pdu.size(); ++i) {
    // coverage: constant evaluation, and targets other than x86-64 and AArch64 (s390x, armhf)
    out[1U + i] = pdu[i];
  }
  const std::uint16_t c = crc16_modbus<Table>::compute(byte_view(out.data(), n - 2U));
  store_le16(out, n - 2U, c);
  return n;
}

/// Decodes a whole RTU ADU (the bytes between two silent intervals). Failed (consumed = size):
/// modbus_pdu_length (fewer than 4 or more than 256 bytes), crc_mismatch (expected = computed,
/// received = sent), modbus_slave_address (248..255).
template <crc_table_size Table = default_crc_table>
constexpr decode_result<rtu_frame> decode_rtu(byte_view adu) noexcept {
  const std::size_t n = adu.size();
  if (n < 3U || !pdu_size_ok(n - 3U)) {  // address, PDU, CRC
    return decode_failure{errc::modbus_pdu_length, n};
  }
  const std::uint16_t received = load_le16(adu, n - 2U);
  const std::uint16_t computed = crc16_modbus<Table>::compute(adu.first(n - 2U));
  if (computed != received) {
    return decode_failure{errc::crc_mismatch, n, computed, received};
  }
  const std::uint8_t slave = adu[0];
  if (slave > max_unicast_address) {
    return decode_failure{errc::modbus_slave_address, n};
  }
  // Every field given (aggregate initialisation): each is stored once.
  return decode_result<rtu_frame>::complete(rtu_frame{slave, adu.subspan(1, n - 3U), received}, n);
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_RTU_HPP
