// Modbus server dispatch against an array-backed device: responses, exceptions from the codec
// and from the device, broadcasts, other addresses, missing accessors.
#include "motionbus/modbus/server.hpp"

#include "motionbus/modbus/framer.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <vector>
#include "../support/bytes.hpp"

using namespace motionbus;
using namespace motionbus::modbus;

using namespace testutil;

namespace {

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

// A server built as docs/modbus.md §3 describes: bytes in chunks from the UART into a framer
// with its default options, idle() at the end of the burst (the t3.5 timer), serve_rtu on every
// frame. Returns what it sends.
namespace {
std::vector<bytes> serve_stream(const bytes& stream, std::size_t chunk, framer_options options) {
  array_device dev;
  options.role = framer_role::server;
  options.address = 0x11;
  rtu_framer rx(options);
  std::vector<bytes> sent;
  auto answer = [&](const rtu_frame& frame) {
    std::uint8_t out[256] = {};
    const byte_view adu(frame.pdu.data() - 1, frame.pdu.size() + 3U);
    const auto n = serve_rtu(dev, 0x11, adu, out);
    REQUIRE(n.ok());
    if (n.value() > 0U) {
      sent.emplace_back(out, out + n.value());
    }
  };
  for (std::size_t at = 0; at < stream.size(); at += chunk) {
    feed_all(rx, byte_view(stream.data() + at, std::min(chunk, stream.size() - at)),
             [&](const auto& r) {
               if (r.is_complete()) {
                 answer(r.value());
               }
               return true;
             });
  }
  const auto last = rx.idle();
  if (last.is_complete()) {
    answer(last.value());
  }
  return sent;
}
}  // namespace

TEST_CASE("server over a framer: requests whose counts disagree with their length get exceptions") {
  // Modbus over Serial Line §2.5.1.1 (frames end with the silence) and Modbus Application
  // Protocol §7 (01 for an unknown function, 03 for a byte count that disagrees)
  const bytes count_zero = {0x11, 0x10, 0x01, 0x60, 0x00, 0x00, 0x00, 0x02,
                            0x2B, 0x00, 0x01, 0x00, 0x64, 0x8C, 0x88};
  const bytes unknown = {0x11, 0x42, 0x00, 0x00, 0x00, 0x00, 0x7B, 0x55};
  for (std::size_t chunk : {std::size_t{1}, std::size_t{3}, std::size_t{64}}) {
    CAPTURE(chunk);
    auto sent = serve_stream(count_zero, chunk, {});
    REQUIRE(sent.size() == 1);
    CHECK(sent[0] == bytes{0x11, 0x90, 0x03, 0x0D, 0xC4});
    sent = serve_stream(unknown, chunk, {});
    REQUIRE(sent.size() == 1);
    CHECK(sent[0] == bytes{0x11, 0xC2, 0x01, 0xB1, 0x65});
    // without the silence, the length rule cannot frame either: nothing is sent
    CHECK(serve_stream(count_zero, chunk,
                       framer_options{framer_role::server, 0x11, frame_end::length})
              .empty());
    CHECK(serve_stream(unknown, chunk, framer_options{framer_role::server, 0x11, frame_end::length})
              .empty());
  }
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

namespace {

// The array device's holding registers through the big-endian accessors (no register buffer in
// the server): the same registers, byte by byte as the PDU carries them.
struct be_device {
  std::uint16_t holding[100] = {};
  std::uint8_t read_registers_be(std::uint8_t function, std::uint16_t address,
                                 std::uint16_t quantity, mutable_byte_view out) {
    if (address + quantity > 100) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      const std::uint16_t v =
          function == 0x04 ? static_cast<std::uint16_t>(1000 + address + i) : holding[address + i];
      out[2 * i] = static_cast<std::uint8_t>(v >> 8U);
      out[2 * i + 1] = static_cast<std::uint8_t>(v & 0xFFU);
    }
    return 0;
  }
  std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity, byte_view data) {
    if (address + quantity > 100 || data.size() != 2U * quantity) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      holding[address + i] = register_at(data, i);
    }
    return 0;
  }
};

}  // namespace

TEST_CASE("server: big-endian register accessors answer as the register-array ones") {
  array_device a;
  be_device b;
  const bytes requests[] = {
      {0x06, 0x00, 0x05, 0x12, 0x34},
      {0x03, 0x00, 0x04, 0x00, 0x02},
      {0x04, 0x00, 0x01, 0x00, 0x03},
      {0x10, 0x00, 0x0A, 0x00, 0x02, 0x04, 0x00, 0x01, 0x00, 0x02},
      {0x03, 0x00, 0x0A, 0x00, 0x02},
      {0x16, 0x00, 0x05, 0x00, 0xF2, 0x00, 0x25},
      {0x03, 0x00, 0x05, 0x00, 0x01},
      {0x17, 0x00, 0x14, 0x00, 0x02, 0x00, 0x14, 0x00, 0x01, 0x02, 0xAB, 0xCD},
      {0x03, 0x00, 0x63, 0x00, 0x02},  // past the end: 02 from both
      {0x10, 0x00, 0x63, 0x00, 0x02, 0x04, 0x00, 0x01, 0x00, 0x02},
  };
  for (const bytes& q : requests) {
    CAPTURE(q[0]);
    CHECK(call(b, 0x11, q) == call(a, 0x11, q));
  }
  CHECK(b.holding[5] == ((0x1234 & 0x00F2) | (0x0025 & ~0x00F2)));
  CHECK(b.holding[20] == 0xABCD);
}

TEST_CASE("server: serve_frame answers a frame the framer checked, without decoding it again") {
  array_device dev;
  dev.holding[2] = 0xBEEF;
  const std::uint8_t pdu[] = {0x03, 0x00, 0x02, 0x00, 0x01};
  std::uint8_t adu[8] = {};
  REQUIRE(encode_rtu(0x11, byte_view(pdu, sizeof pdu), adu).value() == sizeof adu);
  rtu_framer rx({framer_role::server, 0x11});
  const auto f = rx.feed(byte_view(adu, sizeof adu));
  REQUIRE(f.is_complete());
  std::uint8_t out[256] = {};
  const auto n = serve_frame(dev, 0x11, f.value(), out);
  REQUIRE(n.ok());
  const auto r = decode_rtu(byte_view(out, n.value()));
  REQUIRE(r.is_complete());
  CHECK(bytes(r->pdu.begin(), r->pdu.end()) == bytes{0x03, 0x02, 0xBE, 0xEF});
  // the bitwise CRC gives the same ADU
  std::uint8_t out2[256] = {};
  CHECK(serve_frame<crc_table_size::bitwise>(dev, 0x11, f.value(), out2).value() == n.value());
  CHECK(std::equal(out, out + n.value(), out2));
  // another address, a frame without a PDU, a short output buffer
  CHECK(serve_frame(dev, 0x12, f.value(), out).value() == 0);
  rtu_frame empty;
  empty.slave = 0x11;
  CHECK(serve_frame(dev, 0x11, empty, out).value() == 0);
  CHECK(serve_frame(dev, 0x11, f.value(), mutable_byte_view(out, 255)).error() ==
        errc::buffer_too_small);
}

namespace {

// The array device restricted to reading registers: the other functions its accessors allow
// are answered with 01, and their requests are not decoded (no 03 for a bad count).
struct read_only_device : array_device {
  static constexpr function_set functions = functions_of(0x03, 0x04);
};

}  // namespace

TEST_CASE("server: a device's own function set narrows what its accessors allow") {
  read_only_device dev;
  dev.holding[1] = 0x0102;
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x01, 0x00, 0x01}) == bytes{0x03, 0x02, 0x01, 0x02});
  CHECK(call(dev, 0x11, {0x06, 0x00, 0x01, 0x12, 0x34}) == bytes{0x86, 0x01});
  CHECK(dev.holding[1] == 0x0102);
  CHECK(call(dev, 0x11, {0x01, 0x00, 0x00, 0x07, 0xD1}) == bytes{0x81, 0x01});  // not 03
  CHECK(call(dev, 0x11, {0x10, 0x00, 0x00, 0x00, 0x01, 0x02, 0x00, 0x01}) == bytes{0x90, 0x01});
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x00, 0x00, 0x7E}) == bytes{0x83, 0x03});  // its own: 03
  static_assert(functions_of(0x01, 0x10) == ((function_set{1} << 1U) | (function_set{1} << 16U)),
                "one bit per function");
}
