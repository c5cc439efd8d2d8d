// The client differential's two clients (tests/interop/client_differential.cpp, ctest
// interop.client_differential, and fuzz/interop/client_libmodbus_fuzz.cpp): libmodbus's master
// (its public calls: modbus_read_registers and the others, which check a response with its
// internal check_confirmation) reading a response fed to it through a socket pair, and the
// library's client (rtu_client_framer told of the silence after the response, then
// decode_response_for) on the same bytes; the requests and responses both get; the classes of
// difference docs/modbus.md §15 lists.
#ifndef MOTIONBUS_TESTS_INTEROP_CLIENT_DIFFERENTIAL_HPP
#define MOTIONBUS_TESTS_INTEROP_CLIENT_DIFFERENTIAL_HPP

#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <motionbus/modbus.hpp>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "../support/prng.hpp"

namespace client_diff {

namespace mb = motionbus;
namespace mo = motionbus::modbus;

// The functions libmodbus's master has a call for (modbus_read_bits ... modbus_report_slave_id).
inline constexpr std::uint8_t functions[] = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06,
                                             0x0F, 0x10, 0x16, 0x17, 0x11};

// A request as the caller gives it to libmodbus: within its limits and the address space.
struct request {
  std::uint8_t slave = 1;
  std::uint8_t function = 0x03;
  std::uint16_t address = 0;   // FC17: the read address
  std::uint16_t quantity = 1;  // FC17: the read quantity
  std::uint16_t value = 0;     // FC05 (0 or 1), FC06
  std::uint16_t and_mask = 0;
  std::uint16_t or_mask = 0;
  std::uint16_t write_address = 0;       // FC17
  std::uint16_t write_quantity = 1;      // FC17
  std::vector<std::uint8_t> bits;        // FC0F: one a byte
  std::vector<std::uint16_t> registers;  // FC10, FC17's write
};

// `quantity` from 1 to `limit`: small, at the limit, or any; an address that keeps the request
// inside the 65536 addresses.
inline void quantity_and_address(testutil::splitmix64& rng, std::uint16_t limit,
                                 std::uint16_t& quantity, std::uint16_t& address) {
  switch (rng.below(4)) {
    case 0: quantity = limit; break;
    case 1: quantity = static_cast<std::uint16_t>(1U + rng.below(limit)); break;
    default: quantity = static_cast<std::uint16_t>(1U + rng.below(limit < 20U ? limit : 20U));
  }
  address = static_cast<std::uint16_t>(rng.below(0x10000U - quantity + 1U));
}

inline request random_request(testutil::splitmix64& rng) {
  request q;
  q.slave = static_cast<std::uint8_t>(1U + rng.below(247));
  q.function = functions[rng.below(sizeof functions)];
  switch (q.function) {
    case 0x01:
    case 0x02: quantity_and_address(rng, MODBUS_MAX_READ_BITS, q.quantity, q.address); break;
    case 0x03:
    case 0x04: quantity_and_address(rng, MODBUS_MAX_READ_REGISTERS, q.quantity, q.address); break;
    case 0x05:
    case 0x06:
      q.address = static_cast<std::uint16_t>(rng.next());
      q.value = q.function == 0x05 ? static_cast<std::uint16_t>(rng.below(2))
                                   : static_cast<std::uint16_t>(rng.next());
      break;
    case 0x0F:
      quantity_and_address(rng, MODBUS_MAX_WRITE_BITS, q.quantity, q.address);
      for (unsigned i = 0; i < q.quantity; ++i) {
        q.bits.push_back(static_cast<std::uint8_t>(rng.below(2)));
      }
      break;
    case 0x10:
      quantity_and_address(rng, MODBUS_MAX_WRITE_REGISTERS, q.quantity, q.address);
      for (unsigned i = 0; i < q.quantity; ++i) {
        q.registers.push_back(static_cast<std::uint16_t>(rng.next()));
      }
      break;
    case 0x16:
      q.address = static_cast<std::uint16_t>(rng.next());
      q.and_mask = static_cast<std::uint16_t>(rng.next());
      q.or_mask = static_cast<std::uint16_t>(rng.next());
      break;
    case 0x17:
      quantity_and_address(rng, MODBUS_MAX_WR_READ_REGISTERS, q.quantity, q.address);
      quantity_and_address(rng, MODBUS_MAX_WR_WRITE_REGISTERS, q.write_quantity, q.write_address);
      for (unsigned i = 0; i < q.write_quantity; ++i) {
        q.registers.push_back(static_cast<std::uint16_t>(rng.next()));
      }
      break;
    default: break;  // FC11: no fields
  }
  return q;
}

inline void put16(std::vector<std::uint8_t>& v, unsigned x) {
  v.push_back(static_cast<std::uint8_t>(x >> 8U));
  v.push_back(static_cast<std::uint8_t>(x & 0xFFU));
}

// A valid response PDU to `q`: normal (random data where the function returns data), or one in
// eight an exception with a code the specification defines.
inline std::vector<std::uint8_t> valid_response(testutil::splitmix64& rng, const request& q) {
  const std::uint8_t f = q.function;
  std::vector<std::uint8_t> pdu{f};
  if (rng.below(8) == 0) {
    static const std::uint8_t codes[] = {1, 2, 3, 4, 5, 6, 8, 10, 11};
    pdu[0] = static_cast<std::uint8_t>(f | 0x80U);
    pdu.push_back(codes[rng.below(sizeof codes)]);
    return pdu;
  }
  switch (f) {
    case 0x01:
    case 0x02: {
      const unsigned n = (q.quantity + 7U) / 8U;
      pdu.push_back(static_cast<std::uint8_t>(n));
      for (unsigned i = 0; i < n; ++i) {
        pdu.push_back(rng.byte());
      }
      if (q.quantity % 8U != 0U) {  // the unused high bits of the last byte: 0
        pdu.back() = static_cast<std::uint8_t>(pdu.back() & ((1U << (q.quantity % 8U)) - 1U));
      }
      break;
    }
    case 0x03:
    case 0x04:
    case 0x17:
      pdu.push_back(static_cast<std::uint8_t>(2U * q.quantity));
      for (unsigned i = 0; i < 2U * q.quantity; ++i) {
        pdu.push_back(rng.byte());
      }
      break;
    case 0x05:
      put16(pdu, q.address);
      put16(pdu, q.value != 0U ? 0xFF00U : 0U);
      break;
    case 0x06:
      put16(pdu, q.address);
      put16(pdu, q.value);
      break;
    case 0x0F:
    case 0x10:
      put16(pdu, q.address);
      put16(pdu, q.quantity);
      break;
    case 0x16:
      put16(pdu, q.address);
      put16(pdu, q.and_mask);
      put16(pdu, q.or_mask);
      break;
    default: {  // FC11: a byte count, the server's ID, its run indicator, more bytes
      const unsigned n = static_cast<unsigned>(rng.below(24));
      pdu.push_back(static_cast<std::uint8_t>(n));
      for (unsigned i = 0; i < n; ++i) {
        pdu.push_back(rng.byte());
      }
    }
  }
  return pdu;
}

// address, PDU, CRC
inline void append_crc(std::vector<std::uint8_t>& adu) {
  const std::uint16_t crc = mb::crc16_modbus<>::compute(mb::byte_view(adu.data(), adu.size()));
  adu.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  adu.push_back(static_cast<std::uint8_t>(crc >> 8U));
}
inline std::vector<std::uint8_t> adu_of(std::uint8_t slave, const std::vector<std::uint8_t>& pdu) {
  std::vector<std::uint8_t> adu{slave};
  adu.insert(adu.end(), pdu.begin(), pdu.end());
  append_crc(adu);
  return adu;
}

// What a client made of a response.
struct outcome {
  enum kind_t { accepted, exception, refused } kind = refused;
  std::uint8_t exception_code = 0;
  std::vector<std::uint16_t> values;  // registers, bits (0/1), FC11's bytes; none for writes
  int error = 0;                      // libmodbus: errno; the library: its errc
  std::string text() const {
    std::string s = kind == accepted ? "accepted" : kind == exception ? "exception " : "refused ";
    if (kind == exception) {
      s += std::to_string(exception_code);
    } else if (kind == refused) {
      s += std::to_string(error);
    } else {
      s += std::to_string(values.size()) + " values";
    }
    return s;
  }
};

inline bool same(const outcome& a, const outcome& b) {
  if (a.kind != b.kind) {
    return false;
  }
  return a.kind == outcome::refused ||
         (a.kind == outcome::exception ? a.exception_code == b.exception_code
                                       : a.values == b.values);
}

// libmodbus's master: an RTU context whose file descriptor is one end of a socket pair; the
// response is written to the other end before the call, which then finds it there.
struct libmodbus_master {
  modbus_t* ctx = nullptr;
  int sv[2] = {-1, -1};

  /// False when libmodbus cannot be set up.
  bool open() {
    ctx = modbus_new_rtu("/dev/null", 9600, 'E', 8, 1);
    // the response is in the socket before the request goes out: 1 us timeouts only end a
    // response shorter than libmodbus's length rule wants
    return ctx != nullptr && socketpair(AF_UNIX, SOCK_STREAM, 0, sv) == 0 &&
           modbus_set_socket(ctx, sv[0]) == 0 && modbus_set_response_timeout(ctx, 0, 1) == 0 &&
           modbus_set_byte_timeout(ctx, 0, 1) == 0;
  }
  ~libmodbus_master() {
    if (ctx != nullptr) {
      modbus_free(ctx);
    }
    for (const int fd : sv) {
      if (fd >= 0) {
        close(fd);
      }
    }
  }
  static std::vector<std::uint8_t> drain(int fd) {
    std::vector<std::uint8_t> out;
    std::uint8_t buf[512];
    ssize_t got = 0;
    while ((got = recv(fd, buf, sizeof buf, MSG_DONTWAIT)) > 0) {
      out.insert(out.end(), buf, buf + got);
    }
    return out;
  }

  /// libmodbus's call for `q` reading `response`; `sent` gets the request ADU it wrote.
  outcome exchange(const request& q, const std::vector<std::uint8_t>& response,
                   std::vector<std::uint8_t>& sent) {
    drain(sv[0]);
    drain(sv[1]);
    outcome o;
    if (modbus_set_slave(ctx, q.slave) != 0 ||
        (!response.empty() && send(sv[1], response.data(), response.size(), 0) !=
                                  static_cast<ssize_t>(response.size()))) {
      o.error = -1;
      return o;
    }
    std::uint16_t regs[MODBUS_MAX_READ_REGISTERS] = {};
    std::uint8_t bits[MODBUS_MAX_READ_BITS] = {};
    std::uint8_t id[256] = {};
    int rc = -1;
    errno = 0;
    switch (q.function) {
      case 0x01: rc = modbus_read_bits(ctx, q.address, q.quantity, bits); break;
      case 0x02: rc = modbus_read_input_bits(ctx, q.address, q.quantity, bits); break;
      case 0x03: rc = modbus_read_registers(ctx, q.address, q.quantity, regs); break;
      case 0x04: rc = modbus_read_input_registers(ctx, q.address, q.quantity, regs); break;
      case 0x05: rc = modbus_write_bit(ctx, q.address, q.value); break;
      case 0x06: rc = modbus_write_register(ctx, q.address, q.value); break;
      case 0x0F: rc = modbus_write_bits(ctx, q.address, q.quantity, q.bits.data()); break;
      case 0x10: rc = modbus_write_registers(ctx, q.address, q.quantity, q.registers.data()); break;
      case 0x16: rc = modbus_mask_write_register(ctx, q.address, q.and_mask, q.or_mask); break;
      case 0x17:
        rc = modbus_write_and_read_registers(ctx, q.write_address, q.write_quantity,
                                             q.registers.data(), q.address, q.quantity, regs);
        break;
      default: rc = modbus_report_slave_id(ctx, sizeof id, id); break;
    }
    const int e = errno;
    sent = drain(sv[1]);
    drain(sv[0]);  // what libmodbus's length rule left unread
    if (rc >= 0) {
      o.kind = outcome::accepted;
      if (q.function <= 0x02) {
        o.values.assign(bits, bits + q.quantity);
      } else if (q.function <= 0x04 || q.function == 0x17) {
        o.values.assign(regs, regs + q.quantity);
      } else if (q.function == 0x11) {
        o.values.assign(id, id + rc);
      }
    } else if (e >= MODBUS_ENOBASE && e < MODBUS_ENOBASE + MODBUS_EXCEPTION_MAX) {
      o.kind = outcome::exception;
      o.exception_code = static_cast<std::uint8_t>(e - MODBUS_ENOBASE);
    } else {
      o.error = e;
    }
    return o;
  }
};

/// The library's client on the same bytes: the framer of the request sent, told of the silence
/// after the response (frame_end::silence), the first frame it hands over decoded by
/// decode_response_for against the request.
inline outcome library_client(const std::vector<std::uint8_t>& request_adu,
                              const std::vector<std::uint8_t>& response) {
  outcome o;
  if (request_adu.size() < 4U) {
    o.error = static_cast<int>(mb::errc::invalid_argument);
    return o;
  }
  mo::rtu_client_framer framer(mo::framer_options{request_adu[0]});
  const mb::byte_view request(request_adu.data(), request_adu.size());
  framer.sent(request);
  mb::decode_result<mo::rtu_frame> frame = mb::need_input{1};
  (void)mb::feed_all(framer, mb::byte_view(response.data(), response.size()),
                     [&frame](const mb::decode_result<mo::rtu_frame>& r) {
                       if (r.is_complete()) {
                         frame = r;
                         return false;  // the first frame is the response
                       }
                       return true;
                     });
  if (!frame.is_complete()) {
    frame = framer.idle();
  }
  if (!frame.is_complete()) {
    o.error = static_cast<int>(frame.is_failed() ? frame.error() : mb::errc::truncated);
    return o;
  }
  const mb::byte_view pdu = frame.value().pdu;
  const auto r = mo::decode_response_for(request.subspan(1, request.size() - 3U), pdu);
  if (!r.is_complete()) {
    o.error = static_cast<int>(r.error());
    return o;
  }
  if (r.value().exception) {
    o.kind = outcome::exception;
    o.exception_code = r.value().exception_code;
    return o;
  }
  o.kind = outcome::accepted;
  const std::uint8_t f = r.value().function;
  const mb::byte_view data = r.value().data;
  if (f <= 0x02) {
    for (unsigned i = 0; i < r.value().quantity; ++i) {
      o.values.push_back(static_cast<std::uint16_t>((data[i / 8U] >> (i % 8U)) & 1U));
    }
  } else if (f <= 0x04 || f == 0x17) {
    for (std::size_t i = 0; i + 1U < data.size(); i += 2U) {
      o.values.push_back(static_cast<std::uint16_t>((data[i] << 8U) | data[i + 1U]));
    }
  } else if (f == 0x11) {
    o.values.assign(data.begin(), data.end());
  }
  return o;
}

/// The documented class of a difference (docs/modbus.md §15), or "" when it is of none.
/// `ours` and `theirs`: the library's and libmodbus's outcomes for the request `q`.
inline std::string difference_class(const request& q, const outcome& ours, const outcome& theirs) {
  const auto our_error = static_cast<mb::errc>(ours.error);
  // 1. a write's response whose echo differs from the request (FC05/06/16: any field; FC0F/10:
  //    the address): libmodbus checks only its length (and the FC0F/10 quantity), the library
  //    every echoed field
  if ((q.function == 0x05 || q.function == 0x06 || q.function == 0x0F || q.function == 0x10 ||
       q.function == 0x16) &&
      theirs.kind == outcome::accepted && ours.kind == outcome::refused &&
      our_error == mb::errc::modbus_mismatch) {
    return "write echo differs";
  }
  // 2. a bit read whose last byte has unused high bits set: libmodbus ignores them, the library
  //    refuses the response (the bits it reads are the same)
  if (q.function <= 0x02 && theirs.kind == outcome::accepted && ours.kind == outcome::refused &&
      our_error == mb::errc::reserved_bits) {
    return "unused bits set";
  }
  // 3. an exception code the specification does not define beyond 0x0B: libmodbus reports a
  //    malformed exception (EMBBADEXC), the library the exception with its code
  if (ours.kind == outcome::exception && ours.exception_code >= MODBUS_EXCEPTION_MAX &&
      theirs.kind == outcome::refused && theirs.error == EMBBADEXC) {
    return "exception code above 0x0B";
  }
  return "";
}

}  // namespace client_diff

#endif
