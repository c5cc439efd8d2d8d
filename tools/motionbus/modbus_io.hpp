// Modbus RTU transactions on a serial port for the CLI (client side).
#ifndef MOTIONBUS_TOOLS_MODBUS_IO_HPP
#define MOTIONBUS_TOOLS_MODBUS_IO_HPP

#include <motionbus/modbus/pdu_client.hpp>
#include <motionbus/modbus/rtu.hpp>
#include <motionbus/modbus/timing.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "cli.hpp"
#include "serial.hpp"

namespace modbus_io {

/// The response PDU to one request ADU, or an error code: "timeout" (nothing came), the
/// framer's error for what came instead (a silence ended it: "truncated", "crc_mismatch"...),
/// "write_error", "read_error".
struct exchange {
  std::vector<std::uint8_t> pdu;
  std::string error;
};

exchange transact(serial::port& port, std::uint8_t slave, const std::uint8_t* adu, std::size_t size,
                  motionbus::modbus::report_id_format fc11, int timeout_ms);

/// The same in Modbus ASCII (Serial Line §2.5.2): the request PDU `pdu` to `slave` as an
/// ASCII ADU (':' hex LRC CR LF), the response framed by the ASCII framer; the errors of
/// transact, and the ASCII framer's (non_hex_character, odd_digit_count, missing_crlf,
/// crc_mismatch for a bad LRC).
exchange transact_ascii(serial::port& port, std::uint8_t slave, motionbus::byte_view pdu,
                        int timeout_ms);

/// The FC11 response layout named "standard" or "sm" (a usage error otherwise).
motionbus::modbus::report_id_format fc11_of(const std::string& name);
const char* fc11_name(motionbus::modbus::report_id_format f);
/// The name of a Modbus exception code (Modbus Application Protocol V1.1b3 §7), "unknown" for
/// a code it does not define.
std::string exception_name(std::uint8_t code);
/// The SM unit's version bytes as text: upper byte, then the lower byte's two nibbles
/// ("01 00" is Ver.1.0.0, SM unit guideline §11).
std::string sm_version_text(std::uint8_t upper, std::uint8_t lower);

/// An RTU frame as a server sees it (decode modbus request, monitor modbus).
cli::outcome describe_request(const motionbus::modbus::rtu_frame& frame);
/// An RTU frame as a client sees it: checked against `request` when given (decode modbus
/// response --request, monitor modbus), else what the response carries alone.
cli::outcome describe_response(const motionbus::modbus::rtu_frame& frame,
                               const motionbus::modbus::rtu_frame* request,
                               motionbus::modbus::report_id_format fc11);

/// What an emulator served: the request's fields and the reply's bytes ("none": no reply, a
/// broadcast or another address), one line (text or JSON) at `time_us` since it started.
void print_served(const motionbus::modbus::rtu_frame& request, const std::uint8_t* reply,
                  std::size_t size, std::uint64_t time_us);

/// The library's parity for the line settings (character and silence times: modbus/timing.hpp).
motionbus::modbus::parity parity_of(const serial::settings& s);

}  // namespace modbus_io

#endif
