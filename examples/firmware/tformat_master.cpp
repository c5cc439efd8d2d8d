// motionbus firmware example — a T-format master on a UART: it polls an encoder (on the test
// bench, `motionbus serve tformat-encoder` on the host end of the UART) for Data IDs 3, 0, 1
// and 2 and an EEPROM read, decodes each response with the stream receiver (checked against
// its request), and reports what it decoded on the debugger's console (semihosting), a line
// per transaction, then "done".
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/receiver.hpp"
#include "report.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

constexpr std::uint32_t timeout_us = 500000;  // generous: the peer is a host process
constexpr unsigned attempts = 40;

tf::receiver rx;

// "<prefix><value>" in decimal into `out` at `at`; returns the new end.
std::size_t put(char* out, std::size_t at, const char* prefix, std::uint32_t value) {
  while (*prefix != '\0') {
    out[at++] = *prefix++;
  }
  return at + report::decimal(out + at, value);
}

// One transaction: the request out, the response in, a line on the console. A request without
// an answer is sent again, up to `attempts` times, as a polling master does (the peer may not be
// listening yet); whatever arrives before a request (a late answer to an earlier one) is
// dropped, and a response the receiver rejects (one that does not answer this request) is
// counted and waited past.
void transact(tf::data_id id, std::uint8_t address) {
  std::uint8_t request[tf::max_request_size] = {};
  const std::size_t n = tf::encode_request(id, address, 0, request).value_or(0);
  char line[96];
  std::size_t at = put(line, 0, "id ", static_cast<std::uint32_t>(id));
  bool answered = false;
  std::uint32_t rejected = 0;
  for (unsigned attempt = 0; !answered && attempt < attempts; ++attempt) {
    std::uint8_t stale = 0;
    while (board::uart_read(stale)) {
    }
    rx.sent(mb::byte_view(request, n));
    board::uart_write(request, n);
    const std::uint32_t start = board::now_us();
    while (!answered && board::now_us() - start < timeout_us) {
      std::uint8_t byte = 0;
      if (!board::uart_read(byte)) {
        continue;
      }
      mb::put_each(rx, byte, [&](const auto& r) {
        if (!r.is_complete()) {
          ++rejected;
          return true;
        }
        const tf::response& v = r.value();
        at = put(line, at, " ok sf ", v.sf);
        if (v.layout().abs()) {
          at = put(line, at, " abs ", v.abs);
        }
        if (v.layout().abm()) {
          at = put(line, at, " abm ", v.abm);
        }
        if (v.layout().enid()) {
          at = put(line, at, " enid ", v.enid);
        }
        if (v.layout().almc()) {
          at = put(line, at, " almc ", v.almc);
        }
        if (v.layout().eeprom()) {
          at = put(line, at, " address ", v.address);
          at = put(line, at, " edf ", v.edf);
        }
        answered = true;
        return false;
      });
    }
  }
  if (!answered) {
    at = put(line, at, " no answer, rejected ", rejected);
  }
  line[at++] = '\n';
  line[at] = '\0';
  board::console(line);
}

}  // namespace

int main() {
  board::init();
  rx = tf::receiver(tf::receiver_options{});
  transact(tf::data_id::read_all, 0);
  transact(tf::data_id::read_abs, 0);
  transact(tf::data_id::read_abm, 0);
  transact(tf::data_id::read_enid, 0);
  transact(tf::data_id::eeprom_read, 5);
  board::console("done\n");
  for (;;) {
  }
}
