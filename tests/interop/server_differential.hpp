// The server differential's two servers (tests/interop/server_differential.cpp, ctest
// interop.server_differential, and fuzz/interop/server_libmodbus_fuzz.cpp): the library's
// device on its own copy of a register image, libmodbus's modbus_reply on a mapping of the same
// image (an RTU context writing to a socket pair), and the classes of difference
// docs/modbus.md §13 lists.
#ifndef MOTIONBUS_TESTS_INTEROP_SERVER_DIFFERENTIAL_HPP
#define MOTIONBUS_TESTS_INTEROP_SERVER_DIFFERENTIAL_HPP

#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <motionbus/modbus.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace server_diff {

namespace mb = motionbus;
namespace mo = motionbus::modbus;

// The mapping: each table's first address and size (libmodbus's
// modbus_mapping_new_start_address).
constexpr std::uint16_t bits_start = 100;
constexpr std::uint16_t bits_count = 300;
constexpr std::uint16_t input_bits_start = 0;
constexpr std::uint16_t input_bits_count = 2100;
constexpr std::uint16_t registers_start = 1000;
constexpr std::uint16_t registers_count = 200;
constexpr std::uint16_t input_registers_start = 0xFF00;
constexpr std::uint16_t input_registers_count = 0x100;

// The library's device on its own copy of the same image (libmodbus's tables: one byte per
// bit, a uint16 per register).
struct image {
  std::vector<std::uint8_t> bits = std::vector<std::uint8_t>(bits_count);
  std::vector<std::uint8_t> input_bits = std::vector<std::uint8_t>(input_bits_count);
  std::vector<std::uint16_t> registers = std::vector<std::uint16_t>(registers_count);
  std::vector<std::uint16_t> input_registers = std::vector<std::uint16_t>(input_registers_count);

  static bool inside(std::uint16_t address, std::size_t quantity, std::uint16_t start,
                     std::size_t count) {
    return address >= start && address - start + quantity <= count;
  }
  std::uint8_t read_bits(std::uint8_t function, std::uint16_t address, std::uint16_t quantity,
                         mb::mutable_byte_view packed) {
    const bool coils = function == 0x01;
    const std::vector<std::uint8_t>& table = coils ? bits : input_bits;
    const std::uint16_t start = coils ? bits_start : input_bits_start;
    if (!inside(address, quantity, start, table.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      const auto bit = static_cast<std::uint8_t>(1U << (i % 8U));
      packed[i / 8U] = static_cast<std::uint8_t>(
          table[address - start + i] != 0U ? (packed[i / 8U] | bit) : (packed[i / 8U] & ~bit));
    }
    return 0;
  }
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              mb::span<std::uint16_t> out) {
    const bool holding = function != 0x04;
    const std::vector<std::uint16_t>& table = holding ? registers : input_registers;
    const std::uint16_t start = holding ? registers_start : input_registers_start;
    if (!inside(address, out.size(), start, table.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = table[address - start + i];
    }
    return 0;
  }
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, mb::byte_view packed) {
    if (!inside(address, quantity, bits_start, bits.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      bits[address - bits_start + i] = static_cast<std::uint8_t>((packed[i / 8U] >> (i % 8U)) & 1U);
    }
    return 0;
  }
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> values) {
    if (!inside(address, values.size(), registers_start, registers.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      registers[address - registers_start + i] = values[i];
    }
    return 0;
  }
};

inline bool same_image(const image& a, const modbus_mapping_t* m) {
  return std::memcmp(a.bits.data(), m->tab_bits, a.bits.size()) == 0 &&
         std::memcmp(a.registers.data(), m->tab_registers, a.registers.size() * 2U) == 0;
}

// libmodbus's server: modbus_reply on `map`, its response read back from the socket pair.
struct libmodbus_server {
  modbus_t* ctx = nullptr;
  modbus_mapping_t* map = nullptr;
  int sv[2] = {-1, -1};

  /// False when libmodbus cannot be set up.
  bool open() {
    ctx = modbus_new_rtu("/dev/null", 9600, 'E', 8, 1);
    // a response timeout of 1 us: libmodbus waits it out after some exceptions, before it
    // flushes the line
    if (ctx == nullptr || modbus_set_slave(ctx, 1) != 0 ||
        socketpair(AF_UNIX, SOCK_STREAM, 0, sv) != 0 || modbus_set_socket(ctx, sv[0]) != 0 ||
        modbus_set_response_timeout(ctx, 0, 1) != 0) {
      return false;
    }
    map = modbus_mapping_new_start_address(bits_start, bits_count, input_bits_start,
                                           input_bits_count, registers_start, registers_count,
                                           input_registers_start, input_registers_count);
    return map != nullptr;
  }
  ~libmodbus_server() {
    if (map != nullptr) {
      modbus_mapping_free(map);
    }
    if (ctx != nullptr) {
      modbus_free(ctx);
    }
    for (const int fd : sv) {
      if (fd >= 0) {
        close(fd);
      }
    }
  }
  /// The response ADU to the request ADU `adu` in `out` (512 bytes); its size, 0 for none.
  std::size_t reply(const std::uint8_t* adu, std::size_t n, std::uint8_t* out) {
    modbus_reply(ctx, adu, static_cast<int>(n), map);
    const ssize_t got = recv(sv[1], out, 512, MSG_DONTWAIT);
    return got > 0 ? static_cast<std::size_t>(got) : 0U;
  }
  /// The library's image becomes libmodbus's (after a difference, to carry on from one image).
  void copy_to(image& dev) const {
    std::memcpy(dev.bits.data(), map->tab_bits, dev.bits.size());
    std::memcpy(dev.registers.data(), map->tab_registers, dev.registers.size() * 2U);
  }
  /// libmodbus's image becomes `from` (every table).
  void load(const image& from) {
    std::memcpy(map->tab_bits, from.bits.data(), from.bits.size());
    std::memcpy(map->tab_input_bits, from.input_bits.data(), from.input_bits.size());
    std::memcpy(map->tab_registers, from.registers.data(), from.registers.size() * 2U);
    std::memcpy(map->tab_input_registers, from.input_registers.data(),
                from.input_registers.size() * 2U);
  }
  /// Both images from `next()` (a source of random 64-bit values).
  template <class Next>
  void fill(image& dev, Next&& next) {
    for (std::size_t i = 0; i < bits_count; ++i) {
      dev.bits[i] = map->tab_bits[i] = static_cast<std::uint8_t>(next() & 1U);
    }
    for (std::size_t i = 0; i < input_bits_count; ++i) {
      dev.input_bits[i] = map->tab_input_bits[i] = static_cast<std::uint8_t>(next() & 1U);
    }
    for (std::size_t i = 0; i < registers_count; ++i) {
      dev.registers[i] = map->tab_registers[i] = static_cast<std::uint16_t>(next());
    }
    for (std::size_t i = 0; i < input_registers_count; ++i) {
      dev.input_registers[i] = map->tab_input_registers[i] = static_cast<std::uint16_t>(next());
    }
  }
};

// The documented class of a difference (docs/modbus.md, "Against libmodbus's server"), or ""
// when it is of none. `ours`/`theirs`: the two response ADUs (empty for no response).
inline std::string difference_class(const std::vector<std::uint8_t>& pdu, bool broadcast,
                                    const std::uint8_t* ours, std::size_t our_size,
                                    const std::uint8_t* theirs, std::size_t their_size) {
  const std::uint8_t f = pdu[0];
  const bool our_exception = our_size == 5U && ours[1] == (f | 0x80U);
  const bool their_exception = their_size == 5U;
  // 1. a request function code with its top bit set (no function has one): the library
  //    answers 01 with the code as it came (its top bit the exception flag); libmodbus adds
  //    0x80 to it, which wraps to a code without the flag (a normal response's)
  if (f >= 0x80U && our_exception && ours[2] == 0x01U && their_size == 5U &&
      theirs[1] == static_cast<std::uint8_t>(f + 0x80U) && theirs[2] == 0x01U) {
    return "function code >= 0x80";
  }
  // 2. a write whose byte count is not the one its quantity needs (FC0F: (quantity + 7) / 8,
  //    FC10: 2 x quantity, FC17: 2 x write quantity): the library refuses it (03); libmodbus
  //    takes a larger count (FC0F, FC10) and answers or executes as if it were right, or
  //    checks the address first
  if (f == 0x0FU || f == 0x10U || f == 0x17U) {
    const std::size_t at = f == 0x17U ? 9U : 5U;
    const unsigned q = (static_cast<unsigned>(pdu[at - 2U]) << 8U) | pdu[at - 1U];
    const unsigned right = f == 0x0FU ? (q + 7U) / 8U : 2U * q;
    if (pdu.size() > at && pdu[at] != right && (broadcast ? our_size == 0U : our_exception) &&
        (broadcast || ours[2] == 0x03U)) {
      return "byte count not the quantity's";
    }
  }
  // 3. FC05 with a value other than FF00 or 0000 at an address outside the coils: the library
  //    answers 03 (the value is checked first), libmodbus 02
  if (f == 0x05U && our_exception && ours[2] == 0x03U && their_exception && theirs[2] == 0x02U) {
    return "FC05 value and address both wrong";
  }
  // 4. FC07 (read exception status, serial line only), which libmodbus knows but does not
  //    serve: libmodbus sends nothing, the library answers 01 (illegal function) as to any
  //    function its device does not serve
  if (f == 0x07U && our_exception && ours[2] == 0x01U && their_size == 0U) {
    return "FC07: libmodbus does not answer";
  }
  return "";
}

}  // namespace server_diff

#endif
