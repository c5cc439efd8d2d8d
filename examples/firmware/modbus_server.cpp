// motionbus firmware example — a generic Modbus RTU server on a UART, slave 1: 100 coils,
// 100 discrete inputs, 100 holding and 100 input registers at addresses 0..99, and every
// function the server dispatch serves (01-06, 0F, 10, 11, 16, 17). The device below is the
// whole application: the library frames, checks, dispatches and answers (exceptions included).
//
// The serving loop (framer, serve_frame, the line silence) is modbus_serve_loop.hpp's, the device
// generic_device.hpp's.
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "generic_device.hpp"
#include "modbus_serve_loop.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

firmware::generic_device dev;

}  // namespace

int main() {
  board::init();
  firmware::serve_forever(dev, [](std::uint32_t) {});
}
