// motionbus — the server's side of the Modbus PDU codec (MODBUS Application Protocol
// Specification V1.1b3 §6, §7): encode_*_response and encode_exception build the reply to a
// request that decode_request (modbus/pdu.hpp) decoded and checked; exception_for says which
// exception a decoding error is answered with. Dispatch over a device in modbus/server.hpp.
#ifndef MOTIONBUS_MODBUS_PDU_SERVER_HPP
#define MOTIONBUS_MODBUS_PDU_SERVER_HPP

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
// Server: responses out (requests are decoded by decode_request, modbus/pdu.hpp)

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
  return 2U + detail::copy_packed_bits(packed, quantity, out, 2);
}

/// FC03/04/17 response: the registers `values`.
constexpr result<std::size_t> encode_read_registers_response(std::uint8_t function,
                                                             span<const std::uint16_t> values,
                                                             mutable_byte_view out) noexcept {
  if (!detail::is_read_registers(function) && function != 0x17U) {
    return errc::invalid_argument;
  }
  if (values.empty() || values.size() > max_read_registers) {
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
    return detail::encode_words(f, {q.address, (f == 0x05 || f == 0x06) ? q.value : q.quantity},
                                out);
  }
  if (f != 0x16) {
    return errc::invalid_argument;
  }
  return detail::encode_words(f, {q.address, q.and_mask, q.or_mask}, out);
}

/// FC07 response: the exception status byte.
constexpr result<std::size_t> encode_exception_status_response(std::uint8_t status,
                                                               mutable_byte_view out) noexcept {
  if (out.size() < 2U) {
    return errc::buffer_too_small;
  }
  out[0] = function_code::read_exception_status;
  out[1] = status;
  return std::size_t{2};
}

/// FC0B response: status word (0xFFFF busy, 0x0000 ready) and event count.
constexpr result<std::size_t> encode_comm_event_counter_response(std::uint16_t status,
                                                                 std::uint16_t event_count,
                                                                 mutable_byte_view out) noexcept {
  return detail::encode_words(function_code::get_comm_event_counter, {status, event_count}, out);
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
  out[0] = function_code::get_comm_event_log;
  out[1] = static_cast<std::uint8_t>(6U + events.size());
  store_be16(out, 2, status);
  store_be16(out, 4, event_count);
  store_be16(out, 6, message_count);
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
  out[0] = function_code::read_fifo_queue;
  store_be16(out, 1, static_cast<std::uint16_t>(2U + 2U * values.size()));
  store_be16(out, 3, static_cast<std::uint16_t>(values.size()));
  detail::put_registers(out, 5, values);
  return 5U + 2U * values.size();
}

/// FC2B/0E response: header and `objects`, already laid out as (id, length, value)... as they
/// go on the wire, `object_count` of them. Errors: modbus_byte_count (objects do not parse to
/// exactly that count), modbus_pdu_length, buffer_too_small.
constexpr result<std::size_t> encode_device_identification_response(
    std::uint8_t read_code, std::uint8_t conformity, bool more_follows, std::uint8_t next_object,
    std::uint8_t object_count, byte_view objects, mutable_byte_view out) noexcept {
  const detail::object_walk w = detail::walk_objects(objects, 0, object_count);
  if (!w.inside || w.end != objects.size()) {
    return errc::modbus_byte_count;
  }
  if (7U + objects.size() > max_pdu_size) {
    return errc::modbus_pdu_length;
  }
  if (out.size() < 7U + objects.size()) {
    return errc::buffer_too_small;
  }
  out[0] = function_code::encapsulated_interface;
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
// Server: file records, FC14 and FC15 (Modbus App. Protocol §6.14, §6.15; requests decoded by
// decode_file_record_request, modbus/file_record.hpp)

/// FC14 response: per record read, its length (1 + bytes), reference type 6 and `data` (its
/// registers, big-endian; file, record and length unused). Errors: modbus_byte_count (data
/// empty or of an odd size), modbus_pdu_length (none, or past 253 bytes), buffer_too_small.
constexpr result<std::size_t> encode_read_file_record_response(span<const file_record> records,
                                                               mutable_byte_view out) noexcept {
  std::size_t size = 2;
  for (const file_record& rec : records) {
    if (rec.data.empty() || rec.data.size() % 2U != 0U) {
      return errc::modbus_byte_count;
    }
    size += 2U + rec.data.size();
  }
  if (records.empty() || size > max_pdu_size) {
    return errc::modbus_pdu_length;
  }
  if (out.size() < size) {
    return errc::buffer_too_small;
  }
  out[0] = read_file_record_function;
  out[1] = static_cast<std::uint8_t>(size - 2U);
  std::size_t at = 2;
  for (const file_record& rec : records) {
    out[at] = static_cast<std::uint8_t>(1U + rec.data.size());
    out[at + 1U] = file_reference_type;
    for (std::size_t i = 0; i < rec.data.size(); ++i) {
      out[at + 2U + i] = rec.data[i];
    }
    at += 2U + rec.data.size();
  }
  return size;
}

/// FC15 response: the request `q` (decode_file_record_request) echoed. Errors:
/// invalid_argument (q is no FC15 request), buffer_too_small.
constexpr result<std::size_t> encode_write_file_record_response(const file_records& q,
                                                                mutable_byte_view out) noexcept {
  if (q.function != write_file_record_function || q.response) {
    return errc::invalid_argument;
  }
  const std::size_t size = 2U + q.body.size();
  if (out.size() < size) {
    return errc::buffer_too_small;
  }
  out[0] = write_file_record_function;
  out[1] = static_cast<std::uint8_t>(q.body.size());
  for (std::size_t i = 0; i < q.body.size(); ++i) {
    out[2U + i] = q.body[i];
  }
  return size;
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_PDU_SERVER_HPP
