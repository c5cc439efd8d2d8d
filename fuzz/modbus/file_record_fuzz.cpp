// FC14/FC15 file records (modbus/file_record.hpp, the FC14/15 parts of pdu_client.hpp,
// pdu_server.hpp and server.hpp). The input: a length L, a request PDU of L bytes, then a
// response PDU (the rest). Oracles:
//   - the request decoder agrees with a plain re-reading of §6.14/§6.15 written here (valid,
//     exception 03, exception 02, not FC14/15), and a decoded request re-encodes to the input;
//   - the response decoders never read outside the PDU; a complete FC14 response re-encodes
//     to the input, holds the requested number of records of the requested lengths, and an
//     FC15 response is the request's bytes;
//   - what the server answers to a valid request decodes as its response.
#include <motionbus/modbus/file_record.hpp>
#include <motionbus/modbus/pdu_client.hpp>
#include <motionbus/modbus/pdu_server.hpp>
#include <motionbus/modbus/rtu.hpp>
#include <motionbus/modbus/server.hpp>

#include <algorithm>
#include <cstring>
#include <vector>

#include "../fuzz_check.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

// The spec read plainly: 0 valid, 1 not FC14/15, 2 or 3 the exception, -1 not a PDU.
int plain_verdict(const std::uint8_t* p, std::size_t n) {
  if (n < 1 || n > 253) {
    return -1;
  }
  if (p[0] != 0x14 && p[0] != 0x15) {
    return 1;
  }
  const bool read = p[0] == 0x14;
  if (n < 2) {
    return 3;
  }
  const unsigned count = p[1];
  if (read && (count < 7 || count > 0xF5 || count % 7 != 0)) {
    return 3;
  }
  if (!read && (count < 9 || count > 0xFB)) {
    return 3;
  }
  if (n != 2U + count) {
    return 3;
  }
  struct sub {
    unsigned ref, file, record, length;
  };
  std::vector<sub> subs;
  unsigned reply = 2;
  for (std::size_t at = 2; at < n;) {
    if (at + 7 > n) {
      return 3;
    }
    auto word = [&](std::size_t k) { return static_cast<unsigned>(p[k] * 256U + p[k + 1]); };
    const sub s{p[at], word(at + 1), word(at + 3), word(at + 5)};
    reply += 2 + 2 * s.length;
    if (s.length == 0 || (read && reply > 253)) {
      return 3;
    }
    at += 7 + (read ? 0 : 2 * s.length);
    if (at > n) {
      return 3;
    }
    subs.push_back(s);
  }
  for (const sub& s : subs) {
    if (s.ref != 6 || s.file == 0 || s.record > 0x270F || s.record + s.length > 0x2710) {
      return 2;
    }
  }
  return 0;
}

// A file store of four files of 0x2710 records that answers every record with its number.
struct store {
  std::uint8_t read_file_record(std::uint16_t file, std::uint16_t record,
                                mb::mutable_byte_view out) {
    if (file > 4) {
      return 0x02;
    }
    for (std::size_t i = 0; i < out.size() / 2; ++i) {
      mb::store_be16(out, 2 * i, static_cast<std::uint16_t>(record + i));
    }
    return 0;
  }
  std::uint8_t write_file_record(std::uint16_t file, std::uint16_t, mb::byte_view data) {
    return file > 4 || data.empty() ? std::uint8_t{0x02} : std::uint8_t{0};
  }
};

void check_response(mb::byte_view request, const mo::file_records& q, mb::byte_view pdu) {
  std::uint8_t out[mo::max_pdu_size] = {};
  if (q.function == mo::read_file_record_function) {
    const auto r = mo::decode_read_file_record_response(request, pdu);
    if (!r.is_complete()) {
      MOTIONBUS_FUZZ_CHECK(r.is_failed() && r.consumed() == pdu.size());
      return;
    }
    if (r->exception) {
      MOTIONBUS_FUZZ_CHECK(pdu.size() == 2 && pdu[0] == 0x94);
      return;
    }
    MOTIONBUS_FUZZ_CHECK(r->count == q.count);
    std::vector<mo::file_record> records;
    for (std::size_t k = 0; k < r->count; ++k) {
      const auto rec = mo::file_record_at(r.value(), k);
      const auto asked = mo::file_record_at(q, k);
      MOTIONBUS_FUZZ_CHECK(rec.ok() && asked.ok());
      MOTIONBUS_FUZZ_CHECK(rec->data.size() == 2U * asked->length);
      MOTIONBUS_FUZZ_CHECK(rec->file == asked->file && rec->record == asked->record);
      MOTIONBUS_FUZZ_CHECK(rec->data.data() >= pdu.data() &&
                           rec->data.data() + rec->data.size() <= pdu.data() + pdu.size());
      records.push_back(rec.value());
    }
    const auto n = mo::encode_read_file_record_response(
        mb::span<const mo::file_record>(records.data(), records.size()), out);
    MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == pdu.size());
    MOTIONBUS_FUZZ_CHECK(std::memcmp(out, pdu.data(), pdu.size()) == 0);
  } else {
    const auto r = mo::decode_write_file_record_response(request, pdu);
    if (!r.is_complete()) {
      MOTIONBUS_FUZZ_CHECK(r.is_failed() && r.consumed() == pdu.size());
      return;
    }
    if (!r->exception) {
      MOTIONBUS_FUZZ_CHECK(pdu.size() == request.size());
      MOTIONBUS_FUZZ_CHECK(std::memcmp(pdu.data(), request.data(), pdu.size()) == 0);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* input, std::size_t input_size) {
  const std::size_t size = input_size == 0 ? 0 : std::min<std::size_t>(input[0], input_size - 1);
  const std::uint8_t* data = input_size == 0 ? input : input + 1;
  const mb::byte_view pdu(data, size);
  const mb::byte_view response(data + size, input_size == 0 ? 0 : input_size - 1 - size);
  const int verdict = plain_verdict(data, size);
  const auto d = mo::decode_file_record_request(pdu);
  if (!d.is_complete()) {
    MOTIONBUS_FUZZ_CHECK(d.is_failed() && d.consumed() == size);
    const int code = static_cast<int>(mo::exception_for(d.error()));
    MOTIONBUS_FUZZ_CHECK(
        verdict == -1
            ? d.error() == mb::errc::modbus_pdu_length
            : (verdict == 1 ? d.error() == mb::errc::modbus_illegal_function : code == verdict));
  } else {
    MOTIONBUS_FUZZ_CHECK(verdict == 0 && d.consumed() == size);
    const mo::file_records& q = d.value();
    std::vector<mo::file_record> records;
    for (std::size_t k = 0; k < q.count; ++k) {
      const auto rec = mo::file_record_at(q, k);
      MOTIONBUS_FUZZ_CHECK(rec.ok());
      records.push_back(rec.value());
    }
    MOTIONBUS_FUZZ_CHECK(mo::file_record_at(q, q.count).error() == mb::errc::out_of_range);
    std::uint8_t out[mo::max_pdu_size] = {};
    const mb::span<const mo::file_record> subs(records.data(), records.size());
    const auto n = q.function == mo::read_file_record_function
                       ? mo::encode_read_file_record(subs, out)
                       : mo::encode_write_file_record(subs, out);
    MOTIONBUS_FUZZ_CHECK(n.ok() && n.value() == size && std::memcmp(out, data, size) == 0);

    // the server's answer is a response to it
    store dev;
    std::uint8_t adu[mo::max_rtu_size] = {};
    std::uint8_t reply[mo::max_rtu_size] = {};
    const auto a = mo::encode_rtu(1, pdu, adu);
    MOTIONBUS_FUZZ_CHECK(a.ok());
    const auto served = mo::serve_rtu(dev, 1, mb::byte_view(adu, a.value()), reply);
    MOTIONBUS_FUZZ_CHECK(served.ok() && served.value() >= 5);
    const mb::byte_view answer(reply + 1, served.value() - 3);
    if (q.function == mo::read_file_record_function) {
      const auto r = mo::decode_read_file_record_response(pdu, answer);
      MOTIONBUS_FUZZ_CHECK(r.is_complete());
    } else {
      const auto r = mo::decode_write_file_record_response(pdu, answer);
      MOTIONBUS_FUZZ_CHECK(r.is_complete());
    }
    check_response(pdu, q, answer);

    // and the input's response
    check_response(pdu, q, response);
  }
  return 0;
}
