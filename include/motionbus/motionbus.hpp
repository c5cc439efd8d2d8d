// motionbus — umbrella header: every public header of the library.
#ifndef MOTIONBUS_MOTIONBUS_HPP
#define MOTIONBUS_MOTIONBUS_HPP

#include "motionbus/biss.hpp"
#include "motionbus/core.hpp"
#include "motionbus/devices/absys.hpp"
#include "motionbus/devices/absys_emulator.hpp"
#include "motionbus/devices/sm_unit.hpp"
#include "motionbus/devices/sm_unit_emulator.hpp"
#include "motionbus/devices/ts5700n8500.hpp"
#include "motionbus/modbus.hpp"
#include "motionbus/tformat.hpp"
#include "motionbus/version.hpp"

#endif  // MOTIONBUS_MOTIONBUS_HPP
