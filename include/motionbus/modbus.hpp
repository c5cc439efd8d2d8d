// motionbus — Modbus: PDU codec (client and server) and the RTU ADU.
#ifndef MOTIONBUS_MODBUS_HPP
#define MOTIONBUS_MODBUS_HPP

#include "motionbus/modbus/pdu.hpp"
#include "motionbus/modbus/rtu.hpp"

#endif  // MOTIONBUS_MODBUS_HPP
