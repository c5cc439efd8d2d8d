// The Modbus ASCII framer and the RTU framer over TCP (frame_end::length) or on a serial line
// (frame_end::silence: `idle` lines are the t3.5 silences) driven by text lines on stdin, for
// tests/interop/pymodbus_framers.py and pymodbus_framer_differential.py, which compare them
// with pymodbus's framers:
//   framers_tool ascii|rtu-tcp|rtu server|client|listener ADDRESS
// Lines in:  sent HEX   (the request written: sent())
//            feed CHUNK HEX   (the bytes in chunks of CHUNK: feed_all)
//            put HEX    (one byte at a time: put_each)
//            idle       (idle())
//            encode SLAVE HEXPDU   (encode_ascii or encode_rtu)
// Lines out: frame SLAVE HEXPDU | error NAME | encoded HEX | bad-line
#include <motionbus/core/stream.hpp>
#include <motionbus/modbus/ascii.hpp>
#include <motionbus/modbus/framer.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "../support/hex.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

std::vector<std::uint8_t> from_hex(const std::string& s) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i + 1 < s.size(); i += 2) {
    out.push_back(static_cast<std::uint8_t>(std::stoul(s.substr(i, 2), nullptr, 16)));
  }
  return out;
}

template <class Result>
bool print(const Result& r) {
  if (r.is_complete()) {
    std::cout << "frame " << unsigned{r.value().slave} << ' ' << testutil::to_hex(r.value().pdu)
              << '\n';
  } else if (r.is_failed()) {
    std::cout << "error " << mb::to_string(r.error()) << '\n';
  }
  return true;
}

template <class Framer, class Encode>
int run(Framer& f, Encode&& encode) {
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string op;
    in >> op;
    if (op == "sent") {
      std::string hex;
      in >> hex;
      const auto b = from_hex(hex);
      f.sent(mb::byte_view(b.data(), b.size()));
    } else if (op == "feed") {
      std::size_t chunk = 1;
      std::string hex;
      in >> chunk >> hex;
      const auto b = from_hex(hex);
      for (std::size_t at = 0; at < b.size(); at += chunk) {
        const std::size_t n = chunk < b.size() - at ? chunk : b.size() - at;
        (void)mb::feed_all(f, mb::byte_view(b.data() + at, n),
                           [](const auto& r) { return print(r); });
      }
    } else if (op == "put") {
      std::string hex;
      in >> hex;
      for (const std::uint8_t c : from_hex(hex)) {
        mb::put_each(f, c, [](const auto& r) { return print(r); });
      }
    } else if (op == "idle") {
      (void)print(f.idle());
    } else if (op == "encode") {
      unsigned slave = 0;
      std::string hex;
      in >> slave >> hex;
      const auto pdu = from_hex(hex);
      std::uint8_t out[mo::max_ascii_size] = {};
      const auto n = encode(static_cast<std::uint8_t>(slave), mb::byte_view(pdu.data(), pdu.size()),
                            mb::mutable_byte_view(out, sizeof out));
      if (n.ok()) {
        std::cout << "encoded " << testutil::to_hex(mb::byte_view(out, n.value())) << '\n';
      } else {
        std::cout << "error " << mb::to_string(n.error()) << '\n';
      }
    } else {
      std::cout << "bad-line\n";
    }
    std::cout.flush();
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: framers_tool ascii|rtu-tcp|rtu server|client|listener ADDRESS\n";
    return 2;
  }
  const std::string mode = argv[1];
  const std::string role_name = argv[2];
  const auto address = static_cast<std::uint8_t>(std::strtoul(argv[3], nullptr, 0));
  const mo::framer_role role = role_name == "client"     ? mo::framer_role::client
                               : role_name == "listener" ? mo::framer_role::listener
                                                         : mo::framer_role::server;
  if (mode == "ascii") {
    mo::ascii_framer f(role, mo::ascii_options{address});
    return run(f, [](std::uint8_t s, mb::byte_view p, mb::mutable_byte_view o) {
      return mo::encode_ascii(s, p, o);
    });
  }
  mo::rtu_framer f(
      role == mo::framer_role::client ? role : mo::framer_role::server,
      mo::framer_options{address, mode == "rtu" ? mo::frame_end::silence : mo::frame_end::length});
  return run(f, [](std::uint8_t s, mb::byte_view p, mb::mutable_byte_view o) {
    return mo::encode_rtu(s, p, o);
  });
}
