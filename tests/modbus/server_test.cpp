// Modbus server dispatch against an array-backed device: responses, exceptions from the codec
// and from the device, broadcasts, other addresses, missing accessors.
#include "motionbus/modbus/server.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

using namespace motionbus;
using namespace motionbus::modbus;

namespace {

using bytes = std::vector<std::uint8_t>;

// 100 coils, 100 discrete inputs, 100 holding and 100 input registers at addresses 0..99.
struct array_device {
  bool coils[100] = {};
  std::uint16_t holding[100] = {};
  int writes = 0;

  std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
                         mutable_byte_view packed) {
    if (address + quantity > 100) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      const bool bit = function == 0x01 ? coils[address + i] : ((address + i) % 3 == 0);
      if (bit) {
        packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (1U << (i % 8U)));
      }
    }
    return 0;
  }
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              span<std::uint16_t> out) {
    if (address + out.size() > 100) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] =
          function == 0x04 ? static_cast<std::uint16_t>(1000 + address + i) : holding[address + i];
    }
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, byte_view packed) {
    if (address + quantity > 100) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      coils[address + i] = bit_at(packed, i);
    }
    ++writes;
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, span<const std::uint16_t> values) {
    if (address + values.size() > 100) {
      return 0x02;
    }
    if (address == 99 && values[0] == 0xDEAD) {
      return 0x04;  // device failure
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      holding[address + i] = values[i];
    }
    ++writes;
    return 0;
  }
  std::uint8_t report_server_id(mutable_byte_view out, std::size_t& size) {
    out[0] = 2;
    out[1] = 0x42;
    out[2] = 0xFF;
    size = 3;
    return 0;
  }
};

struct empty_device {};

template <class Device>
bytes call(Device& dev, std::uint8_t slave, const bytes& pdu, std::uint8_t own = 0x11) {
  std::uint8_t adu[256] = {};
  const std::size_t n = encode_rtu(slave, byte_view(pdu.data(), pdu.size()), adu).value();
  std::uint8_t out[256] = {};
  const auto r = serve_rtu(dev, own, byte_view(adu, n), out);
  REQUIRE(r.ok());
  if (r.value() == 0) {
    return {};
  }
  const auto f = decode_rtu(byte_view(out, r.value()));
  REQUIRE(f.is_complete());
  CHECK(f->slave == own);
  return bytes(f->pdu.begin(), f->pdu.end());
}

}  // namespace

TEST_CASE("server: reads and writes through the device's accessors") {
  array_device dev;
  CHECK(call(dev, 0x11, {0x06, 0x00, 0x05, 0x12, 0x34}) == bytes{0x06, 0x00, 0x05, 0x12, 0x34});
  CHECK(dev.holding[5] == 0x1234);
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x04, 0x00, 0x02}) ==
        bytes{0x03, 0x04, 0x00, 0x00, 0x12, 0x34});
  CHECK(call(dev, 0x11, {0x04, 0x00, 0x01, 0x00, 0x01}) == bytes{0x04, 0x02, 0x03, 0xE9});
  CHECK(call(dev, 0x11, {0x10, 0x00, 0x0A, 0x00, 0x02, 0x04, 0x00, 0x01, 0x00, 0x02}) ==
        bytes{0x10, 0x00, 0x0A, 0x00, 0x02});
  CHECK(dev.holding[11] == 2);
  CHECK(call(dev, 0x11, {0x0F, 0x00, 0x03, 0x00, 0x0A, 0x02, 0xCD, 0x01}) ==
        bytes{0x0F, 0x00, 0x03, 0x00, 0x0A});
  CHECK(dev.coils[3]);
  CHECK(!dev.coils[4]);
  CHECK(call(dev, 0x11, {0x01, 0x00, 0x03, 0x00, 0x0A}) == bytes{0x01, 0x02, 0xCD, 0x01});
  CHECK(call(dev, 0x11, {0x05, 0x00, 0x04, 0xFF, 0x00}) == bytes{0x05, 0x00, 0x04, 0xFF, 0x00});
  CHECK(dev.coils[4]);
  CHECK(call(dev, 0x11, {0x02, 0x00, 0x00, 0x00, 0x04}) == bytes{0x02, 0x01, 0x09});  // 0 and 3
  // FC16 mask write: (0x0012 & 0x00F2) | (0x0025 & ~0x00F2) = 0x0017 (spec §6.16 example)
  dev.holding[4] = 0x0012;
  CHECK(call(dev, 0x11, {0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25}) ==
        bytes{0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25});
  CHECK(dev.holding[4] == 0x0017);
  // FC17: write first, then read
  CHECK(call(dev, 0x11, {0x17, 0x00, 0x14, 0x00, 0x01, 0x00, 0x14, 0x00, 0x01, 0x02, 0xAB, 0xCD}) ==
        bytes{0x17, 0x02, 0xAB, 0xCD});
  CHECK(call(dev, 0x11, {0x11}) == bytes{0x11, 0x02, 0x42, 0xFF});
}

TEST_CASE("server: exceptions in the spec's order, from the codec and from the device") {
  array_device dev;
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x00, 0x00, 0x7E}) == bytes{0x83, 0x03});  // quantity
  CHECK(call(dev, 0x11, {0x03, 0xFF, 0xFF, 0x00, 0x00}) == bytes{0x83, 0x03});  // 03 before 02
  CHECK(call(dev, 0x11, {0x03, 0xFF, 0xFF, 0x00, 0x02}) == bytes{0x83, 0x02});  // overflow
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x63, 0x00, 0x02}) == bytes{0x83, 0x02});  // device map
  CHECK(call(dev, 0x11, {0x05, 0x00, 0x01, 0x12, 0x34}) == bytes{0x85, 0x03});  // coil value
  CHECK(call(dev, 0x11, {0x06, 0x00, 0x63, 0xDE, 0xAD}) == bytes{0x86, 0x04});  // device failure
  CHECK(call(dev, 0x11, {0x2B, 0x0E, 0x01, 0x00}) == bytes{0xAB, 0x01});        // not served
  CHECK(call(dev, 0x11, {0x10, 0x00, 0x01, 0x00, 0x02, 0x03, 0x00, 0x0A, 0x01}) ==
        bytes{0x90, 0x03});
  empty_device none;
  CHECK(call(none, 0x11, {0x03, 0x00, 0x00, 0x00, 0x01}) == bytes{0x83, 0x01});
  CHECK(call(none, 0x11, {0x11}) == bytes{0x91, 0x01});
}

TEST_CASE("server: broadcasts are executed and never answered; other addresses are ignored") {
  array_device dev;
  CHECK(call(dev, 0x00, {0x06, 0x00, 0x07, 0x00, 0x2A}).empty());
  CHECK(dev.holding[7] == 0x2A);
  CHECK(call(dev, 0x00, {0x03, 0x00, 0x00, 0x00, 0x7E}).empty());  // not even an exception
  CHECK(call(dev, 0x12, {0x06, 0x00, 0x08, 0x00, 0x2A}).empty());
  CHECK(dev.holding[8] == 0);
  // a corrupted frame: nothing
  std::uint8_t adu[8] = {0x11, 0x06, 0x00, 0x08, 0x00, 0x2A, 0x00, 0x00};
  std::uint8_t out[256] = {};
  CHECK(serve_rtu(dev, 0x11, adu, out).value() == 0);
  CHECK(serve_rtu(dev, 0x11, adu, mutable_byte_view(out, 10)).error() == errc::buffer_too_small);
  CHECK(dev.writes == 1);
}
