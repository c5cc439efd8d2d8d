// motionbus — T-format: frames, byte codec (master and encoder side), line coding, stream
// receiver. The TS5700N8500 emulator is in devices/ts5700n8500_emulator.hpp.
#ifndef MOTIONBUS_TFORMAT_HPP
#define MOTIONBUS_TFORMAT_HPP

#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/frame.hpp"
#include "motionbus/tformat/line.hpp"
#include "motionbus/tformat/listener.hpp"
#include "motionbus/tformat/position.hpp"
#include "motionbus/tformat/receiver.hpp"

#endif  // MOTIONBUS_TFORMAT_HPP
