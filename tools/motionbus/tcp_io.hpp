// Modbus TCP for the CLI, on standalone Asio (Debian libasio-dev, header-only): the client's
// one transaction (read modbus --tcp) and what the gateway's event loop shares with it. Asio
// runs the sockets and the timers; the serial line joins the same loop as a POSIX stream
// descriptor on the port libserialport opened (serial::port::native_handle).
#ifndef MOTIONBUS_TOOLS_TCP_IO_HPP
#define MOTIONBUS_TOOLS_TCP_IO_HPP

#include <motionbus/core/span.hpp>

#include <cstdint>
#include <string>

#include "modbus_io.hpp"
#include "options.hpp"

namespace tcp_io {

/// One MBAP transaction with the server at `to`: the request PDU `pdu` to unit `unit` with
/// transaction id `transaction`; the response PDU, or an error code: "connect_error",
/// "timeout" (no whole response within `timeout_ms`, connecting included), "read_error",
/// "write_error", or the MBAP decoder's (a response with another transaction id is
/// "transaction_mismatch", another unit "unit_mismatch").
modbus_io::exchange transact(const cli::endpoint& to, std::uint8_t unit, motionbus::byte_view pdu,
                             std::uint16_t transaction, int timeout_ms);

}  // namespace tcp_io

#endif
