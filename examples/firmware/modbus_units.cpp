// motionbus firmware example — one UART, four Modbus RTU servers: units 1 to 4 answer as four
// devices, each its own registers and identity; every other address stays silent. The framer
// takes the range of addresses (framer_options::last_address), serve_units() serves each frame
// by the device its unit is given, and the response carries that unit's address.
//
// Unit u (1..4): 8 * u holding registers at addresses 0..8u-1 (unit 1: 8, unit 4: 32), as
// written, 0 at power-up; 8 input registers, input register i reads 1000 * u + i; FC11
// answers server ID u, run indicator on, "unit u". Units 1 and 2 serve registers only; units 3
// and 4 also 16 coils (FC01/05/0F), so that a coil request to unit 1 or 2 is exception 01.
// A broadcast (address 0) is executed by no unit (the lookup has no device for it).
//
// The silence that ends a frame the framer cannot size is modbus_serve_loop.hpp's (50 ms under
// emulation).
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "modbus_serve_loop.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

constexpr std::uint8_t first_unit = 1;
constexpr std::uint8_t last_unit = 4;
constexpr std::uint16_t max_holding = 8U * last_unit;
constexpr std::uint16_t inputs = 8;
constexpr std::uint16_t coil_count = 16;

struct unit_device {
  std::uint8_t unit = 0;
  std::uint16_t holding[max_holding] = {};
  std::uint16_t coils = 0;  // bit i: coil i (units 3 and 4)

  std::uint16_t holding_count() const { return static_cast<std::uint16_t>(8U * unit); }
  bool has_coils() const { return unit >= 3U; }

  std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
                         mb::mutable_byte_view packed) {
    if (function != 0x01 || !has_coils()) {
      return 0x01;
    }
    if (address + quantity > coil_count) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      if (((coils >> (address + i)) & 1U) != 0U) {
        packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (1U << (i % 8U)));
      }
    }
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, mb::byte_view packed) {
    if (!has_coils()) {
      return 0x01;
    }
    if (address + quantity > coil_count) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      const auto bit = static_cast<std::uint16_t>(1U << (address + i));
      coils = mo::bit_at(packed, i) ? static_cast<std::uint16_t>(coils | bit)
                                    : static_cast<std::uint16_t>(coils & ~bit);
    }
    return 0;
  }
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              mb::span<std::uint16_t> out) {
    const std::uint16_t count = function == 0x04 ? inputs : holding_count();
    if (address + out.size() > count) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = function == 0x04 ? static_cast<std::uint16_t>(1000U * unit + address + i)
                                : holding[address + i];
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> values) {
    if (address + values.size() > holding_count()) {
      return 0x02;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      holding[address + i] = values[i];
    }
    return 0;
  }
  // FC11: the byte count, then server ID u, run indicator 0xFF (on), "unit u".
  std::uint8_t report_server_id(mb::mutable_byte_view out, std::size_t& size) {
    const char text[] = "unit ";
    const std::size_t n = 2U + (sizeof text - 1U) + 1U;
    out[0] = static_cast<std::uint8_t>(n);
    out[1] = unit;
    out[2] = 0xFF;
    for (std::size_t i = 0; i + 1U < sizeof text; ++i) {
      out[3U + i] = static_cast<std::uint8_t>(text[i]);
    }
    out[n] = static_cast<std::uint8_t>('0' + unit);
    size = 1U + n;
    return 0;
  }
};

unit_device units[last_unit];

}  // namespace

int main() {
  board::init();
  for (std::uint8_t u = first_unit; u <= last_unit; ++u) {
    units[u - 1U].unit = u;
  }
  static mo::rtu_server_framer rx;
  static std::uint8_t reply[mo::max_rtu_size];
  rx = mo::rtu_server_framer(
      {first_unit, mo::frame_end::silence, mo::report_id_format::standard, last_unit});
  firmware::frame_forever(
      rx,
      [](const mo::rtu_frame& frame) {
        const auto n = mo::serve_units(
            [](std::uint8_t u) -> unit_device* {
              return u >= first_unit && u <= last_unit ? &units[u - 1U] : nullptr;
            },
            frame, mb::mutable_byte_view(reply, sizeof reply));
        if (n.ok() && n.value() > 0U) {  // nothing for broadcasts and units without a device
          board::uart_write(reply, n.value());
        }
      },
      [](std::uint32_t) {});
}
