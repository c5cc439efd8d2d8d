// motionbus — Modbus file records: FC14 Read File Record and FC15 Write File Record (MODBUS
// Application Protocol V1.1b3 §6.14, §6.15), the vocabulary both roles share and the request
// decoder (a server decodes what it receives with it, a client what it sent). Client encoders
// and response decoders in modbus/pdu_client.hpp, the server's response encoders in
// modbus/pdu_server.hpp, dispatch to a device in modbus/server.hpp. Frame diagrams in
// docs/modbus.md ("File records").
//
//   FC14 request   14 | byte count 0x07..0xF5 | sub-requests of 7 bytes:
//                  06 | file number 1..0xFFFF (2) | record number 0..0x270F (2) | length N (2)
//   FC14 response  14 | data length | per sub-request: 1 + 2N | 06 | N registers
//   FC15 request   15 | data length 0x09..0xFB | per sub-request: 06 | file | record | N |
//                  N registers
//   FC15 response  the request echoed
//
// Choices where the text leaves room (docs/modbus.md): a record length of 0 is illegal (03);
// the records of a sub-request must end at record 0x270F or before (record + N <= 0x2710, 02);
// the §6.14 state diagram's checks are answered in its order, the byte count and lengths first
// (03: modbus_byte_count, modbus_quantity), then each sub-request's reference type, file number
// and record range (02: modbus_reference_type, modbus_file_number, modbus_record_number).
#ifndef MOTIONBUS_MODBUS_FILE_RECORD_HPP
#define MOTIONBUS_MODBUS_FILE_RECORD_HPP

#include <cstddef>
#include <cstdint>

#include "motionbus/core/bytes.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/modbus/pdu.hpp"

namespace motionbus {
namespace modbus {

inline constexpr std::uint8_t read_file_record_function = 0x14;
inline constexpr std::uint8_t write_file_record_function = 0x15;
inline constexpr std::uint8_t file_reference_type = 0x06;  ///< the only one defined (§6.14)
inline constexpr std::uint16_t max_record_number = 0x270F;
inline constexpr std::size_t file_subrequest_size = 7;  ///< reference type, file, record, N

/// One sub-request (or its answer): `length` records (registers) of file `file` from record
/// `record`. `data`: the records as big-endian register bytes (2 x length), in an FC15 request
/// and in FC14/FC15 responses; empty in an FC14 request. A view into the decoded PDU.
struct file_record {
  byte_view data{};
  std::uint16_t file = 0;
  std::uint16_t record = 0;
  std::uint16_t length = 0;
};

/// A checked FC14/FC15 request or response: its sub-requests as they are on the wire, `count`
/// of them (file_record_at reads one). Views into the decoded PDUs.
struct file_records {
  byte_view body{};      ///< what follows the byte count
  byte_view requests{};  ///< an FC14 response: the request's sub-requests (file, record, N)
  std::uint8_t function = 0;
  std::uint8_t count = 0;
  bool response = false;
  bool exception = false;           ///< a response: an exception response (count 0)
  std::uint8_t exception_code = 0;  ///< wire value when exception
};

namespace detail {

// One sub-request's fields (§6.14, §6.15): the reference type, the file number, the records.
constexpr errc check_file_fields(std::uint8_t reference, std::uint16_t file, std::uint16_t record,
                                 std::uint16_t length) noexcept {
  if (reference != file_reference_type) {
    return errc::modbus_reference_type;
  }
  if (file == 0U) {
    return errc::modbus_file_number;
  }
  if (record > max_record_number || std::size_t{record} + length > max_record_number + 1U) {
    return errc::modbus_record_number;
  }
  return errc::ok;
}

// The byte size of sub-request k's part of the body: FC14 request 7, FC15 7 + 2N, FC14
// response 2 + 2N.
constexpr std::size_t file_part_size(std::uint8_t f, bool response, std::uint16_t length) noexcept {
  if (f == read_file_record_function) {
    return response ? 2U + 2U * std::size_t{length} : file_subrequest_size;
  }
  return file_subrequest_size + 2U * std::size_t{length};
}

// The request whose function is `f` and whose data (after the function code) is `data`: the
// byte count, the sub-requests' layout and lengths (03), then each one's fields (02).
constexpr decode_result<file_records> decode_file_records(std::uint8_t f, byte_view data) noexcept {
  const std::size_t n = data.size() + 1U;
  if (f != read_file_record_function && f != write_file_record_function) {
    return decode_failure{errc::modbus_illegal_function, n};
  }
  if (data.empty()) {
    return decode_failure{errc::truncated, n};
  }
  const bool read = f == read_file_record_function;
  const std::size_t count = data[0];
  const byte_view body = data.subspan(1);
  errc e = errc::ok;
  if (read ? (count < 0x07U || count > 0xF5U || count % file_subrequest_size != 0U)
           : (count < 0x09U || count > 0xFBU)) {
    e = errc::modbus_byte_count;
  } else if (body.size() != count) {
    e = body.size() < count ? errc::truncated : errc::modbus_byte_count;
  }
  std::size_t k = 0;
  std::size_t reply = 2;  // FC14: the response's size, function and data length first
  for (std::size_t at = 0; e == errc::ok && at < count; ++k) {
    if (at + file_subrequest_size > count) {
      e = errc::modbus_byte_count;  // FC15: a sub-request's header cut by the data length
      break;
    }
    const std::uint16_t length = load_be16(body, at + 5U);
    const std::size_t part = file_part_size(f, false, length);
    reply += 2U + 2U * std::size_t{length};
    if (length == 0U || (read && reply > max_pdu_size)) {
      e = errc::modbus_quantity;  // no records, or more than an FC14 response holds
    } else if (at + part > count) {
      e = errc::modbus_byte_count;  // FC15: the records run past the data length
    }
    at += part;
  }
  for (std::size_t at = 0; e == errc::ok && at < count;) {
    const std::uint16_t length = load_be16(body, at + 5U);
    e = check_file_fields(body[at], load_be16(body, at + 1U), load_be16(body, at + 3U), length);
    at += file_part_size(f, false, length);
  }
  if (e != errc::ok) {
    return decode_failure{e, n};
  }
  file_records r;
  r.body = body;
  r.requests = body;
  r.function = f;
  r.count = static_cast<std::uint8_t>(k);
  return decode_result<file_records>::complete(r, n);
}

}  // namespace detail

/// Decodes a complete FC14 or FC15 request PDU. Complete: the sub-requests (file_record_at).
/// Failed (consumed = PDU size), in the order a server checks: modbus_pdu_length (empty or
/// > 253 bytes), modbus_illegal_function (not FC14/15), truncated (fewer bytes than the byte
/// count says, or none), modbus_byte_count (byte count outside 0x07..0xF5 or not 7 per
/// sub-request for FC14, outside 0x09..0xFB for FC15, more bytes than it says, or a sub-request
/// cut by it), modbus_quantity (a record length of 0, or an FC14 response that would pass 253
/// bytes) — exception 03; then modbus_reference_type (not 6), modbus_file_number (0),
/// modbus_record_number (record number past 0x270F, or its records past record 0x270F) —
/// exception 02.
constexpr decode_result<file_records> decode_file_record_request(byte_view pdu) noexcept {
  if (!pdu_size_ok(pdu.size())) {
    return decode_failure{errc::modbus_pdu_length, pdu.size()};
  }
  return detail::decode_file_records(pdu[0], pdu.subspan(1));
}

/// Sub-request `index` (0-based) of checked file records; errc::out_of_range past the last.
/// For an FC14 response: the file and record numbers of the request, the data of the response.
constexpr result<file_record> file_record_at(const file_records& r, std::size_t index) noexcept {
  if (index >= r.count) {
    return errc::out_of_range;
  }
  std::size_t at = 0;       // in r.requests
  std::size_t data_at = 0;  // in r.body, an FC14 response
  for (std::size_t k = 0; k < index; ++k) {
    const std::uint16_t length = load_be16(r.requests, at + 5U);
    at += detail::file_part_size(r.function, false, length);
    data_at += detail::file_part_size(r.function, true, length);
  }
  file_record rec;
  rec.file = load_be16(r.requests, at + 1U);
  rec.record = load_be16(r.requests, at + 3U);
  rec.length = load_be16(r.requests, at + 5U);
  const std::size_t bytes = 2U * std::size_t{rec.length};
  if (r.function == write_file_record_function) {
    rec.data = r.body.subspan(at + file_subrequest_size, bytes);
  } else if (r.response) {
    rec.data = r.body.subspan(data_at + 2U, bytes);
  }
  return rec;
}

}  // namespace modbus
}  // namespace motionbus

#endif  // MOTIONBUS_MODBUS_FILE_RECORD_HPP
