// motionbus — Modbus RTU server dispatch: the library decodes, checks, calls the user's data
// accessors and builds the response or the right exception; nothing for broadcasts (address
// 0: executed, never answered) or for other addresses (Modbus over Serial Line §2.2).
//
// The device is any type with some of these members (detected at compile time; no virtual
// calls, no heap). Each returns 0 on success or a Modbus exception code (02 illegal address,
// 03 illegal value, 04 device failure, or any other code, passed through):
//   std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
//                          motionbus::mutable_byte_view packed);        // FC01, FC02
//   std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
//                               motionbus::span<std::uint16_t> out);    // FC03, FC04 (and 16, 17)
//   std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity,
//                            motionbus::byte_view packed);              // FC05, FC0F
//   std::uint8_t write_registers(std::uint16_t address,
//                                motionbus::span<const std::uint16_t>); // FC06, FC10 (16, 17)
//   std::uint8_t report_server_id(motionbus::mutable_byte_view out, std::size_t& size); // FC11
//   std::uint8_t admit(motionbus::byte_view pdu);  // optional: a device-specific first check
//                                                  // of the raw request PDU (e.g. its own
//                                                  // order of exceptions); 0 lets it through
// A function whose accessor is missing is answered with exception 01. The request's own limits
// are checked first (decode_request: exception 01, then 03, then 02), as the spec's state
// diagrams order them (Modbus App. Protocol §6).
#ifndef MOTIONBUS_MODBUS_SERVER_HPP
#define MOTIONBUS_MODBUS_SERVER_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/rtu.hpp"

namespace motionbus {
namespace modbus {

namespace detail {

template <class D, class = void>
struct has_read_bits : std::false_type {};
template <class D>
struct has_read_bits<D,
                     std::void_t<decltype(std::declval<D&>().read_bits(
                         std::uint8_t{}, std::uint16_t{}, std::uint16_t{}, mutable_byte_view{}))>>
    : std::true_type {};

template <class D, class = void>
struct has_read_registers : std::false_type {};
template <class D>
struct has_read_registers<D, std::void_t<decltype(std::declval<D&>().read_registers(
                                 std::uint8_t{}, std::uint16_t{}, span<std::uint16_t>{}))>>
    : std::true_type {};

template <class D, class = void>
struct has_write_coils : std::false_type {};
template <class D>
struct has_write_coils<D, std::void_t<decltype(std::declval<D&>().write_coils(
                              std::uint16_t{}, std::uint16_t{}, byte_view{}))>> : std::true_type {};

template <class D, class = void>
struct has_write_registers : std::false_type {};
template <class D>
struct has_write_registers<D, std::void_t<decltype(std::declval<D&>().write_registers(
                                  std::uint16_t{}, span<const std::uint16_t>{}))>>
    : std::true_type {};

template <class D, class = void>
struct has_admit : std::false_type {};
template <class D>
struct has_admit<D, std::void_t<decltype(std::declval<D&>().admit(byte_view{}))>> : std::true_type {
};

template <class D, class = void>
struct has_report_server_id : std::false_type {};
template <class D>
struct has_report_server_id<D, std::void_t<decltype(std::declval<D&>().report_server_id(
                                   mutable_byte_view{}, std::declval<std::size_t&>()))>>
    : std::true_type {};

constexpr std::uint8_t illegal_function_code =
    static_cast<std::uint8_t>(exception_code::illegal_function);

// Serves one decoded request; writes the response PDU into `pdu_out` (>= 253 bytes).
// Returns its size (an exception response is 2 bytes).
template <class Device>
constexpr std::size_t serve_pdu(Device& dev, const request& q, mutable_byte_view pdu_out) noexcept {
  const std::uint8_t f = q.function;
  std::uint8_t code = illegal_function_code;
  std::uint16_t regs[max_read_registers] = {};
  std::uint16_t writes[max_write_registers] = {};
  auto exception = [&](std::uint8_t c) { return encode_exception(f, c, pdu_out).value_or(0); };
  const std::size_t write_count = q.data.size() / 2U;
  for (std::size_t i = 0; i < write_count && i < max_write_registers; ++i) {
    writes[i] = register_at(q.data, i);
  }
  if (f == 0x01 || f == 0x02) {
    if constexpr (has_read_bits<Device>::value) {
      const std::size_t n = (q.quantity + 7U) / 8U;
      for (std::size_t i = 0; i < n; ++i) {
        pdu_out[2U + i] = 0;
      }
      code = dev.read_bits(f, q.address, q.quantity, pdu_out.subspan(2, n));
      if (code == 0U) {
        const std::size_t size =
            encode_read_bits_response(f, q.quantity, pdu_out.subspan(2, n), pdu_out).value_or(0);
        return size;
      }
    }
  } else if (f == 0x03 || f == 0x04) {
    if constexpr (has_read_registers<Device>::value) {
      code = dev.read_registers(f, q.address, span<std::uint16_t>(regs, q.quantity));
      if (code == 0U) {
        return encode_read_registers_response(f, span<const std::uint16_t>(regs, q.quantity),
                                              pdu_out)
            .value_or(0);
      }
    }
  } else if (f == 0x05 || f == 0x0F) {
    if constexpr (has_write_coils<Device>::value) {
      const std::uint8_t one[1] = {static_cast<std::uint8_t>(q.value == coil_on ? 1U : 0U)};
      code = f == 0x05 ? dev.write_coils(q.address, 1, byte_view(one, 1))
                       : dev.write_coils(q.address, q.quantity, q.data);
      if (code == 0U) {
        return encode_write_response(q, pdu_out).value_or(0);
      }
    }
  } else if (f == 0x06 || f == 0x10) {
    if constexpr (has_write_registers<Device>::value) {
      const std::uint16_t single[1] = {q.value};
      code = f == 0x06
                 ? dev.write_registers(q.address, span<const std::uint16_t>(single, 1))
                 : dev.write_registers(q.address, span<const std::uint16_t>(writes, write_count));
      if (code == 0U) {
        return encode_write_response(q, pdu_out).value_or(0);
      }
    }
  } else if (f == 0x16) {
    if constexpr (has_read_registers<Device>::value && has_write_registers<Device>::value) {
      code = dev.read_registers(0x03, q.address, span<std::uint16_t>(regs, 1));
      if (code == 0U) {
        const auto v = static_cast<std::uint16_t>(
            (regs[0] & q.and_mask) | (q.or_mask & static_cast<std::uint16_t>(~q.and_mask)));
        code = dev.write_registers(q.address, span<const std::uint16_t>(&v, 1));
      }
      if (code == 0U) {
        return encode_write_response(q, pdu_out).value_or(0);
      }
    }
  } else if (f == 0x17) {
    if constexpr (has_read_registers<Device>::value && has_write_registers<Device>::value) {
      // the write is performed before the read (§6.17)
      code = dev.write_registers(q.write_address, span<const std::uint16_t>(writes, write_count));
      if (code == 0U) {
        code = dev.read_registers(0x03, q.address, span<std::uint16_t>(regs, q.quantity));
      }
      if (code == 0U) {
        return encode_read_registers_response(f, span<const std::uint16_t>(regs, q.quantity),
                                              pdu_out)
            .value_or(0);
      }
    }
  } else if (f == 0x11) {
    if constexpr (has_report_server_id<Device>::value) {
      std::size_t size = 0;
      code = dev.report_server_id(pdu_out.subspan(1, max_pdu_size - 1U), size);
      if (code == 0U && size + 1U <= max_pdu_size) {
        pdu_out[0] = f;
        return size + 1U;
      }
    }
  }
  return exception(code == 0U ? static_cast<std::uint8_t>(exception_code::server_device_failure)
                              : code);
}

}  // namespace detail

/// Serves one RTU request ADU (the bytes of one frame) for a server at `own_address`
/// (1..247). Returns the size of the response ADU written to `out` (which must hold 256
/// bytes), or 0 when nothing is to be sent: a bad CRC or length, another address, or a
/// broadcast (executed all the same). errc::buffer_too_small when `out` is shorter than 256.
template <class Device>
constexpr result<std::size_t> serve_rtu(Device& dev, std::uint8_t own_address, byte_view adu,
                                        mutable_byte_view out) noexcept {
  if (out.size() < max_rtu_size) {
    return errc::buffer_too_small;
  }
  const decode_result<rtu_frame> f = decode_rtu(adu);
  if (!f.is_complete()) {
    return std::size_t{0};  // no response to a corrupted frame
  }
  const rtu_frame& frame = f.value();
  if (frame.slave != own_address && !frame.broadcast()) {
    return std::size_t{0};
  }
  std::uint8_t pdu[max_pdu_size] = {};
  std::size_t n = 0;
  std::uint8_t admitted = 0;
  if constexpr (detail::has_admit<Device>::value) {
    admitted = dev.admit(frame.pdu);
  }
  const decode_result<request> q = decode_request(frame.pdu);
  if (admitted != 0U) {
    n = encode_exception(frame.pdu[0], admitted, mutable_byte_view(pdu, max_pdu_size)).value_or(0);
  } else if (q.is_complete()) {
    n = detail::serve_pdu(dev, q.value(), mutable_byte_view(pdu, max_pdu_size));
  } else {
    n = encode_exception(frame.pdu[0], static_cast<std::uint8_t>(exception_for(q.error())),
                         mutable_byte_view(pdu, max_pdu_size))
            .value_or(0);
  }
  if (frame.broadcast() || n == 0U) {
    return std::size_t{0};
  }
  return encode_rtu(own_address, byte_view(pdu, n), out);
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_SERVER_HPP
