// motionbus — Modbus PDU codec for both roles (Modbus Application Protocol V1.1b3).
//
// Client: encode_* requests into a caller buffer; decode_response(pdu, request) checks the
//         answer against the request it belongs to.
// Server: decode_request(pdu) enforces every limit of the spec and says which exception to
//         answer (exception_for); encode_*_response and encode_exception build the reply.
// PDUs are function code + data, at most 253 bytes; register values are big-endian on the
// wire. Decoded values that carry data (packed coils, register bytes, opaque payloads) are
// views into the caller's input: valid while that buffer is.
// Implemented: 01, 02, 03, 04, 05, 06, 07, 08 (all defined sub-functions), 0B, 0C, 0F, 10, 11,
// 16, 17, 18, 2B/0E (read device identification), exception responses with any code, and a raw
// path for any other function code.
#ifndef MOTIONBUS_MODBUS_PDU_HPP
#define MOTIONBUS_MODBUS_PDU_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {
namespace modbus {

inline constexpr std::size_t max_pdu_size = 253;

/// Function codes (Modbus App. Protocol §6).
enum class function_code : std::uint8_t {
  read_coils = 0x01,
  read_discrete_inputs = 0x02,
  read_holding_registers = 0x03,
  read_input_registers = 0x04,
  write_single_coil = 0x05,
  write_single_register = 0x06,
  read_exception_status = 0x07,
  diagnostics = 0x08,
  get_comm_event_counter = 0x0B,
  get_comm_event_log = 0x0C,
  write_multiple_coils = 0x0F,
  write_multiple_registers = 0x10,
  report_server_id = 0x11,
  mask_write_register = 0x16,
  read_write_multiple_registers = 0x17,
  read_fifo_queue = 0x18,
  encapsulated_interface = 0x2B,
};

/// Exception codes as sent on the wire (§7). Unknown codes pass through unchanged.
enum class exception_code : std::uint8_t {
  illegal_function = 0x01,
  illegal_data_address = 0x02,
  illegal_data_value = 0x03,
  server_device_failure = 0x04,
  acknowledge = 0x05,
  server_device_busy = 0x06,
  memory_parity_error = 0x08,
  gateway_path_unavailable = 0x0A,
  gateway_target_failed = 0x0B,
};

inline constexpr std::uint8_t exception_flag = 0x80;

/// Limits (§6.1–6.17).
inline constexpr std::uint16_t max_read_bits = 2000;          // FC01/02
inline constexpr std::uint16_t max_read_registers = 125;      // FC03/04, FC17 read
inline constexpr std::uint16_t max_write_coils = 1968;        // FC0F
inline constexpr std::uint16_t max_write_registers = 123;     // FC10
inline constexpr std::uint16_t max_rw_write_registers = 121;  // FC17 write
inline constexpr std::uint16_t coil_on = 0xFF00;
inline constexpr std::uint16_t coil_off = 0x0000;

/// Which response layout FC11 uses: the standard one (byte count, then device bytes) or the
/// Tsubaki SM unit's (exactly two bytes, no byte count: version upper, version lower).
enum class report_id_format : std::uint8_t { standard = 0, two_bytes_no_count = 1 };

/// A request as a server sees it (fields as the function has them).
struct request {
  // (The fields are ordered by size, so that the struct has no padding: 28 bytes on 32-bit
  // targets.)
  /// FC0F packed coils, FC10/FC17 register bytes (big-endian pairs), FC08 data, or the whole
  /// data part of a function this codec does not frame. A view into the decoded input.
  byte_view data{};
  std::uint16_t address = 0;         ///< starting address (FC01-06, 0F, 10, 16; FC17 read address)
  std::uint16_t quantity = 0;        ///< FC01-04, 0F, 10; FC17 read quantity
  std::uint16_t value = 0;           ///< FC05 (0xFF00/0x0000), FC06
  std::uint16_t and_mask = 0;        ///< FC16
  std::uint16_t or_mask = 0;         ///< FC16
  std::uint16_t write_address = 0;   ///< FC17
  std::uint16_t write_quantity = 0;  ///< FC17
  std::uint16_t sub_function = 0;    ///< FC08
  std::uint8_t function = 0;
  std::uint8_t mei_type = 0;   ///< FC2B (0x0E: read device identification)
  std::uint8_t read_code = 0;  ///< FC2B/0E: 1 basic, 2 regular, 3 extended, 4 one object
  std::uint8_t object_id = 0;  ///< FC2B/0E
};

/// A response as a client sees it.
struct response {
  // (The fields are ordered by size, so that the struct has no padding: 36 bytes on 32-bit
  // targets, which a client keeps on its stack.)
  /// FC01/02 packed bits, FC03/04/17/18 register bytes, FC08 data, FC0C events, FC11 payload,
  /// FC2B/0E objects (id, length, value ...), raw data. A view into the input.
  byte_view data{};
  std::uint8_t function = 0;  ///< without the exception flag
  bool exception = false;
  std::uint8_t exception_code = 0;  ///< wire value when exception
  std::uint8_t byte_count = 0;
  std::uint16_t address = 0;        ///< echo: FC05, 06, 0F, 10, 16
  std::uint16_t quantity = 0;       ///< echo: FC0F, 10
  std::uint16_t value = 0;          ///< echo: FC05, 06
  std::uint16_t and_mask = 0;       ///< echo: FC16
  std::uint16_t or_mask = 0;        ///< echo: FC16
  std::uint16_t sub_function = 0;   ///< FC08
  std::uint16_t status = 0;         ///< FC07 (output byte), FC0B, FC0C
  std::uint16_t event_count = 0;    ///< FC0B, FC0C
  std::uint16_t message_count = 0;  ///< FC0C
  std::uint16_t fifo_count = 0;     ///< FC18
  std::uint8_t conformity = 0;      ///< FC2B/0E
  bool more_follows = false;        ///< FC2B/0E
  std::uint8_t next_object = 0;     ///< FC2B/0E
  std::uint8_t object_count = 0;    ///< FC2B/0E
};

/// FC08 sub-functions (Modbus over Serial Line §6.1).
namespace diagnostic {
inline constexpr std::uint16_t return_query_data = 0x00;
inline constexpr std::uint16_t restart_communications = 0x01;
inline constexpr std::uint16_t return_diagnostic_register = 0x02;
inline constexpr std::uint16_t change_ascii_delimiter = 0x03;
inline constexpr std::uint16_t force_listen_only = 0x04;
inline constexpr std::uint16_t clear_counters = 0x0A;
inline constexpr std::uint16_t return_bus_message_count = 0x0B;
inline constexpr std::uint16_t return_bus_error_count = 0x0C;
inline constexpr std::uint16_t return_exception_count = 0x0D;
inline constexpr std::uint16_t return_server_message_count = 0x0E;
inline constexpr std::uint16_t return_no_response_count = 0x0F;
inline constexpr std::uint16_t return_nak_count = 0x10;
inline constexpr std::uint16_t return_busy_count = 0x11;
inline constexpr std::uint16_t return_overrun_count = 0x12;
inline constexpr std::uint16_t clear_overrun_counter = 0x14;
/// True for the sub-functions defined by the specification.
constexpr bool is_defined(std::uint16_t sub) noexcept {
  return sub <= 0x04U || (sub >= 0x0AU && sub <= 0x12U) || sub == 0x14U;
}
}  // namespace diagnostic

inline constexpr std::uint8_t mei_read_device_identification = 0x0E;
inline constexpr std::uint16_t max_fifo_count = 31;

/// Register i of big-endian register bytes (no bounds check beyond the caller's: i < size/2).
constexpr std::uint16_t register_at(byte_view bytes, std::size_t i) noexcept {
  return static_cast<std::uint16_t>((bytes[2U * i] << 8U) | bytes[2U * i + 1U]);
}
/// Bit i of packed coils (LSB of the first byte first).
constexpr bool bit_at(byte_view packed, std::size_t i) noexcept {
  return ((packed[i / 8U] >> (i % 8U)) & 1U) != 0U;
}

/// The exception a server answers for a request decoding error (§7; the order of checks in
/// decode_request follows the state diagrams of §6: function, quantity/values, address).
constexpr exception_code exception_for(errc e) noexcept {
  switch (e) {
    case errc::modbus_illegal_function: return exception_code::illegal_function;
    case errc::modbus_address_overflow: return exception_code::illegal_data_address;
    default: return exception_code::illegal_data_value;
  }
}

namespace detail {

constexpr std::uint16_t be16(byte_view in, std::size_t at) noexcept {
  return static_cast<std::uint16_t>((in[at] << 8U) | in[at + 1U]);
}
constexpr void put_be16(mutable_byte_view out, std::size_t at, std::uint16_t v) noexcept {
  out[at] = static_cast<std::uint8_t>(v >> 8U);
  out[at + 1U] = static_cast<std::uint8_t>(v & 0xFFU);
}
/// Writes `values` big-endian from `out[at]` on; the caller has checked that they fit. One
/// pointer walks the output: g++ 12 -O3 sees the bound of this loop when it vectorises it
/// (indexing `out` per register made it warn -Wstringop-overflow about writes past a caller's
/// array that the size check above every call excludes).
constexpr void put_registers(mutable_byte_view out, std::size_t at,
                             span<const std::uint16_t> values) noexcept {
  std::uint8_t* p = out.data() + at;
  for (const std::uint16_t v : values) {
    *p++ = static_cast<std::uint8_t>(v >> 8U);
    *p++ = static_cast<std::uint8_t>(v & 0xFFU);
  }
}
/// The common 5-byte PDU: function code, then two big-endian words.
constexpr result<std::size_t> encode_two_words(std::uint8_t function, std::uint16_t first,
                                               std::uint16_t second,
                                               mutable_byte_view out) noexcept {
  if (out.size() < 5U) {
    return errc::buffer_too_small;
  }
  out[0] = function;
  put_be16(out, 1, first);
  put_be16(out, 3, second);
  return std::size_t{5};
}
constexpr bool is_read_bits(std::uint8_t f) noexcept {
  return f == 0x01 || f == 0x02;
}
constexpr bool is_read_registers(std::uint8_t f) noexcept {
  return f == 0x03 || f == 0x04;
}
constexpr std::size_t bytes_for_bits(std::size_t bits) noexcept {
  return (bits + 7U) / 8U;
}
constexpr bool overflows(std::uint16_t address, std::uint16_t quantity) noexcept {
  return static_cast<std::uint32_t>(address) + quantity > 0x10000U;
}

// Checks a read quantity: limits first (exception 03), then the address range (exception 02).
constexpr errc check_read(std::uint8_t f, std::uint16_t address, std::uint16_t quantity) noexcept {
  const std::uint16_t max = is_read_bits(f) ? max_read_bits : max_read_registers;
  if (quantity < 1U || quantity > max) {
    return errc::modbus_quantity;
  }
  return overflows(address, quantity) ? errc::modbus_address_overflow : errc::ok;
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// Client: requests

/// FC01/02/03/04: read `quantity` bits or registers from `address`. Errors: invalid_argument
/// (not a read function), modbus_quantity, modbus_address_overflow, buffer_too_small.
constexpr result<std::size_t> encode_read(function_code fc, std::uint16_t address,
                                          std::uint16_t quantity, mutable_byte_view out) noexcept {
  const auto f = static_cast<std::uint8_t>(fc);
  if (!detail::is_read_bits(f) && !detail::is_read_registers(f)) {
    return errc::invalid_argument;
  }
  const errc e = detail::check_read(f, address, quantity);
  if (e != errc::ok) {
    return e;
  }
  return detail::encode_two_words(f, address, quantity, out);
}

/// FC05: one coil on (0xFF00) or off (0x0000).
constexpr result<std::size_t> encode_write_single_coil(std::uint16_t address, bool on,
                                                       mutable_byte_view out) noexcept {
  return detail::encode_two_words(static_cast<std::uint8_t>(function_code::write_single_coil),
                                  address, on ? coil_on : coil_off, out);
}

/// FC06: one holding register.
constexpr result<std::size_t> encode_write_single_register(std::uint16_t address,
                                                           std::uint16_t value,
                                                           mutable_byte_view out) noexcept {
  return detail::encode_two_words(static_cast<std::uint8_t>(function_code::write_single_register),
                                  address, value, out);
}

/// FC0F: `quantity` coils from `packed` (LSB of the first byte first; unused high bits of the
/// last byte are sent as 0). Errors: modbus_quantity (1..1968), modbus_byte_count (`packed`
/// shorter than ceil(quantity/8)), modbus_address_overflow, buffer_too_small.
constexpr result<std::size_t> encode_write_multiple_coils(std::uint16_t address,
                                                          std::uint16_t quantity, byte_view packed,
                                                          mutable_byte_view out) noexcept {
  if (quantity < 1U || quantity > max_write_coils) {
    return errc::modbus_quantity;
  }
  const std::size_t n = detail::bytes_for_bits(quantity);
  if (packed.size() < n) {
    return errc::modbus_byte_count;
  }
  if (detail::overflows(address, quantity)) {
    return errc::modbus_address_overflow;
  }
  if (out.size() < 6U + n) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::write_multiple_coils);
  detail::put_be16(out, 1, address);
  detail::put_be16(out, 3, quantity);
  out[5] = static_cast<std::uint8_t>(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[6U + i] = packed[i];
  }
  const unsigned spare = static_cast<unsigned>(n * 8U - quantity);
  out[5U + n] = static_cast<std::uint8_t>(out[5U + n] & (0xFFU >> spare));
  return 6U + n;
}

/// FC10: registers `values` from `address`. Errors: modbus_quantity (1..123),
/// modbus_address_overflow, buffer_too_small.
constexpr result<std::size_t> encode_write_multiple_registers(std::uint16_t address,
                                                              span<const std::uint16_t> values,
                                                              mutable_byte_view out) noexcept {
  if (values.size() < 1U || values.size() > max_write_registers) {
    return errc::modbus_quantity;
  }
  const auto q = static_cast<std::uint16_t>(values.size());
  if (detail::overflows(address, q)) {
    return errc::modbus_address_overflow;
  }
  if (out.size() < 6U + 2U * values.size()) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::write_multiple_registers);
  detail::put_be16(out, 1, address);
  detail::put_be16(out, 3, q);
  out[5] = static_cast<std::uint8_t>(2U * q);
  detail::put_registers(out, 6, values);
  return 6U + 2U * values.size();
}

/// FC16: register = (register AND and_mask) OR (or_mask AND NOT and_mask).
constexpr result<std::size_t> encode_mask_write_register(std::uint16_t address,
                                                         std::uint16_t and_mask,
                                                         std::uint16_t or_mask,
                                                         mutable_byte_view out) noexcept {
  if (out.size() < 7U) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::mask_write_register);
  detail::put_be16(out, 1, address);
  detail::put_be16(out, 3, and_mask);
  detail::put_be16(out, 5, or_mask);
  return std::size_t{7};
}

/// FC17: write `values` at `write_address`, then read `read_quantity` registers from
/// `read_address`. Errors: modbus_quantity (read 1..125, write 1..121),
/// modbus_address_overflow, buffer_too_small.
constexpr result<std::size_t> encode_read_write_multiple_registers(std::uint16_t read_address,
                                                                   std::uint16_t read_quantity,
                                                                   std::uint16_t write_address,
                                                                   span<const std::uint16_t> values,
                                                                   mutable_byte_view out) noexcept {
  if (read_quantity < 1U || read_quantity > max_read_registers || values.size() < 1U ||
      values.size() > max_rw_write_registers) {
    return errc::modbus_quantity;
  }
  const auto wq = static_cast<std::uint16_t>(values.size());
  if (detail::overflows(read_address, read_quantity) || detail::overflows(write_address, wq)) {
    return errc::modbus_address_overflow;
  }
  if (out.size() < 10U + 2U * values.size()) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::read_write_multiple_registers);
  detail::put_be16(out, 1, read_address);
  detail::put_be16(out, 3, read_quantity);
  detail::put_be16(out, 5, write_address);
  detail::put_be16(out, 7, wq);
  out[9] = static_cast<std::uint8_t>(2U * wq);
  detail::put_registers(out, 10, values);
  return 10U + 2U * values.size();
}

/// Any function with an opaque data part (FC07, 0B, 0C, 11 with no data; custom functions).
/// Errors: invalid_argument (function 0 or with the exception flag), modbus_pdu_length,
/// buffer_too_small.
constexpr result<std::size_t> encode_raw(std::uint8_t function, byte_view data,
                                         mutable_byte_view out) noexcept {
  if (function == 0U || (function & exception_flag) != 0U) {
    return errc::invalid_argument;
  }
  if (1U + data.size() > max_pdu_size) {
    return errc::modbus_pdu_length;
  }
  if (out.size() < 1U + data.size()) {
    return errc::buffer_too_small;
  }
  out[0] = function;
  for (std::size_t i = 0; i < data.size(); ++i) {
    out[1U + i] = data[i];
  }
  return 1U + data.size();
}

/// FC08 diagnostics: sub-function and its data (2 bytes for all but 00, which echoes any even
/// number of bytes). Errors: modbus_illegal_function (undefined sub-function),
/// modbus_byte_count, modbus_pdu_length, buffer_too_small.
constexpr result<std::size_t> encode_diagnostics(std::uint16_t sub_function, byte_view data,
                                                 mutable_byte_view out) noexcept {
  if (!diagnostic::is_defined(sub_function)) {
    return errc::modbus_illegal_function;
  }
  if (sub_function == diagnostic::return_query_data ? data.size() % 2U != 0U : data.size() != 2U) {
    return errc::modbus_byte_count;
  }
  if (3U + data.size() > max_pdu_size) {
    return errc::modbus_pdu_length;
  }
  if (out.size() < 3U + data.size()) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::diagnostics);
  detail::put_be16(out, 1, sub_function);
  for (std::size_t i = 0; i < data.size(); ++i) {
    out[3U + i] = data[i];
  }
  return 3U + data.size();
}

/// FC18: read the FIFO queue at `address`.
constexpr result<std::size_t> encode_read_fifo_queue(std::uint16_t address,
                                                     mutable_byte_view out) noexcept {
  if (out.size() < 3U) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::read_fifo_queue);
  detail::put_be16(out, 1, address);
  return std::size_t{3};
}

/// FC2B / MEI 0E: read device identification (read code 1 basic, 2 regular, 3 extended,
/// 4 one object) from `object_id`. Errors: modbus_quantity (read code), buffer_too_small.
constexpr result<std::size_t> encode_read_device_identification(std::uint8_t read_code,
                                                                std::uint8_t object_id,
                                                                mutable_byte_view out) noexcept {
  if (read_code < 1U || read_code > 4U) {
    return errc::modbus_quantity;
  }
  if (out.size() < 4U) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::encapsulated_interface);
  out[1] = mei_read_device_identification;
  out[2] = read_code;
  out[3] = object_id;
  return std::size_t{4};
}

/// One object of a read-device-identification response.
struct device_object {
  std::uint8_t id = 0;
  byte_view value{};
};

/// The i-th object (0-based) of a checked FC2B/0E response's data; errc::out_of_range past the
/// last one.
constexpr result<device_object> object_at(const response& r, std::size_t index) noexcept {
  std::size_t at = 0;
  for (std::size_t k = 0; k < r.object_count; ++k) {
    if (at + 2U > r.data.size() || at + 2U + r.data[at + 1U] > r.data.size()) {
      return errc::modbus_byte_count;
    }
    if (k == index) {
      return device_object{r.data[at], r.data.subspan(at + 2U, r.data[at + 1U])};
    }
    at += 2U + r.data[at + 1U];
  }
  return errc::out_of_range;
}

// ---------------------------------------------------------------------------------------------
// Server: requests in, responses out

/// A set of function codes (bit f for function f, 1..63), for a server that decodes only the
/// functions its device serves: the others then cost no code (server dispatch passes the set
/// its device's accessors allow).
using function_set = std::uint64_t;
inline constexpr function_set all_functions = ~function_set{0};
/// Whether function `f` is in `Set` (two 32-bit halves: no 64-bit shift on a 32-bit core).
template <function_set Set>
constexpr bool in_function_set(std::uint8_t f) noexcept {
  constexpr auto low = static_cast<std::uint32_t>(Set);
  constexpr auto high = static_cast<std::uint32_t>(Set >> 32U);
  return f < 32U ? ((low >> f) & 1U) != 0U : (f < 64U && ((high >> (f - 32U)) & 1U) != 0U);
}
/// The set of the given function codes (each 1..63).
template <class... Codes>
constexpr function_set functions_of(Codes... codes) noexcept {
  return (function_set{0} | ... | (function_set{1} << (static_cast<unsigned>(codes) & 63U)));
}

/// Decodes a complete request PDU (e.g. an RTU ADU without address and CRC). Complete: the
/// request (consumed = PDU size). Failed (consumed = PDU size), in the order a server checks:
/// modbus_pdu_length (empty or > 253 bytes), modbus_illegal_function (exception flag set),
/// truncated (fewer bytes than the function's fixed part), modbus_quantity / modbus_byte_count /
/// modbus_coil_value (exception 03), modbus_address_overflow (exception 02). Extra bytes after
/// a fixed-size request are modbus_byte_count. Functions this codec does not frame decode as
/// raw (function and data).
template <function_set Served = all_functions>
constexpr decode_result<request> decode_request(byte_view pdu) noexcept {
  const std::size_t n = pdu.size();
  if (n < 1U || n > max_pdu_size) {
    return decode_failure{errc::modbus_pdu_length, n};
  }
  request q;
  q.function = pdu[0];
  const std::uint8_t f = q.function;
  if ((f & exception_flag) != 0U || f == 0U) {
    return decode_failure{errc::modbus_illegal_function, n};
  }
  // A function outside `Served` takes the raw branch below (the server answers 01); the
  // branches of functions outside it are compiled out.
  constexpr auto serves = [](unsigned code) { return ((Served >> code) & 1U) != 0U; };
  const bool served = in_function_set<Served>(f);
  auto need = [&](std::size_t fixed) { return n < fixed; };
  auto exact = [&](std::size_t size) -> errc {
    return n < size ? errc::truncated : (n > size ? errc::modbus_byte_count : errc::ok);
  };
  errc e = errc::ok;
  if ((serves(0x01) || serves(0x02) || serves(0x03) || serves(0x04)) && served &&
      (detail::is_read_bits(f) || detail::is_read_registers(f))) {
    e = exact(5);
    if (e == errc::ok) {
      q.address = detail::be16(pdu, 1);
      q.quantity = detail::be16(pdu, 3);
      e = detail::check_read(f, q.address, q.quantity);
    }
  } else if ((serves(0x05) || serves(0x06)) && served && (f == 0x05 || f == 0x06)) {
    e = exact(5);
    if (e == errc::ok) {
      q.address = detail::be16(pdu, 1);
      q.value = detail::be16(pdu, 3);
      if (f == 0x05 && q.value != coil_on && q.value != coil_off) {
        e = errc::modbus_coil_value;
      }
    }
  } else if ((serves(0x0F) || serves(0x10)) && served && (f == 0x0F || f == 0x10)) {
    if (need(6)) {
      e = errc::truncated;
    } else {
      q.address = detail::be16(pdu, 1);
      q.quantity = detail::be16(pdu, 3);
      const std::size_t count = pdu[5];
      const bool coils = f == 0x0F;
      const std::uint16_t max = coils ? max_write_coils : max_write_registers;
      const std::size_t want = coils ? detail::bytes_for_bits(q.quantity) : 2U * q.quantity;
      if (q.quantity < 1U || q.quantity > max) {
        e = errc::modbus_quantity;
      } else if (count != want || n != 6U + count) {
        e = errc::modbus_byte_count;
      } else if (detail::overflows(q.address, q.quantity)) {
        e = errc::modbus_address_overflow;
      } else {
        q.data = pdu.subspan(6, count);
      }
    }
  } else if (serves(0x16) && served && f == 0x16) {
    e = exact(7);
    if (e == errc::ok) {
      q.address = detail::be16(pdu, 1);
      q.and_mask = detail::be16(pdu, 3);
      q.or_mask = detail::be16(pdu, 5);
    }
  } else if (serves(0x17) && served && f == 0x17) {
    if (need(10)) {
      e = errc::truncated;
    } else {
      q.address = detail::be16(pdu, 1);
      q.quantity = detail::be16(pdu, 3);
      q.write_address = detail::be16(pdu, 5);
      q.write_quantity = detail::be16(pdu, 7);
      const std::size_t count = pdu[9];
      if (q.quantity < 1U || q.quantity > max_read_registers || q.write_quantity < 1U ||
          q.write_quantity > max_rw_write_registers) {
        e = errc::modbus_quantity;
      } else if (count != 2U * q.write_quantity || n != 10U + count) {
        e = errc::modbus_byte_count;
      } else if (detail::overflows(q.address, q.quantity) ||
                 detail::overflows(q.write_address, q.write_quantity)) {
        e = errc::modbus_address_overflow;
      } else {
        q.data = pdu.subspan(10, count);
      }
    }
  } else if ((serves(0x07) || serves(0x0B) || serves(0x0C) || serves(0x11)) && served &&
             (f == 0x07 || f == 0x0B || f == 0x0C || f == 0x11)) {
    e = exact(1);  // no data: a longer PDU is not read as if it had an address (§3.2 CVEs)
  } else if (serves(0x08) && served && f == 0x08) {
    if (need(3)) {
      e = errc::truncated;
    } else {
      q.sub_function = detail::be16(pdu, 1);
      q.data = pdu.subspan(3);
      if (!diagnostic::is_defined(q.sub_function)) {
        e = errc::modbus_illegal_function;  // §6.8: unsupported sub-function
      } else if (q.sub_function == diagnostic::return_query_data ? (q.data.size() % 2U != 0U)
                                                                 : (q.data.size() != 2U)) {
        e = errc::modbus_byte_count;
      } else if (q.sub_function == diagnostic::restart_communications &&
                 detail::be16(pdu, 3) != 0x0000U && detail::be16(pdu, 3) != 0xFF00U) {
        e = errc::modbus_coil_value;
      }
    }
  } else if (serves(0x18) && served && f == 0x18) {
    e = exact(3);
    if (e == errc::ok) {
      q.address = detail::be16(pdu, 1);
    }
  } else if (serves(0x2B) && served && f == 0x2B) {
    if (need(2)) {
      e = errc::truncated;
    } else {
      q.mei_type = pdu[1];
      if (q.mei_type != mei_read_device_identification) {
        q.data = pdu.subspan(2);  // other MEI types: the server's business
      } else {
        e = exact(4);
        if (e == errc::ok) {
          q.read_code = pdu[2];
          q.object_id = pdu[3];
          if (q.read_code < 1U || q.read_code > 4U) {
            e = errc::modbus_quantity;  // §6.21: illegal read device ID code → exception 03
          }
        }
      }
    }
  } else {
    q.data = pdu.subspan(1);  // raw: the server's own business
  }
  if (e != errc::ok) {
    return decode_failure{e, n};
  }
  return decode_result<request>::complete(q, n);
}

/// Exception response: function | 0x80, code (any code, passed through).
constexpr result<std::size_t> encode_exception(std::uint8_t function, std::uint8_t code,
                                               mutable_byte_view out) noexcept {
  if (out.size() < 2U) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function | exception_flag);
  out[1] = code;
  return std::size_t{2};
}

/// FC01/02 response: `quantity` bits from `packed`, unused high bits of the last byte cleared.
constexpr result<std::size_t> encode_read_bits_response(std::uint8_t function,
                                                        std::uint16_t quantity, byte_view packed,
                                                        mutable_byte_view out) noexcept {
  if (!detail::is_read_bits(function)) {
    return errc::invalid_argument;
  }
  if (quantity < 1U || quantity > max_read_bits) {
    return errc::modbus_quantity;
  }
  const std::size_t n = detail::bytes_for_bits(quantity);
  if (packed.size() < n) {
    return errc::modbus_byte_count;
  }
  if (out.size() < 2U + n) {
    return errc::buffer_too_small;
  }
  out[0] = function;
  out[1] = static_cast<std::uint8_t>(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[2U + i] = packed[i];
  }
  const unsigned spare = static_cast<unsigned>(n * 8U - quantity);
  out[1U + n] = static_cast<std::uint8_t>(out[1U + n] & (0xFFU >> spare));
  return 2U + n;
}

/// FC03/04/17 response: the registers `values`.
constexpr result<std::size_t> encode_read_registers_response(std::uint8_t function,
                                                             span<const std::uint16_t> values,
                                                             mutable_byte_view out) noexcept {
  if (!detail::is_read_registers(function) && function != 0x17U) {
    return errc::invalid_argument;
  }
  if (values.size() < 1U || values.size() > max_read_registers) {
    return errc::modbus_quantity;
  }
  if (out.size() < 2U + 2U * values.size()) {
    return errc::buffer_too_small;
  }
  out[0] = function;
  out[1] = static_cast<std::uint8_t>(2U * values.size());
  detail::put_registers(out, 2, values);
  return 2U + 2U * values.size();
}

/// The normal response to a write request (FC05, 06: the request echoed; FC0F, 10: function,
/// address, quantity; FC16: the request echoed). Other functions: invalid_argument.
constexpr result<std::size_t> encode_write_response(const request& q,
                                                    mutable_byte_view out) noexcept {
  const std::uint8_t f = q.function;
  if (f == 0x05 || f == 0x06 || f == 0x0F || f == 0x10) {
    return detail::encode_two_words(f, q.address, (f == 0x05 || f == 0x06) ? q.value : q.quantity,
                                    out);
  }
  if (f != 0x16) {
    return errc::invalid_argument;
  }
  return encode_mask_write_register(q.address, q.and_mask, q.or_mask, out);
}

/// FC07 response: the exception status byte.
constexpr result<std::size_t> encode_exception_status_response(std::uint8_t status,
                                                               mutable_byte_view out) noexcept {
  if (out.size() < 2U) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::read_exception_status);
  out[1] = status;
  return std::size_t{2};
}

/// FC0B response: status word (0xFFFF busy, 0x0000 ready) and event count.
constexpr result<std::size_t> encode_comm_event_counter_response(std::uint16_t status,
                                                                 std::uint16_t event_count,
                                                                 mutable_byte_view out) noexcept {
  return detail::encode_two_words(static_cast<std::uint8_t>(function_code::get_comm_event_counter),
                                  status, event_count, out);
}

/// FC0C response: status, event count, message count and 0..64 event bytes.
constexpr result<std::size_t> encode_comm_event_log_response(std::uint16_t status,
                                                             std::uint16_t event_count,
                                                             std::uint16_t message_count,
                                                             byte_view events,
                                                             mutable_byte_view out) noexcept {
  if (events.size() > 64U) {
    return errc::modbus_byte_count;
  }
  if (out.size() < 8U + events.size()) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::get_comm_event_log);
  out[1] = static_cast<std::uint8_t>(6U + events.size());
  detail::put_be16(out, 2, status);
  detail::put_be16(out, 4, event_count);
  detail::put_be16(out, 6, message_count);
  for (std::size_t i = 0; i < events.size(); ++i) {
    out[8U + i] = events[i];
  }
  return 8U + events.size();
}

/// FC18 response: the FIFO's 0..31 registers.
constexpr result<std::size_t> encode_fifo_response(span<const std::uint16_t> values,
                                                   mutable_byte_view out) noexcept {
  if (values.size() > max_fifo_count) {
    return errc::modbus_quantity;
  }
  if (out.size() < 5U + 2U * values.size()) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::read_fifo_queue);
  detail::put_be16(out, 1, static_cast<std::uint16_t>(2U + 2U * values.size()));
  detail::put_be16(out, 3, static_cast<std::uint16_t>(values.size()));
  detail::put_registers(out, 5, values);
  return 5U + 2U * values.size();
}

/// FC2B/0E response: header and `objects`, already laid out as (id, length, value)... as they
/// go on the wire, `object_count` of them. Errors: modbus_byte_count (objects do not parse to
/// exactly that count), modbus_pdu_length, buffer_too_small.
constexpr result<std::size_t> encode_device_identification_response(
    std::uint8_t read_code, std::uint8_t conformity, bool more_follows, std::uint8_t next_object,
    std::uint8_t object_count, byte_view objects, mutable_byte_view out) noexcept {
  std::size_t at = 0;
  for (unsigned k = 0; k < object_count; ++k) {
    if (at + 2U > objects.size() || at + 2U + objects[at + 1U] > objects.size()) {
      return errc::modbus_byte_count;
    }
    at += 2U + objects[at + 1U];
  }
  if (at != objects.size()) {
    return errc::modbus_byte_count;
  }
  if (7U + objects.size() > max_pdu_size) {
    return errc::modbus_pdu_length;
  }
  if (out.size() < 7U + objects.size()) {
    return errc::buffer_too_small;
  }
  out[0] = static_cast<std::uint8_t>(function_code::encapsulated_interface);
  out[1] = mei_read_device_identification;
  out[2] = read_code;
  out[3] = conformity;
  out[4] = more_follows ? std::uint8_t{0xFF} : std::uint8_t{0x00};
  out[5] = next_object;
  out[6] = object_count;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    out[7U + i] = objects[i];
  }
  return 7U + objects.size();
}

// ---------------------------------------------------------------------------------------------
// Client: responses in

namespace detail {

// The checks every response shares, in order: PDU length (modbus_pdu_length), the function
// echo (modbus_mismatch, evidence: sent and received function), and an exception response
// (exactly function | 0x80 and a code: complete with r.exception set). Returns true when they
// settle the outcome: `error` (with evidence), or ok for an exception response.
constexpr bool response_head(byte_view pdu, std::uint8_t function, response& r, errc& error,
                             std::uint32_t& expected, std::uint32_t& received) noexcept {
  const std::size_t n = pdu.size();
  if (n < 1U || n > max_pdu_size) {
    error = errc::modbus_pdu_length;
    return true;
  }
  r.function = static_cast<std::uint8_t>(pdu[0] & static_cast<std::uint8_t>(~exception_flag));
  if (r.function != function) {
    error = errc::modbus_mismatch;
    expected = function;
    received = r.function;
    return true;
  }
  if ((pdu[0] & exception_flag) != 0U) {
    if (n != 2U) {
      error = n < 2U ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.exception = true;
      r.exception_code = pdu[1];
    }
    return true;
  }
  return false;
}

}  // namespace detail

/// Client, one function: decodes the response PDU to a read of `quantity` bits (FC01, FC02)
/// or registers (FC03, FC04, and the read part of FC17) by `function`. Complete: r.data holds
/// the packed bits or register bytes, r.byte_count and r.quantity are set; an exception
/// response is complete with r.exception set. Failed (consumed = PDU size): modbus_pdu_length,
/// invalid_argument (`function` is not a read), modbus_mismatch (another function; expected =
/// sent, received = received function), truncated, modbus_byte_count (byte count vs quantity
/// vs bytes present), reserved_bits (unused high bits of the last bit byte set).
/// Links only what a client of these functions needs (decode_response handles every function
/// from the request bytes).
constexpr decode_result<response> decode_read_response(byte_view pdu, function_code function,
                                                       std::uint16_t quantity) noexcept {
  const auto f = static_cast<std::uint8_t>(function);
  const std::size_t n = pdu.size();
  if (!detail::is_read_bits(f) && !detail::is_read_registers(f) && f != 0x17U) {
    return decode_failure{errc::invalid_argument, n};
  }
  response r;
  errc e = errc::ok;
  std::uint32_t want = 0;
  std::uint32_t got = 0;
  if (!detail::response_head(pdu, f, r, e, want, got)) {
    const std::size_t bytes =
        detail::is_read_bits(f) ? detail::bytes_for_bits(quantity) : 2U * quantity;
    if (n < 2U) {
      e = errc::truncated;
    } else if (pdu[1] != bytes || n != 2U + bytes) {
      e = n < 2U + bytes && pdu[1] == bytes ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.byte_count = pdu[1];
      r.data = pdu.subspan(2, bytes);
      r.quantity = quantity;
      const unsigned spare = static_cast<unsigned>(bytes * 8U - quantity);
      if (detail::is_read_bits(f) && spare > 0U &&
          (r.data[bytes - 1U] & static_cast<std::uint8_t>(0xFFU << (8U - spare))) != 0U) {
        e = errc::reserved_bits;
      }
    }
  }
  if (e != errc::ok) {
    return decode_failure{e, n, want, got};
  }
  return decode_result<response>::complete(r, n);
}

/// Client, one function: decodes the response PDU to a write (FC05, FC06, FC0F, FC10) at
/// `address` of `second` (the value for FC05/06, the quantity for FC0F/10), which the response
/// must echo. Complete: r.address and r.value or r.quantity; an exception response is complete
/// with r.exception set. Failed (consumed = PDU size): modbus_pdu_length, invalid_argument
/// (`function` is not one of these), modbus_mismatch (another function, or an echo that
/// differs), truncated, modbus_byte_count (not 5 bytes).
constexpr decode_result<response> decode_write_response(byte_view pdu, function_code function,
                                                        std::uint16_t address,
                                                        std::uint16_t second) noexcept {
  const auto f = static_cast<std::uint8_t>(function);
  const std::size_t n = pdu.size();
  if (f != 0x05U && f != 0x06U && f != 0x0FU && f != 0x10U) {
    return decode_failure{errc::invalid_argument, n};
  }
  response r;
  errc e = errc::ok;
  std::uint32_t want = 0;
  std::uint32_t got = 0;
  if (!detail::response_head(pdu, f, r, e, want, got)) {
    if (n != 5U) {
      e = n < 5U ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.address = detail::be16(pdu, 1);
      const std::uint16_t echoed = detail::be16(pdu, 3);
      if (f == 0x05U || f == 0x06U) {
        r.value = echoed;
      } else {
        r.quantity = echoed;
      }
      if (r.address != address || echoed != second) {
        e = errc::modbus_mismatch;
      }
    }
  }
  if (e != errc::ok) {
    return decode_failure{e, n, want, got};
  }
  return decode_result<response>::complete(r, n);
}

namespace detail {

// The part of a response after the head (function echo, exception) for the functions other
// than the reads and writes with their own decoders, checked against the request `q` when there
// is one (nullptr: only what the response carries itself). Sets `e` on failure.
constexpr void response_body(byte_view pdu, std::uint8_t f, const request* q, report_id_format fc11,
                             response& r, errc& e) noexcept {
  const std::size_t n = pdu.size();
  if (is_read_bits(f) || is_read_registers(f) || f == 0x17U) {  // only when unpaired
    if (n < 2U) {
      e = errc::truncated;
    } else if (pdu[1] != n - 2U || (!is_read_bits(f) && pdu[1] % 2U != 0U)) {
      e = errc::modbus_byte_count;
    } else {
      r.byte_count = pdu[1];
      r.data = pdu.subspan(2);
      r.quantity = static_cast<std::uint16_t>(is_read_bits(f) ? 8U * pdu[1] : pdu[1] / 2U);
    }
  } else if (f == 0x05U || f == 0x06U || f == 0x0FU || f == 0x10U) {  // only when unpaired
    if (n != 5U) {
      e = n < 5U ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.address = be16(pdu, 1);
      (f == 0x05U || f == 0x06U ? r.value : r.quantity) = be16(pdu, 3);
    }
  } else if (f == 0x16) {
    if (n != 7U) {
      e = n < 7U ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.address = be16(pdu, 1);
      r.and_mask = be16(pdu, 3);
      r.or_mask = be16(pdu, 5);
      if (q != nullptr &&
          (r.address != q->address || r.and_mask != q->and_mask || r.or_mask != q->or_mask)) {
        e = errc::modbus_mismatch;
      }
    }
  } else if (f == 0x07) {
    if (n != 2U) {
      e = n < 2U ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.status = pdu[1];
    }
  } else if (f == 0x08) {
    if (n < 3U) {
      e = errc::truncated;
    } else {
      r.sub_function = be16(pdu, 1);
      r.data = pdu.subspan(3);
      if (q != nullptr && r.sub_function != q->sub_function) {
        e = errc::modbus_mismatch;
      } else if (r.sub_function == diagnostic::return_query_data) {
        // the query data echoed: exactly (paired), an even count (unpaired)
        if (q != nullptr ? r.data.size() != q->data.size() : r.data.size() % 2U != 0U) {
          e = errc::modbus_byte_count;
        } else if (q != nullptr) {
          for (std::size_t i = 0; i < r.data.size(); ++i) {
            if (r.data[i] != q->data[i]) {
              e = errc::modbus_mismatch;  // the echo must be exact
            }
          }
        }
      } else if (r.data.size() != 2U) {
        e = errc::modbus_byte_count;
      }
    }
  } else if (f == 0x0B) {
    if (n != 5U) {
      e = n < 5U ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.status = be16(pdu, 1);
      r.event_count = be16(pdu, 3);
    }
  } else if (f == 0x0C) {
    if (n < 8U) {
      e = errc::truncated;
    } else if (pdu[1] != n - 2U || pdu[1] > 6U + 64U) {
      e = errc::modbus_byte_count;
    } else {
      r.byte_count = pdu[1];
      r.status = be16(pdu, 2);
      r.event_count = be16(pdu, 4);
      r.message_count = be16(pdu, 6);
      r.data = pdu.subspan(8);
    }
  } else if (f == 0x18) {
    if (n < 5U) {
      e = errc::truncated;
    } else {
      const std::size_t count = be16(pdu, 1);
      r.fifo_count = be16(pdu, 3);
      if (r.fifo_count > max_fifo_count) {
        e = errc::modbus_quantity;
      } else if (count != 2U + 2U * r.fifo_count || n != 3U + count) {
        e = errc::modbus_byte_count;
      } else {
        r.data = pdu.subspan(5);
      }
    }
  } else if (f == 0x2B && (q != nullptr ? q->mei_type == mei_read_device_identification
                                        : n >= 2U && pdu[1] == mei_read_device_identification)) {
    if (n < 7U) {
      e = errc::truncated;
    } else if (pdu[1] != mei_read_device_identification ||
               (q != nullptr && pdu[2] != q->read_code)) {
      e = errc::modbus_mismatch;
    } else {
      r.conformity = pdu[3];
      r.more_follows = pdu[4] == 0xFFU;
      r.next_object = pdu[5];
      r.object_count = pdu[6];
      // every object's length must lie inside the PDU
      std::size_t at = 7;
      for (unsigned k = 0; k < r.object_count && e == errc::ok; ++k) {
        if (at + 2U > n || at + 2U + pdu[at + 1U] > n) {
          e = errc::modbus_byte_count;
        } else {
          at += 2U + pdu[at + 1U];
        }
      }
      if (e == errc::ok && at != n) {
        e = errc::modbus_byte_count;
      }
      r.data = pdu.subspan(7);
    }
  } else if (f == 0x11 && fc11 == report_id_format::standard) {
    if (n < 2U) {
      e = errc::truncated;
    } else if (pdu[1] != n - 2U) {
      e = errc::modbus_byte_count;
    } else {
      r.byte_count = pdu[1];
      r.data = pdu.subspan(2);
    }
  } else if (f == 0x11) {  // SM unit: exactly two bytes, no byte count
    if (n != 3U) {
      e = n < 3U ? errc::truncated : errc::modbus_byte_count;
    } else {
      r.data = pdu.subspan(1);
    }
  } else {
    r.data = pdu.subspan(1);  // raw
  }
}

}  // namespace detail

/// Decodes a complete response PDU to `sent` (the request as encoded, itself decodable).
/// Complete: the response; an exception response (function | 0x80, any code) is a complete
/// response with `exception` set. Failed (consumed = PDU size): modbus_pdu_length,
/// invalid_argument (`sent` is no valid request), modbus_mismatch (function or echoed fields
/// differ from the request), truncated, modbus_byte_count (byte count vs quantity vs bytes
/// present), reserved_bits (unused high bits of a bit response set).
/// `fc11`: the FC11 layout (report_id_format::two_bytes_no_count for the Tsubaki SM unit).
constexpr decode_result<response> decode_response(
    byte_view pdu, byte_view sent, report_id_format fc11 = report_id_format::standard) noexcept {
  const std::size_t n = pdu.size();
  if (n < 1U || n > max_pdu_size) {
    return decode_failure{errc::modbus_pdu_length, n};
  }
  const decode_result<request> dq = decode_request(sent);
  if (!dq.is_complete()) {
    return decode_failure{errc::invalid_argument, n};
  }
  const request& q = dq.value();
  const std::uint8_t f = q.function;
  if (detail::is_read_bits(f) || detail::is_read_registers(f) || f == 0x17U) {
    return decode_read_response(pdu, static_cast<function_code>(f), q.quantity);
  }
  if (f == 0x05U || f == 0x06U || f == 0x0FU || f == 0x10U) {
    const bool single = f == 0x05U || f == 0x06U;
    return decode_write_response(pdu, static_cast<function_code>(f), q.address,
                                 single ? q.value : q.quantity);
  }
  response r;
  errc e = errc::ok;
  std::uint32_t want = 0;
  std::uint32_t got = 0;
  if (!detail::response_head(pdu, f, r, e, want, got)) {
    detail::response_body(pdu, f, &q, fc11, r, e);
  }
  if (e != errc::ok) {
    return decode_failure{e, n, want, got};
  }
  return decode_result<response>::complete(r, n);
}

/// Decodes a response PDU seen without its request (a bus monitor, a log, a capture): every
/// check the response carries itself (byte counts against the bytes present, fixed sizes,
/// FC08 query data of even length, FC2B objects inside the PDU, the FC11 layout `fc11`), none
/// that needs the request (quantities, echoed fields). Bit reads report quantity = 8 x byte
/// count. Complete and failed as decode_response (no modbus_mismatch from echoes, no
/// invalid_argument, no reserved_bits).
constexpr decode_result<response> decode_response_unpaired(
    byte_view pdu, report_id_format fc11 = report_id_format::standard) noexcept {
  const std::size_t n = pdu.size();
  response r;
  errc e = errc::ok;
  std::uint32_t want = 0;
  std::uint32_t got = 0;
  const std::uint8_t f = n == 0U ? std::uint8_t{0} : static_cast<std::uint8_t>(pdu[0] & 0x7FU);
  if (!detail::response_head(pdu, f, r, e, want, got)) {
    detail::response_body(pdu, f, nullptr, fc11, r, e);
  }
  if (e != errc::ok) {
    return decode_failure{e, n, want, got};
  }
  return decode_result<response>::complete(r, n);
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_PDU_HPP
