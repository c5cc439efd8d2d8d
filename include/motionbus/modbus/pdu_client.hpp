// motionbus — the client's side of the Modbus PDU codec (MODBUS Application Protocol
// Specification V1.1b3 §6): encode_* build requests into a caller's buffer;
// decode_response_for(request, pdu) checks an answer against the request it belongs to (the
// request first, as in T-format's decode_response_for), and
// decode_response_unpaired(pdu) checks what a response carries on its own (a bus monitor).
// Vocabulary in modbus/pdu.hpp.
#ifndef MOTIONBUS_MODBUS_PDU_CLIENT_HPP
#define MOTIONBUS_MODBUS_PDU_CLIENT_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/file_record.hpp"
#include "motionbus/modbus/pdu.hpp"

namespace motionbus {
namespace modbus {

// ---------------------------------------------------------------------------------------------
// Client: requests

/// FC01/02/03/04: read `quantity` bits or registers from `address`. Errors: invalid_argument
/// (not a read function), modbus_quantity, modbus_address_overflow, buffer_too_small.
constexpr result<std::size_t> encode_read(std::uint8_t function, std::uint16_t address,
                                          std::uint16_t quantity, mutable_byte_view out) noexcept {
  const std::uint8_t f = function;
  if (!detail::is_read_bits(f) && !detail::is_read_registers(f)) {
    return errc::invalid_argument;
  }
  const errc e = detail::check_read(f, address, quantity);
  if (e != errc::ok) {
    return e;
  }
  return detail::encode_words(f, {address, quantity}, out);
}

/// FC05: one coil on (0xFF00) or off (0x0000).
constexpr result<std::size_t> encode_write_single_coil(std::uint16_t address, bool on,
                                                       mutable_byte_view out) noexcept {
  return detail::encode_words(function_code::write_single_coil, {address, on ? coil_on : coil_off},
                              out);
}

/// FC06: one holding register.
constexpr result<std::size_t> encode_write_single_register(std::uint16_t address,
                                                           std::uint16_t value,
                                                           mutable_byte_view out) noexcept {
  return detail::encode_words(function_code::write_single_register, {address, value}, out);
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
  return detail::encode_counted(
      function_code::write_multiple_coils, {address, quantity}, n, out,
      [&](std::size_t at) { (void)detail::copy_packed_bits(packed, quantity, out, at); });
}

/// FC10: registers `values` from `address`. Errors: modbus_quantity (1..123),
/// modbus_address_overflow, buffer_too_small.
constexpr result<std::size_t> encode_write_multiple_registers(std::uint16_t address,
                                                              span<const std::uint16_t> values,
                                                              mutable_byte_view out) noexcept {
  if (values.empty() || values.size() > max_write_registers) {
    return errc::modbus_quantity;
  }
  const auto q = static_cast<std::uint16_t>(values.size());
  if (detail::overflows(address, q)) {
    return errc::modbus_address_overflow;
  }
  return detail::encode_counted(function_code::write_multiple_registers, {address, q},
                                std::size_t{2} * q, out,
                                [&](std::size_t at) { detail::put_registers(out, at, values); });
}

/// FC16: register = (register AND and_mask) OR (or_mask AND NOT and_mask).
constexpr result<std::size_t> encode_mask_write_register(std::uint16_t address,
                                                         std::uint16_t and_mask,
                                                         std::uint16_t or_mask,
                                                         mutable_byte_view out) noexcept {
  return detail::encode_words(function_code::mask_write_register, {address, and_mask, or_mask},
                              out);
}

/// FC17: write `values` at `write_address`, then read `read_quantity` registers from
/// `read_address`. Errors: modbus_quantity (read 1..125, write 1..121),
/// modbus_address_overflow, buffer_too_small.
constexpr result<std::size_t> encode_read_write_multiple_registers(std::uint16_t read_address,
                                                                   std::uint16_t read_quantity,
                                                                   std::uint16_t write_address,
                                                                   span<const std::uint16_t> values,
                                                                   mutable_byte_view out) noexcept {
  if (read_quantity < 1U || read_quantity > max_read_registers || values.empty() ||
      values.size() > max_rw_write_registers) {
    return errc::modbus_quantity;
  }
  const auto wq = static_cast<std::uint16_t>(values.size());
  if (detail::overflows(read_address, read_quantity) || detail::overflows(write_address, wq)) {
    return errc::modbus_address_overflow;
  }
  return detail::encode_counted(function_code::read_write_multiple_registers,
                                {read_address, read_quantity, write_address, wq},
                                std::size_t{2} * wq, out,
                                [&](std::size_t at) { detail::put_registers(out, at, values); });
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
  out[0] = function_code::diagnostics;
  store_be16(out, 1, sub_function);
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
  out[0] = function_code::read_fifo_queue;
  store_be16(out, 1, address);
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
  out[0] = function_code::encapsulated_interface;
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
  if (index >= r.object_count) {
    return detail::walk_objects(r.data, 0, r.object_count).inside ? errc::out_of_range
                                                                  : errc::modbus_byte_count;
  }
  const std::size_t at = detail::walk_objects(r.data, 0, index).end;
  if (!detail::walk_objects(r.data, 0, index + 1U).inside) {
    return errc::modbus_byte_count;
  }
  return device_object{r.data[at], r.data.subspan(at + 2U, r.data[at + 1U])};
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
  if (!pdu_size_ok(n)) {
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
      error = detail::exact_size(n, 2U);
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
/// or registers (FC03, FC04, and the read part of FC17) by `function`: what was asked first,
/// the bytes that answer it last, as decode_response_for(sent, pdu). Complete: r.data holds
/// the packed bits or register bytes, r.byte_count and r.quantity are set; an exception
/// response is complete with r.exception set. Failed (consumed = PDU size): modbus_pdu_length,
/// invalid_argument (`function` is not a read), modbus_mismatch (another function; expected =
/// sent, received = received function), truncated, modbus_byte_count (byte count vs quantity
/// vs bytes present), reserved_bits (unused high bits of the last bit byte set).
/// Links only what a client of these functions needs (decode_response_for handles every function
/// from the request bytes).
constexpr decode_result<response> decode_read_response(std::uint8_t function,
                                                       std::uint16_t quantity,
                                                       byte_view pdu) noexcept {
  const std::uint8_t f = function;
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
        detail::is_read_bits(f) ? detail::bytes_for_bits(quantity) : std::size_t{2} * quantity;
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
/// must echo; what was asked first, the response PDU last. Complete: r.address and r.value or
/// r.quantity; an exception response is complete with r.exception set. Failed (consumed = PDU
/// size): modbus_pdu_length, invalid_argument (`function` is not one of these),
/// modbus_mismatch (another function, or an echo that differs), truncated, modbus_byte_count
/// (not 5 bytes).
constexpr decode_result<response> decode_write_response(std::uint8_t function,
                                                        std::uint16_t address, std::uint16_t second,
                                                        byte_view pdu) noexcept {
  const std::uint8_t f = function;
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
      e = detail::exact_size(n, 5U);
    } else {
      r.address = load_be16(pdu, 1);
      const std::uint16_t echoed = load_be16(pdu, 3);
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
      e = detail::exact_size(n, 5U);
    } else {
      r.address = load_be16(pdu, 1);
      (f == 0x05U || f == 0x06U ? r.value : r.quantity) = load_be16(pdu, 3);
    }
  } else if (f == 0x16) {
    if (n != 7U) {
      e = detail::exact_size(n, 7U);
    } else {
      r.address = load_be16(pdu, 1);
      r.and_mask = load_be16(pdu, 3);
      r.or_mask = load_be16(pdu, 5);
      if (q != nullptr &&
          (r.address != q->address || r.and_mask != q->and_mask || r.or_mask != q->or_mask)) {
        e = errc::modbus_mismatch;
      }
    }
  } else if (f == 0x07) {
    if (n != 2U) {
      e = detail::exact_size(n, 2U);
    } else {
      r.status = pdu[1];
    }
  } else if (f == 0x08) {
    if (n < 3U) {
      e = errc::truncated;
    } else {
      r.sub_function = load_be16(pdu, 1);
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
      e = detail::exact_size(n, 5U);
    } else {
      r.status = load_be16(pdu, 1);
      r.event_count = load_be16(pdu, 3);
    }
  } else if (f == 0x0C) {
    if (n < 8U) {
      e = errc::truncated;
    } else if (pdu[1] != n - 2U || pdu[1] > 6U + 64U) {
      e = errc::modbus_byte_count;
    } else {
      r.byte_count = pdu[1];
      r.status = load_be16(pdu, 2);
      r.event_count = load_be16(pdu, 4);
      r.message_count = load_be16(pdu, 6);
      r.data = pdu.subspan(8);
    }
  } else if (f == 0x18) {
    if (n < 5U) {
      e = errc::truncated;
    } else {
      const std::size_t count = load_be16(pdu, 1);
      r.fifo_count = load_be16(pdu, 3);
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
      // every object inside the PDU, and nothing after the last
      const detail::object_walk w = detail::walk_objects(pdu, 7, r.object_count);
      if (!w.inside || w.end != n) {
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
      e = detail::exact_size(n, 3U);
    } else {
      r.data = pdu.subspan(1);
    }
  } else {
    r.data = pdu.subspan(1);  // raw
  }
}

}  // namespace detail

/// Decodes a complete response PDU to `sent` (the request as encoded, itself decodable): the
/// request first, the bytes that answer it second, as tformat::decode_response_for.
/// Complete: the response; an exception response (function | 0x80, any code) is a complete
/// response with `exception` set. Failed (consumed = PDU size): modbus_pdu_length,
/// invalid_argument (`sent` is no valid request), modbus_mismatch (function or echoed fields
/// differ from the request), truncated, modbus_byte_count (byte count vs quantity vs bytes
/// present), reserved_bits (unused high bits of a bit response set).
/// `fc11`: the FC11 layout (report_id_format::two_bytes_no_count for the Tsubaki SM unit).
constexpr decode_result<response> decode_response_for(
    byte_view sent, byte_view pdu, report_id_format fc11 = report_id_format::standard) noexcept {
  const std::size_t n = pdu.size();
  if (!pdu_size_ok(n)) {
    return decode_failure{errc::modbus_pdu_length, n};
  }
  const decode_result<request> dq = decode_request(sent);
  if (!dq.is_complete()) {
    return decode_failure{errc::invalid_argument, n};
  }
  const request& q = dq.value();
  const std::uint8_t f = q.function;
  if (detail::is_read_bits(f) || detail::is_read_registers(f) || f == 0x17U) {
    return decode_read_response(f, q.quantity, pdu);
  }
  if (f == 0x05U || f == 0x06U || f == 0x0FU || f == 0x10U) {
    const bool single = f == 0x05U || f == 0x06U;
    return decode_write_response(f, q.address, single ? q.value : q.quantity, pdu);
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
/// count. Complete and failed as decode_response_for (no modbus_mismatch from echoes, no
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

// ---------------------------------------------------------------------------------------------
// Client: file records, FC14 and FC15 (Modbus App. Protocol §6.14, §6.15; modbus/file_record.hpp)

namespace detail {

// The checks of an FC14/15 request to encode, in the decoder's order (03 before 02): returns
// the request's size. Errors: modbus_pdu_length (no sub-request, or more than the PDU holds),
// modbus_quantity (a length of 0, or an FC14 response past 253 bytes), modbus_byte_count
// (FC15 data not 2 x length bytes), then the fields (modbus_reference_type never: the encoder
// writes 6; modbus_file_number, modbus_record_number).
constexpr result<std::size_t> check_file_request(std::uint8_t f,
                                                 span<const file_record> records) noexcept {
  const bool read = f == read_file_record_function;
  std::size_t size = 2;
  std::size_t reply = 2;
  for (const file_record& rec : records) {
    size += file_part_size(f, false, rec.length);
    reply += 2U + 2U * std::size_t{rec.length};
    if (rec.length == 0U || (read && reply > max_pdu_size)) {
      return errc::modbus_quantity;
    }
    if (!read && rec.data.size() != 2U * std::size_t{rec.length}) {
      return errc::modbus_byte_count;
    }
  }
  if (records.empty() || size > max_pdu_size) {
    return errc::modbus_pdu_length;
  }
  for (const file_record& rec : records) {
    const errc e = check_file_fields(file_reference_type, rec.file, rec.record, rec.length);
    if (e != errc::ok) {
      return e;
    }
  }
  return size;
}

constexpr result<std::size_t> encode_file_request(std::uint8_t f, span<const file_record> records,
                                                  mutable_byte_view out) noexcept {
  const result<std::size_t> size = check_file_request(f, records);
  if (!size.ok()) {
    return size;
  }
  if (out.size() < size.value()) {
    return errc::buffer_too_small;
  }
  out[0] = f;
  out[1] = static_cast<std::uint8_t>(size.value() - 2U);
  std::size_t at = 2;
  for (const file_record& rec : records) {
    out[at] = file_reference_type;
    store_be16(out, at + 1U, rec.file);
    store_be16(out, at + 3U, rec.record);
    store_be16(out, at + 5U, rec.length);
    at += file_subrequest_size;
    if (f == write_file_record_function) {
      for (std::size_t i = 0; i < rec.data.size(); ++i) {
        out[at + i] = rec.data[i];
      }
      at += rec.data.size();
    }
  }
  return size;
}

// The response head of FC14/15 against the request `sent`: sets `q` to the decoded request
// and returns true when the head settles the outcome (a failure in `fail`, or an exception
// response in `r`).
constexpr bool file_response_head(std::uint8_t f, byte_view sent, byte_view pdu, file_records& q,
                                  file_records& r, decode_failure& fail) noexcept {
  fail.consumed = pdu.size();
  if (!pdu_size_ok(pdu.size())) {
    fail.code = errc::modbus_pdu_length;
    return true;
  }
  const decode_result<file_records> dq = decode_file_record_request(sent);
  if (!dq.is_complete() || dq.value().function != f) {
    fail.code = errc::invalid_argument;
    return true;
  }
  q = dq.value();
  response head;
  errc e = errc::ok;
  if (response_head(pdu, f, head, e, fail.expected, fail.received)) {
    fail.code = e;
    r.function = f;
    r.response = true;
    r.exception = head.exception;
    r.exception_code = head.exception_code;
    return true;
  }
  return false;
}

}  // namespace detail

/// FC14: read the sub-requests `records` (file, record, length; data unused). Errors:
/// modbus_quantity (a length of 0, or a response that would pass 253 bytes),
/// modbus_pdu_length (none, or more than 35), modbus_file_number (0), modbus_record_number
/// (past 0x270F), buffer_too_small.
constexpr result<std::size_t> encode_read_file_record(span<const file_record> records,
                                                      mutable_byte_view out) noexcept {
  return detail::encode_file_request(read_file_record_function, records, out);
}

/// FC15: write the sub-requests `records` (file, record, length and 2 x length bytes of
/// big-endian registers in data). Errors: as encode_read_file_record, and modbus_byte_count (data
/// not 2 x length bytes), modbus_pdu_length (more than 253 bytes).
constexpr result<std::size_t> encode_write_file_record(span<const file_record> records,
                                                       mutable_byte_view out) noexcept {
  return detail::encode_file_request(write_file_record_function, records, out);
}

/// Client: decodes the response PDU to the FC14 request `sent` (as encoded): the request first.
/// Complete: the records read (file_record_at: the request's file and record, the response's
/// data); an exception response is complete with exception set. Failed (consumed = PDU size):
/// modbus_pdu_length, invalid_argument (`sent` is no valid FC14 request), modbus_mismatch
/// (another function; or sub-responses of other lengths or in another number than requested),
/// truncated (fewer bytes than the data length says), modbus_byte_count (more; a sub-response
/// whose length is even, below 3, or runs past the data), modbus_reference_type (not 6).
constexpr decode_result<file_records> decode_read_file_record_response(byte_view sent,
                                                                       byte_view pdu) noexcept {
  file_records q;
  file_records r;
  decode_failure fail;
  if (detail::file_response_head(read_file_record_function, sent, pdu, q, r, fail)) {
    if (fail.code == errc::ok) {
      return decode_result<file_records>::complete(r, pdu.size());
    }
    return fail;
  }
  const std::size_t n = pdu.size();
  errc e = errc::ok;
  if (n < 2U) {
    e = errc::truncated;
  } else if (pdu[1] != n - 2U) {
    e = pdu[1] > n - 2U ? errc::truncated : errc::modbus_byte_count;
  }
  std::size_t k = 0;
  std::size_t req = 0;  // in q.body
  for (std::size_t at = 2; e == errc::ok && at < n; ++k) {
    const std::size_t length = pdu[at];
    if (at + 2U > n || length < 3U || length % 2U == 0U || at + 1U + length > n) {
      e = errc::modbus_byte_count;
    } else if (pdu[at + 1U] != file_reference_type) {
      e = errc::modbus_reference_type;
    } else if (k >= q.count || length != 1U + 2U * std::size_t{load_be16(q.body, req + 5U)}) {
      e = errc::modbus_mismatch;  // not the records asked for
    }
    at += 1U + length;
    req += file_subrequest_size;
  }
  if (e == errc::ok && k != q.count) {
    e = errc::modbus_mismatch;  // fewer sub-responses than sub-requests
  }
  if (e != errc::ok) {
    return decode_failure{e, n};
  }
  r = q;
  r.body = pdu.subspan(2);
  r.response = true;
  return decode_result<file_records>::complete(r, n);
}

/// Client: decodes the response PDU to the FC15 request `sent` (as encoded), which must echo it.
/// Complete: the records written; an exception response is complete with exception set. Failed
/// (consumed = PDU size): modbus_pdu_length, invalid_argument (`sent` is no valid FC15
/// request), the request decoder's errors for a response that is no valid FC15 PDU itself,
/// modbus_mismatch (another function, or not the request's bytes).
constexpr decode_result<file_records> decode_write_file_record_response(byte_view sent,
                                                                        byte_view pdu) noexcept {
  file_records q;
  file_records r;
  decode_failure fail;
  if (detail::file_response_head(write_file_record_function, sent, pdu, q, r, fail)) {
    if (fail.code == errc::ok) {
      return decode_result<file_records>::complete(r, pdu.size());
    }
    return fail;
  }
  const std::size_t n = pdu.size();
  const decode_result<file_records> echo = decode_file_record_request(pdu);
  if (!echo.is_complete()) {
    return decode_failure{echo.error(), n};
  }
  bool same = n == sent.size();
  for (std::size_t i = 0; same && i < n; ++i) {
    same = pdu[i] == sent[i];
  }
  if (!same) {
    return decode_failure{errc::modbus_mismatch, n};
  }
  r = echo.value();
  r.response = true;
  return decode_result<file_records>::complete(r, n);
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_PDU_CLIENT_HPP
