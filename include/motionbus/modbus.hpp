// motionbus — Modbus: PDU codec (client and server), RTU, TCP and ASCII ADUs, RTU timing, stream
// framing, server dispatch, file records, typed values over registers.
#ifndef MOTIONBUS_MODBUS_HPP
#define MOTIONBUS_MODBUS_HPP

#include "motionbus/modbus/ascii.hpp"
#include "motionbus/modbus/file_record.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/pdu_server.hpp"
#include "motionbus/modbus/rtu.hpp"
#include "motionbus/modbus/server.hpp"
#include "motionbus/modbus/tcp.hpp"
#include "motionbus/modbus/timing.hpp"
#include "motionbus/modbus/values.hpp"

#endif  // MOTIONBUS_MODBUS_HPP
