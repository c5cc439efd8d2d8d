// motionbus — the Modbus PDU vocabulary shared by both roles (MODBUS Application Protocol
// Specification V1.1b3): function and exception codes, the limits of each function, the
// decoded `request` and `response`, function sets, and the helpers both sides use.
//
// decode_request(pdu) is here: a server decodes what it receives with it, and a client what it
// sent, to check the answer against it. It enforces every limit of the specification and says
// which exception a server answers (exception_for); decode_request<function_set> compiles
// only the functions a device serves. The rest is in one header per role:
//   modbus/pdu_client.hpp  requests out (encode_*), responses in (decode_response_for)
//   modbus/pdu_server.hpp  responses out (encode_*_response, encode_exception)
// PDUs are function code + data, at most 253 bytes; register values are big-endian on the
// wire. Decoded values that carry data (packed coils, register bytes, opaque payloads) are
// views into the caller's input: valid while that buffer is.
// Implemented: 01, 02, 03, 04, 05, 06, 07, 08 (all defined sub-functions), 0B, 0C, 0F, 10, 11,
// 16, 17, 18, 2B/0E (read device identification), exception responses with any code, and a raw
// path for any other function code. FC14/15 (file records, decoded raw here) in
// modbus/file_record.hpp.
#ifndef MOTIONBUS_MODBUS_PDU_HPP
#define MOTIONBUS_MODBUS_PDU_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/bytes.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"

namespace motionbus {
namespace modbus {

inline constexpr std::size_t max_pdu_size = 253;

/// Whether a PDU of `n` bytes fits the specification: 1..253 (Application Protocol §4.1). One
/// check for every PDU decoder and encoder, the RTU framing (address and CRC around the PDU)
/// and TCP (the unit identifier before it).
constexpr bool pdu_size_ok(std::size_t n) noexcept {
  return n >= 1U && n <= max_pdu_size;
}

/// Function codes (Application Protocol §6): `function_code::read_holding_registers` is the
/// byte 0x03. Every function code a codec takes or returns is a std::uint8_t (any byte can
/// arrive on the wire, and a server answers the ones it does not know); these name them.
struct function_code {
  static constexpr std::uint8_t read_coils = 0x01;
  static constexpr std::uint8_t read_discrete_inputs = 0x02;
  static constexpr std::uint8_t read_holding_registers = 0x03;
  static constexpr std::uint8_t read_input_registers = 0x04;
  static constexpr std::uint8_t write_single_coil = 0x05;
  static constexpr std::uint8_t write_single_register = 0x06;
  static constexpr std::uint8_t read_exception_status = 0x07;
  static constexpr std::uint8_t diagnostics = 0x08;
  static constexpr std::uint8_t get_comm_event_counter = 0x0B;
  static constexpr std::uint8_t get_comm_event_log = 0x0C;
  static constexpr std::uint8_t write_multiple_coils = 0x0F;
  static constexpr std::uint8_t write_multiple_registers = 0x10;
  static constexpr std::uint8_t report_server_id = 0x11;
  static constexpr std::uint8_t mask_write_register = 0x16;
  static constexpr std::uint8_t read_write_multiple_registers = 0x17;
  static constexpr std::uint8_t read_fifo_queue = 0x18;
  static constexpr std::uint8_t encapsulated_interface = 0x2B;
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
// inline: one load and a byte swap, inside every server's register loop.
MOTIONBUS_INLINE constexpr std::uint16_t register_at(byte_view bytes, std::size_t i) noexcept {
  return load_be16(bytes, 2U * i);
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
    case errc::modbus_address_overflow:
    case errc::modbus_reference_type:  // FC14/15 sub-requests (§6.14, §6.15)
    case errc::modbus_file_number:
    case errc::modbus_record_number: return exception_code::illegal_data_address;
    default: return exception_code::illegal_data_value;
  }
}

namespace detail {

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
/// The fixed-size PDUs: the function code, then N big-endian words (a read request, FC05/06
/// and their echo, the FC0F/10 response: 2; FC16 and its echo: 3).
template <std::size_t N>
constexpr result<std::size_t> encode_words(std::uint8_t function, const std::uint16_t (&words)[N],
                                           mutable_byte_view out) noexcept {
  if (out.size() < 1U + 2U * N) {
    return errc::buffer_too_small;
  }
  out[0] = function;
  MOTIONBUS_UNROLL(3)
  for (std::size_t i = 0; i < N; ++i) {
    store_be16(out, 1U + 2U * i, words[i]);
  }
  return std::size_t{1U + 2U * N};
}
/// Copies the ceil(quantity / 8) bytes of packed bits from `packed` to `out[at]`, the unused
/// high bits of the last byte cleared (FC0F requests, FC01/02 responses); returns the bytes
/// copied. The caller has checked both sizes.
constexpr std::size_t copy_packed_bits(byte_view packed, std::uint16_t quantity,
                                       mutable_byte_view out, std::size_t at) noexcept {
  const std::size_t n = (quantity + 7U) / 8U;
  for (std::size_t i = 0; i < n; ++i) {
    out[at + i] = packed[i];
  }
  const unsigned spare = static_cast<unsigned>(n * 8U - quantity);
  out[at + n - 1U] = static_cast<std::uint8_t>(out[at + n - 1U] & (0xFFU >> spare));
  return n;
}
/// A PDU of `n` bytes that must be exactly `size` long: ok, truncated (fewer bytes) or
/// modbus_byte_count (more: a longer PDU is never read as if its extra bytes meant something).
constexpr errc exact_size(std::size_t n, std::size_t size) noexcept {
  return n < size ? errc::truncated : (n > size ? errc::modbus_byte_count : errc::ok);
}
/// The FC2B/0E objects (id, length, value...), `count` of them laid out from `in[at]`: where
/// they end, and whether all of them lie inside `in`. When one does not, `end` is where that
/// object would end if its header is there (a lower bound of the bytes needed), else where its
/// header starts. One walk for the framer's length rule, the response checks, object_at and
/// the response encoder.
struct object_walk {
  std::size_t end = 0;
  bool inside = true;
};
constexpr object_walk walk_objects(byte_view in, std::size_t at, std::size_t count) noexcept {
  for (std::size_t k = 0; k < count; ++k) {
    if (at + 2U > in.size()) {
      return {at, false};
    }
    const std::size_t next = at + 2U + in[at + 1U];
    if (next > in.size()) {
      return {next, false};
    }
    at = next;
  }
  return {at, true};
}
/// The requests with a payload: the function code, N big-endian words, a byte count, then
/// `count` bytes written by `put(at)` from `out[at]` (FC0F coils, FC10 and FC17 registers). The
/// caller has checked the values; this checks the room.
template <std::size_t N, class Put>
constexpr result<std::size_t> encode_counted(std::uint8_t function, const std::uint16_t (&words)[N],
                                             std::size_t count, mutable_byte_view out,
                                             Put&& put) noexcept {
  constexpr std::size_t at = 2U + 2U * N;
  if (out.size() < at + count) {
    return errc::buffer_too_small;
  }
  out[0] = function;
  for (std::size_t i = 0; i < N; ++i) {
    store_be16(out, 1U + 2U * i, words[i]);
  }
  out[at - 1U] = static_cast<std::uint8_t>(count);
  put(at);
  return at + count;
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
// inline: a few compares that fold to one with the caller's constant function code.
MOTIONBUS_INLINE constexpr errc check_read(std::uint8_t f, std::uint16_t address,
                                           std::uint16_t quantity) noexcept {
  const std::uint16_t max = is_read_bits(f) ? max_read_bits : max_read_registers;
  if (quantity < 1U || quantity > max) {
    return errc::modbus_quantity;
  }
  return overflows(address, quantity) ? errc::modbus_address_overflow : errc::ok;
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// Function sets

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

// ---------------------------------------------------------------------------------------------
// Requests: decoded by a server from what it receives, and by a client from what it sent (to
// check the answer against it)

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
  if (!pdu_size_ok(n)) {
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
  errc e = errc::ok;
  if ((serves(0x01) || serves(0x02) || serves(0x03) || serves(0x04)) && served &&
      (detail::is_read_bits(f) || detail::is_read_registers(f))) {
    e = detail::exact_size(n, 5);
    if (e == errc::ok) {
      q.address = load_be16(pdu, 1);
      q.quantity = load_be16(pdu, 3);
      e = detail::check_read(f, q.address, q.quantity);
    }
  } else if ((serves(0x05) || serves(0x06)) && served && (f == 0x05 || f == 0x06)) {
    e = detail::exact_size(n, 5);
    if (e == errc::ok) {
      q.address = load_be16(pdu, 1);
      q.value = load_be16(pdu, 3);
      if (f == 0x05 && q.value != coil_on && q.value != coil_off) {
        e = errc::modbus_coil_value;
      }
    }
  } else if ((serves(0x0F) || serves(0x10)) && served && (f == 0x0F || f == 0x10)) {
    if (need(6)) {
      e = errc::truncated;
    } else {
      q.address = load_be16(pdu, 1);
      q.quantity = load_be16(pdu, 3);
      const std::size_t count = pdu[5];
      const bool coils = f == 0x0F;
      const std::uint16_t max = coils ? max_write_coils : max_write_registers;
      const std::size_t want =
          coils ? detail::bytes_for_bits(q.quantity) : std::size_t{2} * q.quantity;
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
    e = detail::exact_size(n, 7);
    if (e == errc::ok) {
      q.address = load_be16(pdu, 1);
      q.and_mask = load_be16(pdu, 3);
      q.or_mask = load_be16(pdu, 5);
    }
  } else if (serves(0x17) && served && f == 0x17) {
    if (need(10)) {
      e = errc::truncated;
    } else {
      q.address = load_be16(pdu, 1);
      q.quantity = load_be16(pdu, 3);
      q.write_address = load_be16(pdu, 5);
      q.write_quantity = load_be16(pdu, 7);
      const std::size_t count = pdu[9];
      if (q.quantity < 1U || q.quantity > max_read_registers || q.write_quantity < 1U ||
          q.write_quantity > max_rw_write_registers) {
        e = errc::modbus_quantity;
      } else if (count != std::size_t{2} * q.write_quantity || n != 10U + count) {
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
    e = detail::exact_size(
        n, 1);  // no data: a longer PDU is not read as if it had an address (§3.2 CVEs)
  } else if (serves(0x08) && served && f == 0x08) {
    if (need(3)) {
      e = errc::truncated;
    } else {
      q.sub_function = load_be16(pdu, 1);
      q.data = pdu.subspan(3);
      if (!diagnostic::is_defined(q.sub_function)) {
        e = errc::modbus_illegal_function;  // §6.8: unsupported sub-function
      } else if (q.sub_function == diagnostic::return_query_data ? (q.data.size() % 2U != 0U)
                                                                 : (q.data.size() != 2U)) {
        e = errc::modbus_byte_count;
      } else if (q.sub_function == diagnostic::restart_communications &&
                 load_be16(pdu, 3) != 0x0000U && load_be16(pdu, 3) != 0xFF00U) {
        e = errc::modbus_coil_value;
      }
    }
  } else if (serves(0x18) && served && f == 0x18) {
    e = detail::exact_size(n, 3);
    if (e == errc::ok) {
      q.address = load_be16(pdu, 1);
    }
  } else if (serves(0x2B) && served && f == 0x2B) {
    if (need(2)) {
      e = errc::truncated;
    } else {
      q.mei_type = pdu[1];
      if (q.mei_type != mei_read_device_identification) {
        q.data = pdu.subspan(2);  // other MEI types: the server's business
      } else {
        e = detail::exact_size(n, 4);
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

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_PDU_HPP
