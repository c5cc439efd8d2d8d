// motionbus firmware example — the generic Modbus RTU server of modbus_server.cpp (slave 1, the
// same device: 100 coils, discrete inputs, holding and input registers, functions 01-06, 0F,
// 10, 11, 16, 17), interrupt-driven: the UART's receive interrupt gives each byte to the server
// framer (put()), a one-shot timer armed at t3.5 after each byte tells it of the line's silence
// (idle()), and the main loop serves the frames the two handlers hand over and sends the answers;
// between requests it sleeps (wfi). Boards: board_irq.hpp.
//
// t3.5 is modbus/timing.hpp's at the line's rate: MOTIONBUS_BAUD (9600 by default, even parity,
// 1 stop bit: 4010 us). QEMU ignores the rate (a byte arrives when the host sent it), so under
// emulation t3.5 is the silence the image waits for, as on a line at that rate.
//
// What the library's contract asks (modbus/framer.hpp, "Interrupts"), and how this image keeps it:
// - put() and idle() never run while another call on the framer runs: only the two handlers call
//   the framer, and the board gives them one priority, so that neither interrupts the other.
// - A frame handed over points into the framer, valid until its next call: the handler copies it
//   at once into a queue slot, and the main loop serves the copy while the next request's bytes
//   arrive (a master that does not wait, or a frame for another slave, right behind it).
// - The queue: `queued` is written by the handlers only, `served` by the main loop only, each a
//   32-bit word (read and written whole by these cores); a slot is written before `queued` counts
//   it, and read before `served` gives it back. One core: the handlers see memory in program
//   order, so what has to be kept in order is the compiler's code: volatile words and
//   std::atomic_signal_fence (a compiler barrier; on several cores, or with a DMA writing the
//   slots, std::atomic_thread_fence would be needed). A frame that finds the queue full (a master
//   sending faster than the answers go out) is dropped and counted.
// - The timer: a byte that arrives as the t3.5 timer expires can leave the timer's interrupt
//   pending after the byte's handler re-armed it; the timer's handler therefore checks on the
//   clock that the line really was silent for t3.5 since the last byte, and re-arms for the rest
//   if not (counted: early).
// - The main loop sleeps with interrupts off between its check of the queue and wfi, so that a
//   frame handed over between the two wakes it (board_irq.hpp: wait_for_interrupt()).
//
// The image's counters (input registers 1000-1006, FC04): frames handed over, frames dropped on
// a full queue, failures put() reported (garbage, bad CRC), failures idle() reported (a frame cut
// short by a silence), the timer's early expiries, the frames ended by idle(), and the longest
// silence seen between two bytes of one frame (in units of 100 us). The checks read them
// (tests/firmware/modbus_back_to_back.py): each failure has a count that names its cause.
//
// Deliberately broken builds, for the checks' own test (tests/firmware/CMakeLists.txt):
// -DMOTIONBUS_BROKEN_DROP=N drops the Nth frame, -DMOTIONBUS_BROKEN_TWICE=N answers it twice.
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "board_irq.hpp"
#include "generic_device.hpp"
#include "motionbus/core/stream.hpp"
#include "motionbus/modbus/framer.hpp"
#include "motionbus/modbus/server.hpp"
#include "motionbus/modbus/timing.hpp"

#ifndef MOTIONBUS_BAUD
#define MOTIONBUS_BAUD 9600
#endif
#ifndef MOTIONBUS_SLAVE
#define MOTIONBUS_SLAVE 1
#endif

namespace mb = motionbus;
namespace mo = motionbus::modbus;

namespace {

constexpr std::uint8_t slave = MOTIONBUS_SLAVE;
constexpr std::uint32_t t35 = mo::t35_us(MOTIONBUS_BAUD, mo::parity::even, 1);

// The handlers' side: the framer, the time of the last byte, the queue's producer index and
// the counters (written by the handlers only).
mo::rtu_server_framer rx;
std::uint32_t last_byte_us = 0;
constexpr std::uint32_t slots = 4;
struct request_copy {
  std::uint8_t slave;
  std::uint8_t size;
  std::uint16_t crc;
  std::uint8_t pdu[mo::max_pdu_size];
};
request_copy queue[slots];
volatile std::uint32_t queued = 0;  // frames handed over (the handlers write it)
volatile std::uint32_t served = 0;  // frames served (the main loop writes it)
enum counter_index : unsigned {
  frames,
  overruns,
  rejected,
  idle_failures,
  early,
  idle_frames,
  longest_gap  // the longest silence between two bytes of one frame, in microseconds
};
volatile std::uint32_t counters[7] = {};
constexpr std::uint16_t counters_at = 1000;
constexpr std::uint16_t counters_end = counters_at + 7U;

void count(counter_index i) {
  counters[i] = counters[i] + 1U;
}

std::uint16_t counter(std::size_t i) {
  if (i == frames) {
    return static_cast<std::uint16_t>(queued);
  }
  if (i == longest_gap) {  // in units of 100 us, up to 6.5 s
    const std::uint32_t units = counters[i] / 100U;
    return static_cast<std::uint16_t>(units < 0xFFFFU ? units : 0xFFFFU);
  }
  return static_cast<std::uint16_t>(counters[i]);
}

// In a handler: a copy of `f` into the next free slot, then counted as queued.
void hand_over(const mo::rtu_frame& f) {
  const std::uint32_t q = queued;
  if (q - served >= slots) {
    count(overruns);
    return;
  }
  request_copy& c = queue[q % slots];
  c.slave = f.slave;
  c.size = static_cast<std::uint8_t>(f.pdu.size());
  c.crc = f.crc;
  for (std::size_t i = 0; i < f.pdu.size(); ++i) {
    c.pdu[i] = f.pdu[i];
  }
  std::atomic_signal_fence(std::memory_order_release);  // the slot written before it counts
  queued = q + 1U;
}

// The UART's receive interrupt, a byte at a time.
void on_byte(std::uint8_t byte) {
  const std::uint32_t now = board::now_us();
  if (rx.pending() > 0U && now - last_byte_us > counters[longest_gap]) {  // inside a frame
    counters[longest_gap] = now - last_byte_us;
  }
  last_byte_us = now;
  mb::put_each(rx, byte, [](const mb::decode_result<mo::rtu_frame>& r) {
    if (r.is_complete()) {
      hand_over(r.value());
    } else if (r.is_failed()) {
      count(rejected);
    }
    return true;
  });
  board::timer_arm(t35);
}

// The one-shot's interrupt: t3.5 after the last byte, what the framer holds ends.
void on_t35() {
  const std::uint32_t quiet = board::now_us() - last_byte_us;
  if (quiet < t35) {
    count(early);
    board::timer_arm(t35 - quiet);
    return;
  }
  const auto r = rx.idle();
  if (r.is_complete()) {
    count(idle_frames);
    hand_over(r.value());
  } else if (r.is_failed()) {
    count(idle_failures);
  }
}

// The generic server's device (generic_device.hpp), and input registers 1000-1006: this image's
// counters (above).
struct device : firmware::generic_device {
  std::uint8_t read_registers(std::uint8_t function, std::uint16_t address,
                              mb::span<std::uint16_t> out) {
    if (function == 0x04 && address >= counters_at && address + out.size() <= counters_end) {
      for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = counter(address + i - counters_at);
      }
      return 0;
    }
    return generic_device::read_registers(function, address, out);
  }
};

device dev;
std::uint8_t reply[mo::max_rtu_size];

}  // namespace

int main() {
  board::init();
  rx = mo::rtu_server_framer({slave});
  board::irq_start(&on_byte, &on_t35);
  for (;;) {
    board::interrupts_off();
    if (queued == served) {
      board::wait_for_interrupt();
    }
    board::interrupts_on();
    const std::uint32_t s = served;
    if (queued == s) {
      continue;
    }
    std::atomic_signal_fence(std::memory_order_acquire);  // the slot read after it counted
    const request_copy& c = queue[s % slots];
    const mo::rtu_frame frame{c.slave, mb::byte_view(c.pdu, c.size), c.crc};
    const auto n = mo::serve_frame(dev, slave, frame, mb::mutable_byte_view(reply, sizeof reply));
    std::atomic_signal_fence(std::memory_order_release);  // the slot read before it is free
    served = s + 1U;
#ifdef MOTIONBUS_BROKEN_DROP
    if (s + 1U == MOTIONBUS_BROKEN_DROP) {
      continue;
    }
#endif
    if (n.ok() && n.value() > 0U) {  // nothing for broadcasts and other addresses
      board::uart_write(reply, n.value());
#ifdef MOTIONBUS_BROKEN_TWICE
      if (s + 1U == MOTIONBUS_BROKEN_TWICE) {
        board::uart_write(reply, n.value());
      }
#endif
    }
  }
}
