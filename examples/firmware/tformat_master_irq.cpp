// motionbus firmware example — the T-format master of tformat_master.cpp, interrupt-driven: the
// UART's receive interrupt gives each byte to the stream receiver (put()), a one-shot timer armed
// after each byte tells it of the line's silence (idle(): a response cut short is dropped), and
// the main loop sends the requests and sleeps (wfi) until the handler hands over the response.
// It polls the encoder (on the test bench, `motionbus serve tformat-encoder` on the host end of
// the UART) for Data IDs 3, 0, 1 and 2 and an EEPROM read and reports each on the debugger's
// console (semihosting) as tformat_master.cpp does; then 100 ID0 reads back to back (each sent
// as soon as the response to the one before is in, none sent again) and a line of counts:
//   back-to-back 100 answered A rejected R truncated T resent S
// (A responses, R frames the receiver rejected and T responses cut short by the silence during
// the 100, S requests sent again after the first answer), then "done".
//
// What the library's contract asks (tformat/receiver.hpp, "Interrupts"), and how this image
// keeps it:
// - put() and idle() never run while another call on the receiver runs: they run in the two
//   handlers, which the board gives one priority; sent() runs in the main loop with interrupts
//   off, before the request's first byte goes out (so that its echo and its response are checked
//   against it).
// - result() is valid until the next put() that settles something: the handler copies the
//   response (a plain struct) into a mailbox at once. The mailbox has one writer at a time: the
//   handler writes it only while `answered` is false and then sets it; the main loop reads it
//   only once `answered` is set, and clears `answered` (interrupts off) when it sends the next
//   request. One core: volatile flags and std::atomic_signal_fence keep the compiler's order.
//
// The silence: MOTIONBUS_IDLE_US after the last byte (50 ms by default: under emulation a
// byte's arrival is the host's scheduling, not the line's rate; on a line at 2.5 Mbps a few
// character times, some microseconds, would do).
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "board_irq.hpp"
#include "motionbus/core/stream.hpp"
#include "motionbus/tformat/codec.hpp"
#include "motionbus/tformat/receiver.hpp"
#include "report.hpp"

#ifndef MOTIONBUS_IDLE_US
#define MOTIONBUS_IDLE_US 50000
#endif

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

constexpr std::uint32_t idle_us = MOTIONBUS_IDLE_US;
constexpr std::uint32_t timeout_us = 500000;  // generous: the peer is a host process
// back to back, a response that does not come is a defect, not a peer not listening yet: a
// response later than this (a host process descheduled for seconds) is counted as lost
constexpr std::uint32_t back_to_back_timeout_us = 5000000;
constexpr unsigned attempts = 40;
constexpr unsigned back_to_back = 100;

// The handlers' side.
tf::receiver rx;
std::uint32_t last_byte_us = 0;
tf::response mailbox;
volatile bool answered = false;
volatile std::uint32_t rejected = 0;
volatile std::uint32_t truncated = 0;

void on_byte(std::uint8_t byte) {
  last_byte_us = board::now_us();
  mb::put_each(rx, byte, [](const mb::decode_result<tf::response>& r) {
    if (r.is_complete()) {
      if (!answered) {
        mailbox = r.value();
        std::atomic_signal_fence(std::memory_order_release);  // the mailbox before the flag
        answered = true;
      }
    } else if (r.is_failed()) {
      rejected = rejected + 1U;
    }
    return true;
  });
  board::timer_arm(idle_us);
}

// The one-shot's interrupt: the line's silence (idle_us after the last byte), and the main
// loop's response timeout (the one-shot armed for it by ask(), re-armed here until it passes, so
// that the sleeping main loop wakes when it does).
volatile std::uint32_t sent_at_us = 0;
volatile std::uint32_t wait_us = 0;  // the timeout of the request in flight
void on_idle() {
  const std::uint32_t now = board::now_us();
  const std::uint32_t quiet = now - last_byte_us;
  if (quiet < idle_us) {  // a byte came as the timer expired: its re-arming left it pending
    board::timer_arm(idle_us - quiet);
    return;
  }
  if (rx.idle().is_failed()) {
    truncated = truncated + 1U;
  }
  const std::uint32_t waited = now - sent_at_us;
  if (!answered && waited < wait_us) {
    board::timer_arm(wait_us - waited);
  }
}

// "<prefix><value>" in decimal into `out` at `at`; returns the new end.
std::size_t put(char* out, std::size_t at, const char* prefix, std::uint32_t value) {
  while (*prefix != '\0') {
    out[at++] = *prefix++;
  }
  return at + report::decimal(out + at, value);
}

// Sends `request` and sleeps until the response is in or `timeout` (microseconds) has passed.
bool ask(const std::uint8_t* request, std::size_t n, tf::response& out,
         std::uint32_t timeout = timeout_us) {
  board::interrupts_off();
  rx.sent(mb::byte_view(request, n));
  answered = false;
  const std::uint32_t start = board::now_us();
  sent_at_us = start;
  wait_us = timeout;
  board::timer_arm(timeout);  // wakes the loop below if nothing comes
  board::interrupts_on();
  board::uart_write(request, n);
  for (;;) {
    board::interrupts_off();
    if (!answered && board::now_us() - start < timeout) {
      board::wait_for_interrupt();  // a byte, the silence or the timeout
    }
    board::interrupts_on();
    if (answered) {
      std::atomic_signal_fence(std::memory_order_acquire);  // the flag before the mailbox
      out = mailbox;
      return true;
    }
    if (board::now_us() - start >= timeout) {
      return false;
    }
  }
}

std::uint32_t resent = 0;
bool first_answered = false;

// One transaction as tformat_master.cpp reports it; a request without an answer is sent again,
// up to `attempts` times, as a polling master does (the peer may not be listening yet).
void transact(tf::data_id id, std::uint8_t address) {
  std::uint8_t request[tf::max_request_size] = {};
  const std::size_t n = tf::encode_request(id, address, 0, request).value_or(0);
  char line[96];
  std::size_t at = put(line, 0, "id ", static_cast<std::uint32_t>(id));
  tf::response v;
  bool ok = false;
  for (unsigned attempt = 0; !ok && attempt < attempts; ++attempt) {
    if (attempt > 0U && first_answered) {
      ++resent;
    }
    ok = ask(request, n, v);
  }
  if (ok) {
    first_answered = true;
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
  } else {
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
  board::irq_start(&on_byte, &on_idle);
  transact(tf::data_id::read_all, 0);
  transact(tf::data_id::read_abs, 0);
  transact(tf::data_id::read_abm, 0);
  transact(tf::data_id::read_enid, 0);
  transact(tf::data_id::eeprom_read, 5);
  // back to back: each ID0 request as soon as the response to the one before is in
  std::uint8_t request[tf::max_request_size] = {};
  const std::size_t n = tf::encode_request(tf::data_id::read_abs, 0, 0, request).value_or(0);
  std::uint32_t got = 0;
  const std::uint32_t rejected_before = rejected;
  const std::uint32_t truncated_before = truncated;
  for (unsigned i = 0; i < back_to_back; ++i) {
    tf::response v;
    if (ask(request, n, v, back_to_back_timeout_us) && v.id == tf::data_id::read_abs) {
      ++got;
    }
  }
  char line[96];
  std::size_t at = put(line, 0, "back-to-back ", back_to_back);
  at = put(line, at, " answered ", got);
  at = put(line, at, " rejected ", rejected - rejected_before);
  at = put(line, at, " truncated ", truncated - truncated_before);
  at = put(line, at, " resent ", resent);
  line[at++] = '\n';
  line[at] = '\0';
  board::console(line);
  board::console("done\n");
  for (;;) {
    board::interrupts_off();
    board::wait_for_interrupt();
    board::interrupts_on();
  }
}
