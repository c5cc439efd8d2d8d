// motionbus's FC14/FC15 codec as text, for tests/interop/file_record_check.py (against
// pymodbus 3.0's file_message classes). Reads lines from stdin, answers one line each:
//   encode14 F:R:N,...          -> the request PDU in hex (encode_read_file_record)
//   encode15 F:R:HEX,...        -> the request PDU in hex (encode_write_file_record)
//   serve HEX                   -> the response PDU in hex that the server dispatch gives to the
//                                  request (a store whose record r of file f holds f * 0x100 + r),
//                                  or the request decoder's error name
//   check14 REQHEX RESPHEX      -> "ok" and each record's data in hex, or the error name
//   check15 REQHEX RESPHEX      -> "ok" or the error name
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "../support/hex.hpp"
#include "motionbus/modbus/file_record.hpp"
#include "motionbus/modbus/pdu_client.hpp"
#include "motionbus/modbus/rtu.hpp"
#include "motionbus/modbus/server.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

std::vector<std::uint8_t> unhex(const std::string& s) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i + 1 < s.size(); i += 2) {
    out.push_back(static_cast<std::uint8_t>(std::stoul(s.substr(i, 2), nullptr, 16)));
  }
  return out;
}
struct store {
  std::uint8_t read_file_record(std::uint16_t file, std::uint16_t record,
                                mb::mutable_byte_view out) {
    for (std::size_t i = 0; i < out.size() / 2U; ++i) {
      mb::store_be16(out, 2U * i, static_cast<std::uint16_t>(file * 0x100U + record + i));
    }
    return 0;
  }
  std::uint8_t write_file_record(std::uint16_t, std::uint16_t, mb::byte_view) { return 0; }
};

// "F:R:X,F:R:X" -> records; X is N (FC14) or the data in hex (FC15), kept in `data`.
std::vector<mo::file_record> records_of(const std::string& text, bool write,
                                        std::vector<std::vector<std::uint8_t>>& data) {
  std::vector<mo::file_record> out;
  std::istringstream in(text);
  std::string item;
  data.reserve(64);
  while (std::getline(in, item, ',')) {
    const std::size_t a = item.find(':');
    const std::size_t b = item.find(':', a + 1);
    mo::file_record r;
    r.file = static_cast<std::uint16_t>(std::stoul(item.substr(0, a)));
    r.record = static_cast<std::uint16_t>(std::stoul(item.substr(a + 1, b - a - 1)));
    if (write) {
      data.push_back(unhex(item.substr(b + 1)));
      r.data = mb::byte_view(data.back().data(), data.back().size());
      r.length = static_cast<std::uint16_t>(data.back().size() / 2U);
    } else {
      r.length = static_cast<std::uint16_t>(std::stoul(item.substr(b + 1)));
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace

int main() {
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string op, a, b;
    in >> op >> a >> b;
    std::uint8_t out[mo::max_rtu_size] = {};
    if (op == "encode14" || op == "encode15") {
      std::vector<std::vector<std::uint8_t>> data;
      const auto recs = records_of(a, op == "encode15", data);
      const mb::span<const mo::file_record> view(recs.data(), recs.size());
      const auto n = op == "encode14" ? mo::encode_read_file_record(view, out)
                                      : mo::encode_write_file_record(view, out);
      std::printf("%s\n",
                  n.ok() ? testutil::to_hex(out, n.value()).c_str() : mb::to_string(n.error()));
    } else if (op == "serve") {
      const auto pdu = unhex(a);
      const auto d = mo::decode_file_record_request(mb::byte_view(pdu.data(), pdu.size()));
      if (!d.is_complete()) {
        std::printf("%s\n", mb::to_string(d.error()));
        continue;
      }
      std::uint8_t adu[mo::max_rtu_size] = {};
      const auto k = mo::encode_rtu(1, mb::byte_view(pdu.data(), pdu.size()), adu);
      store dev;
      const auto n = mo::serve_rtu(dev, 1, mb::byte_view(adu, k.value_or(0)), out);
      std::printf("%s\n",
                  n.value_or(0) < 5U ? "none" : testutil::to_hex(out + 1, n.value() - 3U).c_str());
    } else if (op == "check14" || op == "check15") {
      const auto q = unhex(a);
      const auto r = unhex(b);
      const mb::byte_view qv(q.data(), q.size());
      const mb::byte_view rv(r.data(), r.size());
      const auto d = op == "check14" ? mo::decode_read_file_record_response(qv, rv)
                                     : mo::decode_write_file_record_response(qv, rv);
      if (!d.is_complete()) {
        std::printf("%s\n", mb::to_string(d.error()));
        continue;
      }
      std::string s = "ok";
      for (std::size_t i = 0; op == "check14" && i < d->count; ++i) {
        const auto rec = mo::file_record_at(d.value(), i).value();
        s += " " + testutil::to_hex(rec.data.data(), rec.data.size());
      }
      std::printf("%s\n", s.c_str());
    } else {
      std::printf("error\n");
    }
    std::fflush(stdout);
  }
  return 0;
}
