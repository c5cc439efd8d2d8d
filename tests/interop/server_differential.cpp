// The library's Modbus RTU server against libmodbus's modbus_reply (the Debian libmodbus the
// interop tests use), on the same register image and the same requests: random requests from a
// fixed seed (every function libmodbus serves, addresses and quantities around and across the
// mapping's edges, byte counts right and wrong, broadcasts), each a frame libmodbus's
// modbus_receive would deliver (its length follows the function and the byte count). After
// each request the two responses and the two images are compared: byte-identical, or a
// difference of a class docs/modbus.md lists ("Against libmodbus's server"), counted by class;
// any other difference fails, with the request and both answers.
// Usage: server_differential [REQUESTS] [SEED]
#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <motionbus/modbus.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "prng.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

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

bool same_image(const image& a, const modbus_mapping_t* m) {
  return std::memcmp(a.bits.data(), m->tab_bits, a.bits.size()) == 0 &&
         std::memcmp(a.registers.data(), m->tab_registers, a.registers.size() * 2U) == 0;
}

void put16(std::vector<std::uint8_t>& v, unsigned x) {
  v.push_back(static_cast<std::uint8_t>(x >> 8U));
  v.push_back(static_cast<std::uint8_t>(x & 0xFFU));
}

// An address around one of the tables' edges, or anywhere.
std::uint16_t pick_address(testutil::splitmix64& rng, std::uint16_t start, std::uint16_t count) {
  switch (rng.below(4)) {
    case 0: return static_cast<std::uint16_t>(rng.next());
    case 1: return static_cast<std::uint16_t>(start + count - rng.below(8));
    case 2: return static_cast<std::uint16_t>(start - rng.below(3));
    default: return static_cast<std::uint16_t>(start + rng.below(count));
  }
}

// A quantity around the function's limit, or small, or anything.
unsigned pick_quantity(testutil::splitmix64& rng, unsigned limit) {
  switch (rng.below(5)) {
    case 0: return static_cast<unsigned>(rng.below(0x10000));
    case 1: return limit - 1U + static_cast<unsigned>(rng.below(3));  // limit - 1, limit, limit + 1
    case 2: return 0;
    default: return 1U + static_cast<unsigned>(rng.below(20));
  }
}

// One request PDU (function and data) as the master could send it, its length what
// modbus_receive would read for it.
std::vector<std::uint8_t> random_pdu(testutil::splitmix64& rng) {
  static const std::uint8_t functions[] = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06,
                                           0x0F, 0x10, 0x16, 0x17, 0x00};
  std::uint8_t f = functions[rng.below(sizeof functions)];
  if (f == 0x00) {  // a function libmodbus does not serve (nor 0x11: its answer is its own)
    do {
      f = rng.byte();
    } while (f == 0x11 || (f >= 0x01 && f <= 0x06) || f == 0x0F || f == 0x10 || f == 0x16 ||
             f == 0x17);
  }
  std::vector<std::uint8_t> pdu{f};
  const bool bitwise = f == 0x01 || f == 0x02 || f == 0x05 || f == 0x0F;
  const bool input = f == 0x02 || f == 0x04;
  const std::uint16_t start = bitwise ? (input ? input_bits_start : bits_start)
                                      : (input ? input_registers_start : registers_start);
  const std::uint16_t count = bitwise ? (input ? input_bits_count : bits_count)
                                      : (input ? input_registers_count : registers_count);
  // the data bytes of a write: the right count, or one off, or any
  auto byte_count = [&](unsigned right) {
    switch (rng.below(6)) {
      case 0: return static_cast<unsigned>(rng.below(247));
      case 1: return right + 1U;
      case 2: return right == 0U ? 0U : right - 1U;
      default: return right;
    }
  };
  switch (f) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04:
      put16(pdu, pick_address(rng, start, count));
      put16(pdu, pick_quantity(rng, bitwise ? 2000U : 125U));
      break;
    case 0x05: {
      put16(pdu, pick_address(rng, start, count));
      static const unsigned values[] = {0xFF00, 0x0000, 0x00FF, 0xFFFF, 0x0001};
      put16(pdu, rng.below(3) != 0 ? values[rng.below(2)]
                                   : (rng.below(2) != 0 ? values[2 + rng.below(3)]
                                                        : static_cast<unsigned>(rng.next())));
      break;
    }
    case 0x06:
      put16(pdu, pick_address(rng, start, count));
      put16(pdu, static_cast<unsigned>(rng.next() & 0xFFFFU));
      break;
    case 0x0F:
    case 0x10: {
      put16(pdu, pick_address(rng, start, count));
      const unsigned q = pick_quantity(rng, f == 0x0F ? 1968U : 123U);
      put16(pdu, q);
      const unsigned right = f == 0x0F ? (q + 7U) / 8U : 2U * q;
      unsigned n = byte_count(right);
      if (n > 246U) {  // at most what a 256-byte frame holds
        n = static_cast<unsigned>(rng.below(247));
      }
      pdu.push_back(static_cast<std::uint8_t>(n));
      for (unsigned i = 0; i < n; ++i) {
        pdu.push_back(rng.byte());
      }
      break;
    }
    case 0x16:
      put16(pdu, pick_address(rng, start, count));
      put16(pdu, static_cast<unsigned>(rng.next() & 0xFFFFU));
      put16(pdu, static_cast<unsigned>(rng.next() & 0xFFFFU));
      break;
    case 0x17: {
      put16(pdu, pick_address(rng, start, count));
      put16(pdu, pick_quantity(rng, 125U));
      put16(pdu, pick_address(rng, start, count));
      const unsigned q = pick_quantity(rng, 121U);
      put16(pdu, q);
      unsigned n = byte_count(2U * q);
      if (n > 242U) {
        n = static_cast<unsigned>(rng.below(243));
      }
      pdu.push_back(static_cast<std::uint8_t>(n));
      for (unsigned i = 0; i < n; ++i) {
        pdu.push_back(rng.byte());
      }
      break;
    }
    default: break;  // an unserved function: its code alone
  }
  return pdu;
}

std::string hex(const std::uint8_t* p, std::size_t n) {
  std::string s;
  char b[4];
  for (std::size_t i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, "%02X ", p[i]);
    s += b;
  }
  return s;
}

// The documented class of a difference (docs/modbus.md, "Against libmodbus's server"), or ""
// when it is of none. `ours`/`theirs`: the two response ADUs (empty for no response).
std::string difference_class(const std::vector<std::uint8_t>& pdu, bool broadcast,
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

}  // namespace

int main(int argc, char** argv) {
  const unsigned long requests = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 20000UL;
  const unsigned long long seed = argc > 2 ? std::strtoull(argv[2], nullptr, 0) : 0x28D1FFULL;
  testutil::splitmix64 rng(seed);

  modbus_t* ctx = modbus_new_rtu("/dev/null", 9600, 'E', 8, 1);
  int sv[2];
  if (ctx == nullptr || modbus_set_slave(ctx, 1) != 0 ||
      socketpair(AF_UNIX, SOCK_STREAM, 0, sv) != 0 || modbus_set_socket(ctx, sv[0]) != 0 ||
      modbus_set_response_timeout(ctx, 0, 1) != 0) {  // (libmodbus waits it out after some
                                                      // exceptions before it flushes the line)
    std::fprintf(stderr, "server_differential: cannot set up libmodbus\n");
    return 1;
  }
  modbus_mapping_t* map = modbus_mapping_new_start_address(
      bits_start, bits_count, input_bits_start, input_bits_count, registers_start, registers_count,
      input_registers_start, input_registers_count);
  image dev;
  for (std::size_t i = 0; i < bits_count; ++i) {
    dev.bits[i] = map->tab_bits[i] = static_cast<std::uint8_t>(rng.below(2));
  }
  for (std::size_t i = 0; i < input_bits_count; ++i) {
    dev.input_bits[i] = map->tab_input_bits[i] = static_cast<std::uint8_t>(rng.below(2));
  }
  for (std::size_t i = 0; i < registers_count; ++i) {
    dev.registers[i] = map->tab_registers[i] = static_cast<std::uint16_t>(rng.next());
  }
  for (std::size_t i = 0; i < input_registers_count; ++i) {
    dev.input_registers[i] = map->tab_input_registers[i] = static_cast<std::uint16_t>(rng.next());
  }

  std::map<std::string, unsigned long> classes;
  unsigned long identical = 0;
  unsigned long failures = 0;
  for (unsigned long k = 0; k < requests; ++k) {
    const std::uint8_t slave = rng.below(16) == 0 ? 0 : 1;
    const std::vector<std::uint8_t> pdu = random_pdu(rng);
    std::uint8_t adu[mo::max_rtu_size];
    const std::size_t n = mo::encode_rtu(slave, mb::byte_view(pdu.data(), pdu.size()), adu).value();

    // libmodbus: modbus_reply writes its response to the socket pair
    modbus_reply(ctx, adu, static_cast<int>(n), map);
    std::uint8_t theirs[512];
    const ssize_t got = recv(sv[1], theirs, sizeof theirs, MSG_DONTWAIT);
    const std::size_t their_size = got > 0 ? static_cast<std::size_t>(got) : 0U;

    std::uint8_t ours[mo::max_rtu_size];
    const mo::rtu_frame frame = mo::decode_rtu(mb::byte_view(adu, n)).value();
    const std::size_t our_size = mo::serve_frame(dev, 1, frame, ours).value();

    const bool same_answer = our_size == their_size && std::memcmp(ours, theirs, our_size) == 0;
    const bool same_state = same_image(dev, map);
    if (same_answer && same_state) {
      ++identical;
      continue;
    }
    // the classes of difference docs/modbus.md lists
    const std::string cls = difference_class(pdu, slave == 0, ours, our_size, theirs, their_size);
    if (cls.empty()) {
      ++failures;
      if (failures <= 10) {
        std::printf("DIFFERENT #%lu: request %s\n  motionbus %s\n  libmodbus %s%s\n", k,
                    hex(adu, n).c_str(), hex(ours, our_size).c_str(),
                    hex(theirs, their_size).c_str(), same_state ? "" : "\n  (images differ)");
      }
    } else {
      ++classes[cls];
    }
    // carry on from the same image: libmodbus's
    std::memcpy(dev.bits.data(), map->tab_bits, dev.bits.size());
    std::memcpy(dev.registers.data(), map->tab_registers, dev.registers.size() * 2U);
  }
  std::printf("server differential (seed 0x%llX): %lu requests, %lu identical\n", seed, requests,
              identical);
  for (const auto& c : classes) {
    std::printf("  documented difference %s: %lu\n", c.first.c_str(), c.second);
  }
  modbus_mapping_free(map);
  modbus_free(ctx);
  close(sv[0]);
  close(sv[1]);
  if (failures != 0) {
    std::printf("server differential: %lu differences of no documented class\n", failures);
    return 1;
  }
  return 0;
}
