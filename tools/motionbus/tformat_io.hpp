// T-format records for the CLI's commands (decode, read, monitor).
#ifndef MOTIONBUS_TOOLS_TFORMAT_IO_HPP
#define MOTIONBUS_TOOLS_TFORMAT_IO_HPP

#include <motionbus/tformat.hpp>

#include "cli.hpp"

namespace tformat_io {

/// A response's fields: position, status, alarms spelled out, EEPROM fields, CRC.
cli::record response_record(const motionbus::tformat::response& r);
/// A request's fields: Data ID, CF, and for EEPROM requests the address, data and CRC.
cli::record request_record(const motionbus::tformat::request& q);

}  // namespace tformat_io

#endif
