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
#include "server_differential.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

using namespace server_diff;  // NOLINT(google-build-using-namespace)

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

}  // namespace

int main(int argc, char** argv) {
  const unsigned long requests = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 20000UL;
  const unsigned long long seed = argc > 2 ? std::strtoull(argv[2], nullptr, 0) : 0x28D1FFULL;
  testutil::splitmix64 rng(seed);

  libmodbus_server theirs_server;
  if (!theirs_server.open()) {
    std::fprintf(stderr, "server_differential: cannot set up libmodbus\n");
    return 1;
  }
  modbus_mapping_t* const map = theirs_server.map;
  image dev;
  theirs_server.fill(dev, [&rng] { return rng.next(); });

  std::map<std::string, unsigned long> classes;
  unsigned long identical = 0;
  unsigned long failures = 0;
  for (unsigned long k = 0; k < requests; ++k) {
    const std::uint8_t slave = rng.below(16) == 0 ? 0 : 1;
    const std::vector<std::uint8_t> pdu = random_pdu(rng);
    std::uint8_t adu[mo::max_rtu_size];
    const std::size_t n = mo::encode_rtu(slave, mb::byte_view(pdu.data(), pdu.size()), adu).value();

    // libmodbus: modbus_reply writes its response to the socket pair
    std::uint8_t theirs[512];
    const std::size_t their_size = theirs_server.reply(adu, n, theirs);

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
    theirs_server.copy_to(dev);  // carry on from the same image: libmodbus's
  }
  std::printf("server differential (seed 0x%llX): %lu requests, %lu identical\n", seed, requests,
              identical);
  for (const auto& c : classes) {
    std::printf("  documented difference %s: %lu\n", c.first.c_str(), c.second);
  }
  if (failures != 0) {
    std::printf("server differential: %lu differences of no documented class\n", failures);
    return 1;
  }
  return 0;
}
