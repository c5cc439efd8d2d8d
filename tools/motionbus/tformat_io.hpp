// T-format records for the CLI's commands (decode, read, monitor), and read --watch.
#ifndef MOTIONBUS_TOOLS_TFORMAT_IO_HPP
#define MOTIONBUS_TOOLS_TFORMAT_IO_HPP

#include <motionbus/tformat.hpp>

#include <cstddef>
#include <cstdint>

#include "cli.hpp"
#include "options.hpp"
#include "serial.hpp"

namespace tformat_io {

/// A response's fields: position, status, alarms spelled out, EEPROM fields, CRC.
cli::record response_record(const motionbus::tformat::response& r);
/// A request's fields: Data ID, CF, and for EEPROM requests the address, data and CRC.
cli::record request_record(const motionbus::tformat::request& q);

/// What read tformat --watch sends and how it reads the answers.
struct watch_setup {
  motionbus::tformat::data_id id = motionbus::tformat::data_id::read_all;
  const std::uint8_t* request = nullptr;  ///< the request frame, sent each read
  std::size_t request_size = 0;
  motionbus::tformat::receiver_options receiver{};
  std::uint32_t baud = 2500000;    ///< the line's rate: the library's deadline is taken at it
  std::uint32_t timeout_ms = 200;  ///< the host's allowance, added to the library's deadline
};

/// read tformat --watch (tformat_watch.cpp): reads until --count or Ctrl-C, printing each (a
/// live line on a terminal) and a summary; 0 when the link is up at the end, 1 when it is
/// lost or the port fails.
int watch(serial::port& port, const watch_setup& s, const cli::watch_options& w);

}  // namespace tformat_io

#endif
