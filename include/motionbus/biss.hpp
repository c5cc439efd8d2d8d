// motionbus — BiSS-C: sensor data frames and control communication.
#ifndef MOTIONBUS_BISS_HPP
#define MOTIONBUS_BISS_HPP

#include "motionbus/biss/codec.hpp"
#include "motionbus/biss/control.hpp"
#include "motionbus/biss/eds.hpp"
#include "motionbus/biss/frame.hpp"
#include "motionbus/biss/position.hpp"

#endif  // MOTIONBUS_BISS_HPP
