// The library's client response checks against libmodbus's (the Debian libmodbus the interop
// tests use): random requests from a fixed seed, each made by libmodbus's own call
// (modbus_read_registers, modbus_write_bits, ...: check_confirmation checks the response
// against the request), and a response to it, valid or (mostly) mutated: a bit flipped, a byte
// changed, the byte count off by one, the PDU cut or extended, another function or the
// exception flag, another slave (each with its CRC made right again), a bad CRC, the frame
// cut, bytes after it. libmodbus reads the response from a socket pair; the library's client
// frames the same bytes (rtu_client_framer, the silence after them) and decodes the frame with
// decode_response_for against the request libmodbus sent. Accepted, exception (its code) or
// refused, and the values read, must agree, or differ by a class docs/modbus.md §15 lists,
// counted by class; any other difference fails, with the request and the response.
// Usage: client_differential [EXCHANGES] [SEED]
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "../support/hex.hpp"
#include "client_differential.hpp"

namespace {

using namespace client_diff;  // NOLINT(google-build-using-namespace)

// The response to `q`: valid one time in five, else one to three mutations of a valid one.
std::vector<std::uint8_t> random_response(testutil::splitmix64& rng, const request& q) {
  std::vector<std::uint8_t> pdu = valid_response(rng, q);
  std::uint8_t slave = q.slave;
  bool bad_crc = false;
  std::size_t cut = 0;
  std::vector<std::uint8_t> after;
  const unsigned mutations = rng.below(5) == 0 ? 0U : 1U + static_cast<unsigned>(rng.below(3));
  for (unsigned m = 0; m < mutations; ++m) {
    switch (rng.below(12)) {
      case 0:  // a bit flipped
      {
        const std::size_t bit = rng.below(pdu.size() * 8U);
        pdu[bit / 8U] = static_cast<std::uint8_t>(pdu[bit / 8U] ^ (1U << (bit % 8U)));
        break;
      }
      case 1: pdu[rng.below(pdu.size())] = rng.byte(); break;  // a byte changed
      case 2:                                                  // the byte count one off
        if (pdu.size() > 1U) {
          pdu[1] = static_cast<std::uint8_t>(pdu[1] + (rng.below(2) != 0U ? 1U : 0xFFU));
        }
        break;
      case 3:  // cut short
        pdu.resize(pdu.size() - std::min<std::size_t>(pdu.size() - 1U, 1U + rng.below(3)));
        break;
      case 4:  // bytes added
        for (unsigned i = 1U + static_cast<unsigned>(rng.below(3)); i > 0U; --i) {
          pdu.push_back(rng.byte());
        }
        break;
      case 5:  // another function, or the exception flag turned
        pdu[0] = rng.below(2) != 0U ? static_cast<std::uint8_t>(pdu[0] ^ 0x80U)
                                    : functions[rng.below(sizeof functions)];
        break;
      case 6:  // another slave, or the broadcast address
        slave = rng.below(4) == 0 ? 0 : static_cast<std::uint8_t>(1U + rng.below(247));
        break;
      case 7: bad_crc = true; break;
      case 8: cut = 1U + static_cast<std::size_t>(rng.below(3)); break;  // the frame cut
      case 9:                                                            // bytes after it
        for (unsigned i = 1U + static_cast<unsigned>(rng.below(4)); i > 0U; --i) {
          after.push_back(rng.byte());
        }
        break;
      case 10:  // an exception code of any value
        if ((pdu[0] & 0x80U) != 0U && pdu.size() == 2U) {
          pdu[1] = rng.byte();
        }
        break;
      default:  // an echoed field (FC05/06/0F/10/16) or the last data byte changed
        if (pdu.size() >= 5U) {
          pdu[rng.below(2) != 0U ? pdu.size() - 1U : 1U + rng.below(4)] ^=
              static_cast<std::uint8_t>(1U + rng.below(255));
        }
    }
  }
  std::vector<std::uint8_t> adu = adu_of(slave, pdu);
  if (bad_crc) {
    adu.back() = static_cast<std::uint8_t>(adu.back() ^ (1U + rng.below(255)));
  }
  adu.resize(adu.size() - std::min(cut, adu.size()));
  adu.insert(adu.end(), after.begin(), after.end());
  return adu;
}

}  // namespace

int main(int argc, char** argv) {
  const unsigned long exchanges = argc > 1 ? std::strtoul(argv[1], nullptr, 0) : 20000UL;
  const unsigned long long seed = argc > 2 ? std::strtoull(argv[2], nullptr, 0) : 0x28C11EULL;
  testutil::splitmix64 rng(seed);
  libmodbus_master theirs;
  if (!theirs.open()) {
    std::printf("client differential: cannot set up libmodbus\n");
    return 1;
  }
  std::map<std::string, unsigned long> classes;
  std::map<std::string, unsigned long> refused_by;  // libmodbus's errno where both refuse
  unsigned long agree[3] = {0, 0, 0};
  unsigned long failures = 0;
  for (unsigned long k = 0; k < exchanges; ++k) {
    const request q = random_request(rng);
    const std::vector<std::uint8_t> response = random_response(rng, q);
    std::vector<std::uint8_t> sent;
    const outcome t = theirs.exchange(q, response, sent);
    if (sent.size() < 4U || sent[0] != q.slave || sent[1] != q.function) {
      ++failures;
      std::printf("libmodbus sent no request for #%lu (function %02x): %s\n", k, q.function,
                  testutil::to_hex(sent).c_str());
      continue;
    }
    const outcome o = library_client(sent, response);
    if (same(o, t)) {
      ++agree[o.kind];
      if (o.kind == outcome::refused) {
        ++refused_by[t.error == ETIMEDOUT     ? "timeout"
                     : t.error == EMBBADCRC   ? "EMBBADCRC"
                     : t.error == EMBBADDATA  ? "EMBBADDATA"
                     : t.error == EMBBADEXC   ? "EMBBADEXC"
                     : t.error == EMBBADSLAVE ? "EMBBADSLAVE"
                                              : std::to_string(t.error)];
      }
      continue;
    }
    const std::string cls = difference_class(q, o, t);
    if (cls.empty()) {
      ++failures;
      if (failures <= 10) {
        std::printf("DIFFERENT #%lu: request %s\n  response  %s\n  motionbus %s\n  libmodbus %s\n",
                    k, testutil::to_hex(sent).c_str(), testutil::to_hex(response).c_str(),
                    o.text().c_str(), t.text().c_str());
      }
    } else {
      ++classes[cls];
    }
  }
  std::printf(
      "client differential (seed 0x%llX): %lu exchanges; the same outcome: %lu accepted with the "
      "same values, %lu the same exception, %lu refused by both\n",
      seed, exchanges, agree[outcome::accepted], agree[outcome::exception],
      agree[outcome::refused]);
  std::printf("  refused by both, libmodbus's error:");
  for (const auto& r : refused_by) {
    std::printf(" %s %lu", r.first.c_str(), r.second);
  }
  std::printf("\n");
  for (const auto& c : classes) {
    std::printf("  documented difference %s: %lu\n", c.first.c_str(), c.second);
  }
  if (failures != 0) {
    std::printf("client differential: %lu differences of no documented class\n", failures);
    return 1;
  }
  return 0;
}
