// motionbus — T-format: frames, byte codec (master and encoder side), line coding, stream
// receiver, encoder model.
#ifndef MOTIONBUS_TFORMAT_HPP
#define MOTIONBUS_TFORMAT_HPP

#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/encoder_model.hpp"
#include "motionbus/tformat/frame.hpp"
#include "motionbus/tformat/line.hpp"
#include "motionbus/tformat/receiver.hpp"

#endif  // MOTIONBUS_TFORMAT_HPP
