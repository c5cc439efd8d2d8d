// motionbus — Modbus: PDU codec (client and server), RTU and TCP ADUs, RTU timing, stream
// framing, server dispatch, the TCP-to-RTU gateway core.
#ifndef MOTIONBUS_MODBUS_HPP
#define MOTIONBUS_MODBUS_HPP

#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/gateway.hpp"
#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/pdu_server.hpp"
#include "motionbus/modbus/rtu.hpp"
#include "motionbus/modbus/server.hpp"
#include "motionbus/modbus/tcp.hpp"
#include "motionbus/modbus/timing.hpp"

#endif  // MOTIONBUS_MODBUS_HPP
