// Modbus server dispatch against an array-backed device: responses, exceptions from the codec
// and from the device, broadcasts, other addresses, missing accessors.
#include "motionbus/modbus/server.hpp"

#include "motionbus/modbus/framer.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>
#include "../support/bytes.hpp"
#include "../support/modbus.hpp"
#include "../support/stream.hpp"

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

// Registers only, written through write_registers_be: no read_bits, no report_server_id.
struct be_only_device {
  std::uint8_t write_registers_be(std::uint16_t, std::uint16_t, byte_view) { return 0; }
};
static_assert(served_functions<be_only_device>() == functions_of(0x06, 0x10),
              "a register writer alone serves 06 and 10");
static_assert(served_functions<array_device>() ==
                  functions_of(0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x10, 0x11, 0x16, 0x17),
              "every accessor: every function the dispatch serves");

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
  // a function the device's accessors do not serve (here: a device without read_bits)
  be_only_device regs;
  CHECK(call(regs, 0x11, {0x01, 0x00, 0x00, 0x00, 0x01}) == bytes{0x81, 0x01});
  CHECK(call(regs, 0x11, {0x11}) == bytes{0x91, 0x01});
}

// A server built as docs/modbus.md §3 describes: bytes in chunks from the UART into a framer
// with its default options, idle() at the end of the burst (the t3.5 timer), serve_rtu on every
// frame. Returns what it sends.
namespace {
std::vector<bytes> serve_stream(const bytes& stream, std::size_t chunk, framer_options options) {
  array_device dev;
  options.address = 0x11;
  rtu_framer rx(framer_role::server, options);
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
  const auto each = [&](const decode_result<rtu_frame>& r) {
    if (r.is_complete()) {
      answer(r.value());
    }
    return true;
  };
  feed_chunks(rx, view(stream), chunk, each);
  idle_all(rx, each);
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
    CHECK(serve_stream(count_zero, chunk, framer_options{0x11, frame_end::length}).empty());
    CHECK(serve_stream(unknown, chunk, framer_options{0x11, frame_end::length}).empty());
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
  rtu_framer rx(framer_role::server, {0x11});
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

namespace {

// The array device serving input registers alone (FC04, not FC03).
struct input_only_device : array_device {
  static constexpr function_set functions = functions_of(0x04);
};

}  // namespace

TEST_CASE("server: a device serving FC04 and not FC03 answers FC04 reads") {
  input_only_device dev;  // input register a reads 1000 + a
  CHECK(call(dev, 0x11, {0x04, 0x00, 0x02, 0x00, 0x01}) == bytes{0x04, 0x02, 0x03, 0xEA});
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x02, 0x00, 0x01}) == bytes{0x83, 0x01});
}

namespace {

// The array device, noting the size of the packed coils each write is handed.
struct packed_size_device : array_device {
  std::size_t packed_size = 0;
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, byte_view packed) {
    packed_size = packed.size();
    return array_device::write_coils(address, quantity, packed);
  }
};

}  // namespace

TEST_CASE("server: write_coils is handed the coils' bytes and no more (FC05: one byte)") {
  packed_size_device dev;
  CHECK(call(dev, 0x11, {0x05, 0x00, 0x03, 0xFF, 0x00}) == bytes{0x05, 0x00, 0x03, 0xFF, 0x00});
  CHECK(dev.packed_size == 1U);
  CHECK(dev.coils[3]);
  // FC0F, 10 coils: two bytes
  CHECK(call(dev, 0x11, {0x0F, 0x00, 0x00, 0x00, 0x0A, 0x02, 0xFF, 0x03}) ==
        bytes{0x0F, 0x00, 0x00, 0x00, 0x0A});
  CHECK(dev.packed_size == 2U);
}

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

namespace {

// 16 coils and 16 holding registers at addresses 0..15, as the device: an accessor
// that answers an exception has changed nothing.
struct table {
  std::uint16_t regs[16] = {};
  bool coils[16] = {};
  static bool fits(std::uint16_t address, std::size_t quantity) {
    return address + quantity <= 16U;
  }
  bool operator==(const table& o) const {
    return std::equal(regs, regs + 16, o.regs) && std::equal(coils, coils + 16, o.coils);
  }
};

struct u16_table : table {
  std::uint8_t read_bits(std::uint8_t, std::uint16_t address, std::uint16_t quantity,
                         mutable_byte_view packed) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (coils[address + i] << (i % 8U)));
    }
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, byte_view packed) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      coils[address + i] = bit_at(packed, i);
    }
    return 0;
  }
  std::uint8_t read_registers(std::uint8_t, std::uint16_t address, span<std::uint16_t> out) {
    if (!fits(address, out.size())) {
      return 0x02;
    }
    std::copy(regs + address, regs + address + out.size(), out.begin());
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, span<const std::uint16_t> values) {
    if (!fits(address, values.size())) {
      return 0x02;
    }
    std::copy(values.begin(), values.end(), regs + address);
    return 0;
  }
};

struct be_table : table {
  std::uint8_t read_registers_be(std::uint8_t, std::uint16_t address, std::uint16_t quantity,
                                 mutable_byte_view out) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      out[2 * i] = static_cast<std::uint8_t>(regs[address + i] >> 8U);
      out[2 * i + 1] = static_cast<std::uint8_t>(regs[address + i] & 0xFFU);
    }
    return 0;
  }
  std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity, byte_view data) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      regs[address + i] = register_at(data, i);
    }
    return 0;
  }
};

// The FC17 ranges checked by the device itself: the server then reads once, after the write.
struct checked_table : u16_table {
  int reads = 0;
  std::uint8_t check_registers(std::uint8_t, std::uint16_t address, std::uint16_t quantity) const {
    return fits(address, quantity) ? 0 : 0x02;
  }
  std::uint8_t read_registers(std::uint8_t f, std::uint16_t address, span<std::uint16_t> out) {
    ++reads;
    return u16_table::read_registers(f, address, out);
  }
};

// The response PDU to the RTU ADU `adu` through the framer and serve_frame (no second CRC
// pass); empty when nothing is sent.
template <class Device>
bytes call_frame(Device& dev, const bytes& adu, std::uint8_t own = 0x11) {
  rtu_framer rx(framer_role::server, {own});
  const auto f = rx.feed(byte_view(adu.data(), adu.size()));
  REQUIRE(f.is_complete());
  std::uint8_t out[256] = {};
  const auto r = serve_frame(dev, own, f.value(), out);
  REQUIRE(r.ok());
  if (r.value() == 0) {
    return {};
  }
  const auto d = decode_rtu(byte_view(out, r.value()));
  REQUIRE(d.is_complete());
  return bytes(d->pdu.begin(), d->pdu.end());
}

bytes adu_of(std::uint8_t slave, const bytes& pdu) {
  std::uint8_t adu[256] = {};
  const std::size_t n = encode_rtu(slave, byte_view(pdu.data(), pdu.size()), adu).value();
  return bytes(adu, adu + n);
}

// Every write request of the functions 05, 06, 0F, 10, 16 and 17 with starts and quantities
// about the end of a 16-entry table (inside, across the end, past it).
std::vector<bytes> writes_about_the_end() {
  const std::uint16_t starts[] = {0, 3, 12, 14, 15, 16, 17};
  const std::uint16_t counts[] = {1, 2, 4, 10};
  auto hi = [](unsigned v) { return static_cast<std::uint8_t>(v >> 8U); };
  auto lo = [](unsigned v) { return static_cast<std::uint8_t>(v & 0xFFU); };
  std::vector<bytes> out;
  for (std::uint16_t a : starts) {
    out.push_back({0x05, hi(a), lo(a), 0xFF, 0x00});
    out.push_back({0x06, hi(a), lo(a), 0x12, 0x50});
    out.push_back({0x16, hi(a), lo(a), 0x00, 0xF0, 0x12, 0x05});
    for (std::uint16_t q : counts) {
      bytes coils = {0x0F, hi(a), lo(a), hi(q), lo(q), static_cast<std::uint8_t>((q + 7U) / 8U)};
      coils.resize(coils.size() + (q + 7U) / 8U, 0xFF);  // every coil on
      out.push_back(coils);
      bytes regs = {0x10, hi(a), lo(a), hi(q), lo(q), static_cast<std::uint8_t>(2U * q)};
      for (unsigned i = 0; i < q; ++i) {
        regs.push_back(0x12);
        regs.push_back(static_cast<std::uint8_t>(0x50U + i));
      }
      out.push_back(regs);
      for (std::uint16_t wa : starts) {
        for (std::uint16_t wq : {std::uint16_t{1}, std::uint16_t{3}}) {
          bytes rw = {0x17,   hi(a),  lo(a),  hi(q),  lo(q),
                      hi(wa), lo(wa), hi(wq), lo(wq), static_cast<std::uint8_t>(2U * wq)};
          for (unsigned i = 0; i < wq; ++i) {
            rw.push_back(0x12);
            rw.push_back(static_cast<std::uint8_t>(0x50U + i));
          }
          out.push_back(rw);
        }
      }
    }
  }
  return out;
}

// For one device type: every request of writes_about_the_end() sent to the server's address
// through serve_rtu and through serve_frame, and as a broadcast; an exception leaves the data
// as they were, a normal response (or a broadcast whose unicast twin got one) has written.
template <class Device>
void check_exceptions_change_nothing() {
  int exceptions = 0;
  int normal = 0;
  for (const bytes& q : writes_about_the_end()) {
    std::string hex;
    for (const std::uint8_t b : q) {
      hex += "0123456789ABCDEF"[b >> 4U];
      hex += "0123456789ABCDEF"[b & 15U];
      hex += ' ';
    }
    CAPTURE(hex);
    Device start;
    for (std::uint16_t i = 0; i < 16; ++i) {
      start.regs[i] = static_cast<std::uint16_t>(0x0100U + i);
      start.coils[i] = false;  // the requests turn coils on: a write changes them
    }
    const bytes unicast = adu_of(0x11, q);
    Device by_rtu = start;
    const bytes answer = call(by_rtu, 0x11, q);
    REQUIRE(answer.size() >= 2U);
    Device by_frame = start;
    CHECK(call_frame(by_frame, unicast) == answer);
    Device by_broadcast = start;
    CHECK(call_frame(by_broadcast, adu_of(0x00, q)).empty());
    if ((answer[0] & 0x80U) != 0U) {
      ++exceptions;
      CHECK(static_cast<const table&>(by_rtu) == start);
      CHECK(static_cast<const table&>(by_frame) == start);
      CHECK(static_cast<const table&>(by_broadcast) == start);
    } else {
      ++normal;
      CHECK(!(static_cast<const table&>(by_rtu) == start));  // every request here writes
      CHECK(static_cast<const table&>(by_frame) == by_rtu);
      CHECK(static_cast<const table&>(by_broadcast) == by_rtu);
    }
  }
  CHECK(exceptions > 100);  // both outcomes are exercised
  CHECK(normal > 100);
}

}  // namespace

TEST_CASE("server: FC17 checks both ranges before it writes (Modbus App. Protocol §6.17)") {
  // the request: read 10 registers from 12 (past the end of 16), write 3 := 0x1250
  const bytes q = {0x17, 0x00, 0x0C, 0x00, 0x0A, 0x00, 0x03, 0x00, 0x01, 0x02, 0x12, 0x50};
  u16_table a;
  const bytes adu = adu_of(0x11, q);
  std::uint8_t out[256] = {};
  const auto n = serve_rtu(a, 0x11, byte_view(adu.data(), adu.size()), out);
  REQUIRE(n.ok());
  CHECK(bytes(out, out + n.value()) == bytes{0x11, 0x97, 0x02, 0xCE, 0x34});  // the reply
  CHECK(a.regs[3] == 0);
  CHECK(call(a, 0x00, q).empty());  // a broadcast is not written either
  CHECK(a.regs[3] == 0);
  be_table b;
  CHECK(call(b, 0x11, q) == bytes{0x97, 0x02});
  CHECK(call_frame(b, adu_of(0x00, q)).empty());
  CHECK(b.regs[3] == 0);
  checked_table c;
  CHECK(call(c, 0x11, q) == bytes{0x97, 0x02});
  CHECK(c.regs[3] == 0);
  CHECK(c.reads == 0);  // check_registers answered: nothing was read
  // the write range past the end: 02, nothing written
  const bytes w = {0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x0F, 0x00, 0x02, 0x04, 0, 1, 0, 2};
  CHECK(call(a, 0x11, w) == bytes{0x97, 0x02});
  CHECK(call(c, 0x11, w) == bytes{0x97, 0x02});
  CHECK(a.regs[15] == 0);
  CHECK(c.regs[15] == 0);
  // overlapping ranges: the read sees the write, read once when the device checks
  const bytes o = {0x17, 0x00, 0x02, 0x00, 0x03, 0x00, 0x03, 0x00, 0x01, 0x02, 0x12, 0x50};
  CHECK(call(a, 0x11, o) == bytes{0x17, 0x06, 0x00, 0x00, 0x12, 0x50, 0x00, 0x00});
  CHECK(call(b, 0x11, o) == bytes{0x17, 0x06, 0x00, 0x00, 0x12, 0x50, 0x00, 0x00});
  c.reads = 0;
  CHECK(call(c, 0x11, o) == bytes{0x17, 0x06, 0x00, 0x00, 0x12, 0x50, 0x00, 0x00});
  CHECK(c.reads == 1);
}

TEST_CASE("server: an exception means that nothing was done, unicast or broadcast") {
  SUBCASE("uint16_t accessors") {
    check_exceptions_change_nothing<u16_table>();
  }
  SUBCASE("big-endian accessors") {
    check_exceptions_change_nothing<be_table>();
  }
  SUBCASE("check_registers") {
    check_exceptions_change_nothing<checked_table>();
  }
}

namespace {

// A device whose registers fail once written (a device failure between FC17's write and read).
struct failing_after_write : u16_table {
  bool broken = false;
  std::uint8_t read_registers(std::uint8_t f, std::uint16_t address, span<std::uint16_t> out) {
    return broken ? 0x0B : u16_table::read_registers(f, address, out);
  }
  std::uint8_t write_registers(std::uint16_t address, span<const std::uint16_t> values) {
    broken = true;
    return u16_table::write_registers(address, values);
  }
};

// A device that reports more identification bytes than a PDU holds, or an exception.
struct huge_server_id {
  std::size_t report = 0;
  std::uint8_t code = 0;
  std::uint8_t report_server_id(mutable_byte_view, std::size_t& size) const {
    size = report;
    return code;
  }
};

}  // namespace

TEST_CASE("server: failures after the checks are device failures (04)") {
  // FC17 whose read fails after the write: §6.17's processing failure, 04
  failing_after_write dev;
  CHECK(call(dev, 0x11, {0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x07}) ==
        bytes{0x97, 0x04});
  // FC11 whose reported size does not fit the PDU, the largest size_t included (no wrap-around)
  huge_server_id id;
  for (std::size_t size : {std::size_t{252}, std::size_t{253}, ~std::size_t{0}}) {
    CAPTURE(size);
    id.report = size;
    const bytes r = call(id, 0x11, {0x11});
    if (size == 252U) {
      CHECK(r.size() == 253U);  // the largest PDU
      CHECK(r[0] == 0x11);
    } else {
      CHECK(r == bytes{0x91, 0x04});
    }
  }
}

namespace {

// admit and check_registers overloaded on const: the server calls the const ones (checks change
// nothing); the others would answer 04 and count a call.
struct const_checks : u16_table {
  int non_const_calls = 0;
  std::uint8_t admit(byte_view) const { return 0; }
  std::uint8_t admit(byte_view) {
    ++non_const_calls;
    return 0x04;
  }
  std::uint8_t check_registers(std::uint8_t, std::uint16_t address, std::uint16_t quantity) const {
    return fits(address, quantity) ? 0 : 0x02;
  }
  std::uint8_t check_registers(std::uint8_t, std::uint16_t, std::uint16_t) {
    ++non_const_calls;
    return 0x04;
  }
};

}  // namespace

TEST_CASE("server: admit and check_registers are called const, whatever the device overloads") {
  const_checks dev;
  dev.regs[2] = 0x0102;
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x02, 0x00, 0x01}) == bytes{0x03, 0x02, 0x01, 0x02});
  // FC17: read 2 from 2, write 3 := 0x1250; the const check lets both ranges through
  CHECK(call(dev, 0x11, {0x17, 0x00, 0x02, 0x00, 0x02, 0x00, 0x03, 0x00, 0x01, 0x02, 0x12, 0x50}) ==
        bytes{0x17, 0x04, 0x01, 0x02, 0x12, 0x50});
  CHECK(call(dev, 0x11, {0x17, 0x00, 0x0F, 0x00, 0x02, 0x00, 0x03, 0x00, 0x01, 0x02, 0x00, 0x07}) ==
        bytes{0x97, 0x02});  // the const check's own answer
  CHECK(dev.regs[3] == 0x1250);
  CHECK(dev.non_const_calls == 0);
}

TEST_CASE("server: units 1-4 on one port as four devices (serve_units)") {
  unit_device dev[4] = {{1}, {2}, {3}, {4}};
  int asked_broadcast = 0;
  auto lookup = [&](std::uint8_t unit) -> unit_device* {
    if (unit == 0) {
      ++asked_broadcast;
      return &dev[1];  // the broadcast: executed by unit 2 alone, here
    }
    return unit - 1U < 4U ? &dev[unit - 1U] : nullptr;
  };
  rtu_server_framer rx({1, frame_end::silence, report_id_format::standard, 4});
  bytes stream;
  for (const std::uint8_t slave : bytes{1, 2, 3, 4, 5, 0}) {
    const bytes f = rtu(slave, slave == 0 ? bytes{0x06, 0, 1, 0, 9} : bytes{0x03, 0, 2, 0, 1});
    stream.insert(stream.end(), f.begin(), f.end());
  }
  std::vector<bytes> answers;
  feed_all(rx, view(stream), [&](const decode_result<rtu_frame>& r) {
    REQUIRE(r.is_complete());
    std::uint8_t out[256] = {};
    const auto n = serve_units(lookup, r.value(), out);
    REQUIRE(n.ok());
    if (n.value() != 0U) {
      answers.push_back(bytes(out, out + n.value()));
    }
    return true;
  });
  REQUIRE(answers.size() == 4);  // unit 5 is not taken, the broadcast not answered
  for (std::uint8_t u = 1; u <= 4; ++u) {
    CHECK(answers[u - 1U] == rtu(u, {0x03, 0x02, u, 0x02}));  // each answers as itself
  }
  CHECK(asked_broadcast == 1);
  CHECK(dev[1].writes == 1);
  CHECK(dev[0].writes + dev[2].writes + dev[3].writes == 0);
  // a unit the framer takes but the lookup has no device for: no response
  std::uint8_t out[256] = {};
  const bytes five = rtu(5, {0x03, 0, 2, 0, 1});
  const auto f = decode_rtu(view(five));
  REQUIRE(f.is_complete());
  CHECK(serve_units(lookup, f.value(), out).value() == 0);
  CHECK(serve_units(lookup, f.value(), mutable_byte_view(out, 255)).error() ==
        errc::buffer_too_small);
  // an exception answers as the unit too
  const bytes bad = rtu(3, {0x03, 0, 19, 0, 2});
  const auto g = decode_rtu(view(bad));
  REQUIRE(g.is_complete());
  const std::size_t n = serve_units(lookup, g.value(), out).value();
  CHECK(bytes(out, out + n) == rtu(3, {0x83, 0x02}));
}

TEST_CASE("server: serve_pdu serves a PDU with no address and CRC (Modbus TCP)") {
  array_device dev;
  dev.holding[5] = 0xBEEF;
  std::uint8_t out[max_pdu_size] = {};
  const auto respond = [&](const bytes& pdu) {
    const auto n = serve_pdu(dev, view(pdu), out);
    REQUIRE(n.ok());
    return bytes(out, out + n.value());
  };
  CHECK(respond({0x03, 0, 5, 0, 1}) == bytes{0x03, 0x02, 0xBE, 0xEF});
  CHECK(respond({0x06, 0, 6, 0x12, 0x34}) == bytes{0x06, 0, 6, 0x12, 0x34});
  CHECK(dev.holding[6] == 0x1234);
  CHECK(respond({0x2B, 0x0E, 1, 0}) == bytes{0xAB, 0x01});  // not served: 01
  CHECK(respond({0x03, 0, 5, 0, 0}) == bytes{0x83, 0x03});  // quantity 0: 03
  CHECK(respond({0x03, 0, 99, 0, 2}) == bytes{0x83, 0x02});
  CHECK(respond({0x03, 0, 5}) == bytes{0x83, 0x03});  // truncated
  CHECK(respond({}).empty());
  // the same answers as serve_frame's, address and CRC aside
  for (const bytes& pdu : {bytes{0x01, 0, 0, 0, 9}, bytes{0x10, 0, 1, 0, 1, 2, 0, 7},
                           bytes{0x17, 0, 1, 0, 1, 0, 2, 0, 1, 2, 0, 3}, bytes{0x11}}) {
    array_device a;
    array_device b;
    CHECK(call(a, 0x11, pdu) == bytes(out, out + serve_pdu(b, view(pdu), out).value()));
  }
  CHECK(serve_pdu(dev, view(bytes{0x03, 0, 5, 0, 1}), mutable_byte_view(out, 252)).error() ==
        errc::buffer_too_small);
}

TEST_CASE("server: FC11 answered with the exception its accessor returns") {
  huge_server_id id;
  id.report = 3;
  id.code = 0x04;
  CHECK(call(id, 0x11, {0x11}) == bytes{0x91, 0x04});
  id.code = 0x06;  // busy
  CHECK(call(id, 0x11, {0x11}) == bytes{0x91, 0x06});
  id.code = 0;
  CHECK(call(id, 0x11, {0x11}).size() == 4U);
}

namespace {

// Holding registers through read_registers that fills every register asked with 0xA5C3, or,
// when `skip` is set, writes none of them and answers 0.
struct lazy_reader {
  bool skip = false;
  std::uint8_t read_registers(std::uint8_t, std::uint16_t, span<std::uint16_t> out) {
    if (!skip) {
      std::fill(out.begin(), out.end(), std::uint16_t{0xA5C3});
    }
    return 0;
  }
};

}  // namespace

TEST_CASE("server: read_registers gets its registers cleared: one left unwritten reads 0") {
  // the header: a device that leaves a register unwritten answers 0 for it, never a stale
  // stack value (the first read leaves 0xA5C3 where the server's buffer lives)
  lazy_reader dev;
  std::uint8_t out[max_pdu_size] = {};
  for (const std::uint8_t f : {std::uint8_t{0x03}, std::uint8_t{0x04}}) {
    CAPTURE(f);
    const bytes q = {f, 0x00, 0x00, 0x00, 0x7D};  // 125 registers, the most
    dev.skip = false;
    REQUIRE(serve_pdu(dev, view(q), out).value() == 252U);
    CHECK(out[2] == 0xA5);
    CHECK(out[251] == 0xC3);
    dev.skip = true;
    REQUIRE(serve_pdu(dev, view(q), out).value() == 252U);
    CHECK(out[0] == f);
    CHECK(out[1] == 250U);
    CHECK(std::all_of(out + 2, out + 252, [](std::uint8_t b) { return b == 0U; }));
  }
}

namespace {

// Registers read as big-endian bytes, noting the size of the view each read is handed.
struct be_size_reader {
  std::size_t out_size = 0;
  std::uint8_t read_registers_be(std::uint8_t, std::uint16_t address, std::uint16_t quantity,
                                 mutable_byte_view out) {
    out_size = out.size();
    for (std::size_t i = 0; i < quantity; ++i) {
      store_be16(out, 2U * i, static_cast<std::uint16_t>(address + i));
    }
    return 0;
  }
};

}  // namespace

TEST_CASE("server: read_registers_be is handed the registers' bytes and no more") {
  be_size_reader dev;
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x07, 0x00, 0x01}) == bytes{0x03, 0x02, 0x00, 0x07});
  CHECK(dev.out_size == 2U);
  CHECK(call(dev, 0x11, {0x04, 0x01, 0x00, 0x00, 0x03}) ==
        bytes{0x04, 0x06, 0x01, 0x00, 0x01, 0x01, 0x01, 0x02});
  CHECK(dev.out_size == 6U);
  CHECK(call(dev, 0x11, {0x03, 0x00, 0x00, 0x00, 0x7D}).size() == 252U);  // 125 registers
  CHECK(dev.out_size == 250U);
}

namespace {

// The array device serving only the functions F of those its accessors allow.
template <function_set F>
struct narrowed : array_device {
  static constexpr function_set functions = F;
};

// The response to `pdu` from an array device that serves function F alone.
template <std::uint8_t F>
bytes served_alone(const bytes& pdu) {
  static_assert(served_functions<narrowed<functions_of(F)>>() == functions_of(F), "F alone");
  narrowed<functions_of(F)> dev;
  return call(dev, 0x11, pdu);
}

}  // namespace

TEST_CASE("server: a device's functions may name one function of a pair; it is served") {
  // each function alone, the other of its pair (01/02, 03/04, 05/0F, 06/10, 16/17) not served
  CHECK(served_alone<0x01>({0x01, 0x00, 0x00, 0x00, 0x08}) == bytes{0x01, 0x01, 0x00});
  CHECK(served_alone<0x01>({0x02, 0x00, 0x00, 0x00, 0x08}) == bytes{0x82, 0x01});
  CHECK(served_alone<0x02>({0x02, 0x00, 0x00, 0x00, 0x03}) == bytes{0x02, 0x01, 0x01});
  CHECK(served_alone<0x03>({0x03, 0x00, 0x05, 0x00, 0x01}) == bytes{0x03, 0x02, 0x00, 0x00});
  CHECK(served_alone<0x03>({0x04, 0x00, 0x05, 0x00, 0x01}) == bytes{0x84, 0x01});
  CHECK(served_alone<0x04>({0x04, 0x00, 0x02, 0x00, 0x01}) == bytes{0x04, 0x02, 0x03, 0xEA});
  CHECK(served_alone<0x05>({0x05, 0x00, 0x03, 0xFF, 0x00}) == bytes{0x05, 0x00, 0x03, 0xFF, 0x00});
  CHECK(served_alone<0x05>({0x0F, 0x00, 0x00, 0x00, 0x01, 0x01, 0x01}) == bytes{0x8F, 0x01});
  CHECK(served_alone<0x0F>({0x0F, 0x00, 0x00, 0x00, 0x0A, 0x02, 0xFF, 0x03}) ==
        bytes{0x0F, 0x00, 0x00, 0x00, 0x0A});
  CHECK(served_alone<0x06>({0x06, 0x00, 0x06, 0x12, 0x34}) == bytes{0x06, 0x00, 0x06, 0x12, 0x34});
  CHECK(served_alone<0x06>({0x10, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x07}) == bytes{0x90, 0x01});
  CHECK(served_alone<0x10>({0x10, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x07}) ==
        bytes{0x10, 0x00, 0x01, 0x00, 0x01});
  CHECK(served_alone<0x16>({0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25}) ==
        bytes{0x16, 0x00, 0x04, 0x00, 0xF2, 0x00, 0x25});
  CHECK(served_alone<0x16>({0x17, 0x00, 0x01, 0x00, 0x01, 0x00, 0x02, 0x00, 0x01, 0x02, 0x00,
                            0x03}) == bytes{0x97, 0x01});
  CHECK(served_alone<0x17>({0x17, 0x00, 0x01, 0x00, 0x01, 0x00, 0x02, 0x00, 0x01, 0x02, 0x00,
                            0x03}) == bytes{0x17, 0x02, 0x00, 0x00});
}

namespace {

// FC17's ranges checked by the device, each check noted (function, address, quantity); the
// register `protected_register` may not be written by FC17, though write_registers takes it.
struct noted_checks : u16_table {
  mutable std::vector<std::vector<unsigned>> checks;
  std::uint16_t protected_register = 0xFFFF;
  std::uint8_t check_registers(std::uint8_t function, std::uint16_t address,
                               std::uint16_t quantity) const {
    checks.push_back({function, address, quantity});
    if (function == 0x10 && address <= protected_register &&
        protected_register - address < quantity) {
      return 0x02;
    }
    return fits(address, quantity) ? 0 : 0x02;
  }
};

}  // namespace

TEST_CASE("server: FC17 asks check_registers for the read range as 03, the write range as 10") {
  noted_checks dev;
  dev.regs[2] = 0x0102;
  // read 2 from 2, write 3 := 0x1250
  const bytes q = {0x17, 0x00, 0x02, 0x00, 0x02, 0x00, 0x03, 0x00, 0x01, 0x02, 0x12, 0x50};
  CHECK(call(dev, 0x11, q) == bytes{0x17, 0x04, 0x01, 0x02, 0x12, 0x50});
  CHECK(dev.checks == std::vector<std::vector<unsigned>>{{0x03, 2, 2}, {0x10, 3, 1}});
  // the write range refused by the check: 02 and nothing written, though the write accessor
  // would have taken it (§6.17: both ranges checked before anything is done)
  dev.checks.clear();
  dev.regs[3] = 0;
  dev.protected_register = 3;
  CHECK(call(dev, 0x11, q) == bytes{0x97, 0x02});
  CHECK(dev.regs[3] == 0);
  CHECK(dev.checks == std::vector<std::vector<unsigned>>{{0x03, 2, 2}, {0x10, 3, 1}});
}

TEST_CASE("server: serve_pdu writes a read-bits response and nothing past it") {
  // as the PDU encoders: the bytes returned, none after them (the response is built in place)
  array_device dev;
  dev.coils[8] = true;
  std::uint8_t out[max_pdu_size] = {};
  for (const std::uint8_t f : {std::uint8_t{0x01}, std::uint8_t{0x02}}) {
    CAPTURE(f);
    std::fill(out, out + max_pdu_size, std::uint8_t{0xEE});
    REQUIRE(serve_pdu(dev, view(bytes{f, 0x00, 0x00, 0x00, 0x09}), out).value() == 4U);
    CHECK(out[0] == f);
    CHECK(out[1] == 2U);
    CHECK(out[2] == (f == 0x01 ? 0x00 : 0x49));  // discrete inputs 0, 3 and 6
    CHECK(out[3] == (f == 0x01 ? 0x01 : 0x00));  // coil 8
    CHECK(std::all_of(out + 4, out + max_pdu_size, [](std::uint8_t b) { return b == 0xEE; }));
  }
}

namespace {

// FC11 reported by appending to the size it is handed (out[size++] = ...), noting that size.
struct appending_server_id {
  std::size_t handed = 99;
  std::uint8_t report_server_id(mutable_byte_view out, std::size_t& size) {
    handed = size;
    out[size++] = 2;  // byte count
    out[size++] = 0x42;
    out[size++] = 0xFF;  // run indicator: on
    return 0;
  }
};

}  // namespace

TEST_CASE("server: report_server_id is handed a size of 0, to which it may add its bytes") {
  appending_server_id id;
  CHECK(call(id, 0x11, {0x11}) == bytes{0x11, 0x02, 0x42, 0xFF});
  CHECK(id.handed == 0U);
}
