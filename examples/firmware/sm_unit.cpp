// motionbus firmware example — a Tsubaki SM unit on a UART: the SM unit emulator
// (devices/sm_unit_emulator.hpp) behind the Modbus RTU server dispatch, slave 1, 9600 8E1 on
// real hardware, served by the loop the Modbus images share (modbus_serve_loop.hpp: the framer,
// serve_frame, the line silence).
#include <cstdint>

#include "board.hpp"
#include "modbus_serve_loop.hpp"
#include "motionbus/devices/sm_unit_emulator.hpp"

namespace {

motionbus::devices::sm_unit::emulator unit;

}  // namespace

int main() {
  board::init();
  firmware::serve_forever(unit, [](std::uint32_t now_us) { unit.set_time_ms(now_us / 1000U); });
}
