// motionbus — the shared core: configuration, views, errors, results, bit I/O, CRC engine.
#ifndef MOTIONBUS_CORE_HPP
#define MOTIONBUS_CORE_HPP

#include "motionbus/core/bits.hpp"
#include "motionbus/core/bytes.hpp"
#include "motionbus/core/config.hpp"
#include "motionbus/core/crc.hpp"
#include "motionbus/core/errc.hpp"
#include "motionbus/core/frame_buffer.hpp"
#include "motionbus/core/link_health.hpp"
#include "motionbus/core/position.hpp"
#include "motionbus/core/result.hpp"
#include "motionbus/core/span.hpp"
#include "motionbus/core/stream.hpp"

#endif  // MOTIONBUS_CORE_HPP
