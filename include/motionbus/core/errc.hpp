// motionbus — the library's error codes.
//
// One small enum serves every protocol so that results, tools and logs speak one language.
// Values are explicit and stable; ranges are reserved per protocol:
//   0          success
//   1..31      generic (shared by every codec)
//   32..63     T-format
//   64..127    Modbus (library errors; Modbus exception codes are wire values, kept apart)
//   128..191   BiSS-C
//   192..255   device profiles
// "Need more input" is not an error: decoders report it as its own outcome (see result.hpp).
#ifndef MOTIONBUS_CORE_ERRC_HPP
#define MOTIONBUS_CORE_ERRC_HPP

#include <cstdint>

namespace motionbus {

enum class [[nodiscard]] errc : std::uint8_t{
    ok = 0,
    /// The input ends before the field or frame does (a complete frame was required).
    truncated = 1,
    /// The caller's output buffer cannot hold what the encoder must write. Nothing was written.
    buffer_too_small = 2,
    /// An argument is outside the function's documented domain (e.g. a bit count above 64).
    invalid_argument = 3,
    /// The received check value differs from the one computed over the received data.
    crc_mismatch = 4,
    /// A value decoded from the wire, or given to an encoder, is outside its legal range.
    out_of_range = 5,
    /// A length or count field disagrees with the data actually present.
    length_mismatch = 6,
    /// Bits that the protocol reserves (must be zero or one) have the wrong value.
    reserved_bits = 7,
    /// No frame start was found within the searched input.
    no_frame = 8,

    // T-format (32..63)
    /// CF bits 0..2 are not the sync code 010.
    tformat_sync_code = 32,
    /// CF bit 7 (cc4) is not the XOR of the Data ID bits cc0..cc3.
    tformat_parity = 33,
    /// The Data ID is none of 0, 1, 2, 3, 6, 7, 8, C, D.
    tformat_unknown_data_id = 34,
    /// The frame is longer than its Data ID allows.
    tformat_length = 35,
    /// The response's CF differs from the request's.
    tformat_cf_mismatch = 36,
    /// The EEPROM response's address differs from the request's.
    tformat_address_mismatch = 37,
    /// The encoder answered an abnormal request (ca0/ca1 set): discard and send again.
    tformat_communication_alarm = 38,
    /// A field's start bit (raw bit stream) is not 0.
    tformat_start_bit = 39,
    /// A field's delimiter bit (raw bit stream) is not 1.
    tformat_delimiter = 40,
    /// The EEPROM write response does not echo the data written.
    tformat_data_mismatch = 41,

    // Modbus (64..127). Modbus exception codes are wire values (modbus::exception_code), not errc.
    /// The function code is not one this codec frames (a server answers exception 01).
    modbus_illegal_function = 64,
    /// A quantity is outside the function's limits (Modbus App. Protocol §6; exception 03).
    modbus_quantity = 65,
    /// A byte count disagrees with the quantity or with the bytes present (exception 03).
    modbus_byte_count = 66,
    /// Starting address + quantity runs past 0xFFFF (exception 02).
    modbus_address_overflow = 67,
    /// FC05 value other than 0xFF00 / 0x0000 (exception 03).
    modbus_coil_value = 68,
    /// The response's function or echoed fields do not match the request.
    modbus_mismatch = 69,
    /// Slave address 248..255 (reserved), or a broadcast where one is not allowed.
    modbus_slave_address = 70,
    /// A PDU outside 1..253 bytes, or an ADU outside 4..256.
    modbus_pdu_length = 71,
    /// Modbus ASCII: a character other than a hex digit, CR or the delimiter inside a frame
    /// (Serial Line §2.5.2.1).
    modbus_ascii_character = 80,
    /// Modbus ASCII: an odd number of hex digits between ':' and CR LF (two a byte).
    modbus_ascii_odd_digits = 81,
    /// Modbus ASCII: a frame not ended by CR LF (CR without LF, LF without CR, or a ':' that
    /// restarts it; LF: the delimiter, unless changed).
    modbus_ascii_end = 82,
    /// FC14/15: a sub-request's reference type is not 6 (Modbus App. Protocol §6.14; exception 02).
    modbus_reference_type = 96,
    /// FC14/15: a sub-request's file number is 0 (1..0xFFFF; exception 02).
    modbus_file_number = 97,
    /// FC14/15: a record number past 0x270F, or records that run past it (exception 02).
    modbus_record_number = 98,
    // BiSS-C (128..191)
    /// SL stayed high (idle) over the whole bounded search: no slave acknowledged the clock.
    biss_no_ack = 128,
    /// SL stayed low (Ack) past the bound without a Start bit.
    biss_no_start = 129,
    /// Control communication: no slave answered (R/W echo 00: wrong ID or address CRC).
    biss_not_acknowledged = 130,
    /// Control communication: the slave refused the access (R/W echo 11).
    biss_access_denied = 131,
    /// Control communication: the R/W echo differs from what was sent.
    biss_echo_mismatch = 132,
    /// Control communication: the slave stayed busy (wait states) past the bound in frames.
    biss_timeout = 133,
    /// Control communication: a write's echo (byte or CRC) differs from the byte written.
    biss_write_not_confirmed = 134,
    /// Control communication: abort() ended the access (14 frames with CDM = 0).
    biss_aborted = 135,
    /// Control communication: an access is already running.
    biss_busy = 136,
    /// A layout is inconsistent (field widths, CRC width, chain length).
    biss_layout = 137,
    /// The electronic data sheet fails its own consistency checks.
    biss_eds = 138,
};

/// snake_case name of an error code, as printed by the tools; "unknown" for a value outside
/// the enumeration. The returned string has static storage duration.
constexpr const char* to_string(errc e) noexcept {
  switch (e) {
    case errc::ok: return "ok";
    case errc::truncated: return "truncated";
    case errc::buffer_too_small: return "buffer_too_small";
    case errc::invalid_argument: return "invalid_argument";
    case errc::crc_mismatch: return "crc_mismatch";
    case errc::out_of_range: return "out_of_range";
    case errc::length_mismatch: return "length_mismatch";
    case errc::reserved_bits: return "reserved_bits";
    case errc::no_frame: return "no_frame";
    case errc::tformat_sync_code: return "sync_code";
    case errc::tformat_parity: return "parity";
    case errc::tformat_unknown_data_id: return "unknown_data_id";
    case errc::tformat_length: return "wrong_length";
    case errc::tformat_cf_mismatch: return "cf_mismatch";
    case errc::tformat_address_mismatch: return "address_mismatch";
    case errc::tformat_communication_alarm: return "communication_alarm";
    case errc::tformat_start_bit: return "start_bit";
    case errc::tformat_delimiter: return "delimiter";
    case errc::tformat_data_mismatch: return "data_mismatch";
    case errc::modbus_illegal_function: return "illegal_function";
    case errc::modbus_quantity: return "illegal_quantity";
    case errc::modbus_byte_count: return "byte_count_mismatch";
    case errc::modbus_address_overflow: return "address_overflow";
    case errc::modbus_coil_value: return "illegal_coil_value";
    case errc::modbus_mismatch: return "response_mismatch";
    case errc::modbus_slave_address: return "slave_address";
    case errc::modbus_pdu_length: return "pdu_length";
    case errc::modbus_ascii_character: return "non_hex_character";
    case errc::modbus_ascii_odd_digits: return "odd_digit_count";
    case errc::modbus_ascii_end: return "missing_crlf";
    case errc::modbus_reference_type: return "reference_type";
    case errc::modbus_file_number: return "file_number";
    case errc::modbus_record_number: return "record_number";
    case errc::biss_no_ack: return "no_ack";
    case errc::biss_no_start: return "no_start";
    case errc::biss_not_acknowledged: return "not_acknowledged";
    case errc::biss_access_denied: return "access_denied";
    case errc::biss_echo_mismatch: return "echo_mismatch";
    case errc::biss_timeout: return "timeout";
    case errc::biss_write_not_confirmed: return "write_not_confirmed";
    case errc::biss_aborted: return "aborted";
    case errc::biss_busy: return "busy";
    case errc::biss_layout: return "invalid_layout";
    case errc::biss_eds: return "invalid_eds";
  }
  return "unknown";
}

}  // namespace motionbus

#endif  // MOTIONBUS_CORE_ERRC_HPP
