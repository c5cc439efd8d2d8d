// The library's client response checks against libmodbus's on any response (the differential
// test's two clients: tests/interop/client_differential.hpp). The input: 8 bytes seed the
// request (random_request: a function libmodbus's master has a call for, within its limits)
// and a valid response to it (valid_response); a flags byte; the rest, the response's changes.
// Flags bit 0: the rest is the response itself (else it is XOR-ed onto the valid response's
// ADU, bytes past its end appended); bit 1: the CRC made right again (the last two bytes);
// bits 4-7: bytes cut from the end. libmodbus's call reads the response from a socket pair,
// the library's client frames the same bytes and decodes them against the request libmodbus
// sent. Oracle: libmodbus sent the request; the two outcomes (accepted and the values read,
// the exception and its code, or refused) are the same, or differ by a class docs/modbus.md
// §15 lists.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "../../tests/interop/client_differential.hpp"
#include "../fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static client_diff::libmodbus_master theirs;
  static const bool ready = theirs.open();
  MOTIONBUS_FUZZ_CHECK(ready);
  if (size < 9U) {
    return 0;
  }
  std::uint64_t seed = 0;
  for (std::size_t i = 0; i < 8U; ++i) {
    seed = (seed << 8U) | data[i];
  }
  const std::uint8_t flags = data[8];
  testutil::splitmix64 rng(seed);
  const client_diff::request q = client_diff::random_request(rng);
  std::vector<std::uint8_t> response;
  if ((flags & 1U) != 0U) {
    response.assign(data + 9, data + size);
  } else {
    response = client_diff::adu_of(q.slave, client_diff::valid_response(rng, q));
    for (std::size_t i = 9; i < size; ++i) {
      if (i - 9U < response.size()) {
        response[i - 9U] = static_cast<std::uint8_t>(response[i - 9U] ^ data[i]);
      } else {
        response.push_back(data[i]);
      }
    }
  }
  if (response.size() > 300U) {
    return 0;
  }
  const std::size_t cut = flags >> 4U;
  response.resize(response.size() - (cut < response.size() ? cut : response.size()));
  if ((flags & 2U) != 0U && response.size() >= 2U) {
    response.resize(response.size() - 2U);
    client_diff::append_crc(response);
  }
  std::vector<std::uint8_t> sent;
  const client_diff::outcome t = theirs.exchange(q, response, sent);
  MOTIONBUS_FUZZ_CHECK(sent.size() >= 4U && sent[0] == q.slave && sent[1] == q.function);
  const client_diff::outcome o = client_diff::library_client(sent, response);
  if (!client_diff::same(o, t)) {
    MOTIONBUS_FUZZ_CHECK(!client_diff::difference_class(q, o, t).empty());
  }
  return 0;
}
