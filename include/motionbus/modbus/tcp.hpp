// motionbus — Modbus TCP ADU: MBAP header (transaction id, protocol id 0, length, unit id) +
// PDU, reusing the PDU codec (Modbus Messaging on TCP/IP Implementation Guide V1.0b §3.1.3).
#ifndef MOTIONBUS_MODBUS_TCP_HPP
#define MOTIONBUS_MODBUS_TCP_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/bytes.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu.hpp"

namespace motionbus {
namespace modbus {

inline constexpr std::size_t mbap_size = 7;
inline constexpr std::size_t max_tcp_size = mbap_size + max_pdu_size;  // 260

struct tcp_frame {
  std::uint16_t transaction = 0;
  std::uint16_t protocol = 0;  ///< 0 for Modbus
  std::uint8_t unit = 0;
  byte_view pdu{};  ///< a view into the input
};

/// MBAP header + `pdu`. Errors: modbus_pdu_length, buffer_too_small.
constexpr result<std::size_t> encode_tcp(std::uint16_t transaction, std::uint8_t unit,
                                         byte_view pdu, mutable_byte_view out) noexcept {
  if (!pdu_size_ok(pdu.size())) {
    return errc::modbus_pdu_length;
  }
  const std::size_t n = mbap_size + pdu.size();
  if (out.size() < n) {
    return errc::buffer_too_small;
  }
  const auto length = static_cast<std::uint16_t>(pdu.size() + 1U);  // unit id + PDU
  store_be16(out, 0, transaction);
  store_be16(out, 2, 0);  // protocol: Modbus
  store_be16(out, 4, length);
  out[6] = unit;
  for (std::size_t i = 0; i < pdu.size(); ++i) {
    out[mbap_size + i] = pdu[i];
  }
  return n;
}

/// The size of the TCP ADU at the start of a byte stream (6 + the length field), told from its
/// first bytes, for a reader that holds a stream's bytes as they arrive (a gateway's client
/// connection): each field is checked as soon as it is held, so a bad header fails before its
/// body is awaited. Complete (consumed 0): the ADU's size, 8..260. Incomplete: fewer than 6
/// bytes (4 with a protocol id not 0) held. Failed (consumed = the input: the stream cannot
/// be resynchronised): invalid_argument (protocol id not 0), modbus_pdu_length (length field
/// below 2 or above 254: no PDU, or an ADU over 260 bytes).
constexpr decode_result<std::size_t> tcp_adu_size(byte_view in) noexcept {
  if (in.size() >= 4U && load_be16(in, 2) != 0U) {
    return decode_failure{errc::invalid_argument, in.size()};
  }
  if (in.size() < 6U) {
    return need_input{6U - in.size()};
  }
  const std::size_t length = load_be16(in, 4);
  if (length < 2U || !pdu_size_ok(length - 1U)) {  // the unit identifier, then the PDU
    return decode_failure{errc::modbus_pdu_length, in.size()};
  }
  return decode_result<std::size_t>::complete(6U + length, 0);
}

/// Decodes one TCP ADU from the start of a byte stream. Complete: consumed = 6 + length.
/// Incomplete: the header or the announced bytes are not all there yet. Failed: modbus_pdu_length
/// (length field below 2 or above 254; consumed = the whole input, the stream cannot be
/// resynchronised), invalid_argument (protocol id not 0; consumed = the frame).
constexpr decode_result<tcp_frame> decode_tcp(byte_view in) noexcept {
  if (in.size() < mbap_size) {
    return need_input{mbap_size - in.size()};
  }
  tcp_frame f;
  f.transaction = load_be16(in, 0);
  f.protocol = load_be16(in, 2);
  const std::size_t length = load_be16(in, 4);
  if (length < 1U || !pdu_size_ok(length - 1U)) {  // the unit identifier, then the PDU
    return decode_failure{errc::modbus_pdu_length, in.size()};
  }
  const std::size_t total = 6U + length;
  if (in.size() < total) {
    return need_input{total - in.size()};
  }
  if (f.protocol != 0U) {
    return decode_failure{errc::invalid_argument, total};
  }
  f.unit = in[6];
  f.pdu = in.subspan(mbap_size, length - 1U);
  return decode_result<tcp_frame>::complete(f, total);
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_TCP_HPP
