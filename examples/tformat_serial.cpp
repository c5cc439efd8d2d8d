// Reading a Tamagawa T-format encoder through a USB-RS485 adapter on Linux.
//
//   motionbus_example_tformat_serial /dev/ttyUSB0 [count] [--echo]
//
// The adapter runs at 2.5 Mbaud 8N1 — not a standard termios rate, so the port is set up with
// termios2 and BOTHER (any FTDI FT232R/FT2232 or CH343 class adapter accepts it). Each cycle
// sends an ID3 request and prints position, turns and alarms. `--echo` is for half-duplex
// adapters whose receiver stays on while sending: the request comes back before the response
// and the receiver skips it.
//
// The library does no I/O: this file owns the port; motionbus encodes the request, finds the
// response in the byte stream and decodes it.
#include <asm/ioctls.h>
#include <asm/termbits.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <motionbus/devices/ts5700n8500.hpp>
#include <motionbus/tformat.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>

extern "C" int ioctl(int fd, unsigned long request, ...);  // <sys/ioctl.h> clashes with termbits

namespace mb = motionbus;
namespace tf = motionbus::tformat;
namespace ts = motionbus::devices::ts5700n8500;

namespace {

int open_port(const char* path, unsigned baud) {
  const int fd = open(path, O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    std::perror(path);
    return -1;
  }
  struct termios2 t {};
  if (ioctl(fd, TCGETS2, &t) != 0) {
    std::perror("TCGETS2");
    close(fd);
    return -1;
  }
  t.c_iflag = 0;  // raw: no parity check, no CR/NL mapping, no flow control
  t.c_oflag = 0;
  t.c_lflag = 0;
  t.c_cflag = CS8 | CREAD | CLOCAL | BOTHER;  // 8N1 at the rate below
  t.c_ispeed = baud;
  t.c_ospeed = baud;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (ioctl(fd, TCSETS2, &t) != 0) {
    std::perror("TCSETS2 (2.5 Mbaud)");
    close(fd);
    return -1;
  }
  return fd;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s /dev/ttyUSBx [count] [--echo]\n", argv[0]);
    return 2;
  }
  const int count = argc > 2 && std::strcmp(argv[2], "--echo") != 0 ? std::atoi(argv[2]) : 10;
  const bool echo = argc > 2 && std::strcmp(argv[argc - 1], "--echo") == 0;
  const int fd = open_port(argv[1], ts::standard_bit_rate);
  if (fd < 0) {
    return 1;
  }
  tf::receiver_options opt;
  opt.echo_mode = echo ? tf::echo::expected : tf::echo::none;
  tf::receiver rx(opt);
  std::uint8_t request[tf::max_request_size] = {};
  const std::size_t request_size = tf::encode_request(tf::data_id::read_all, request).value();

  for (int i = 0; i < count; ++i) {
    if (write(fd, request, request_size) != static_cast<ssize_t>(request_size)) {
      std::perror("write");
      return 1;
    }
    rx.sent(mb::byte_view(request, request_size));
    bool done = false;
    // The response starts ~3 us after the request and lasts 44 us at 2.5 Mbps; USB adds its
    // own latency, so allow a few milliseconds.
    for (int polls = 0; polls < 20 && !done; ++polls) {
      pollfd p{fd, POLLIN, 0};
      if (poll(&p, 1, 1) <= 0) {
        continue;
      }
      std::uint8_t buffer[64];
      const ssize_t n = read(fd, buffer, sizeof buffer);
      mb::byte_view in(buffer, n > 0 ? static_cast<std::size_t>(n) : 0U);
      for (;;) {
        const auto r = rx.feed(in);
        if (r.is_incomplete()) {
          break;
        }
        in = in.subspan(r.consumed());
        if (!r) {
          std::printf("error: %s\n", mb::to_string(r.error()));
          continue;
        }
        std::printf("position %6u  turns %5u  absolute %llu", static_cast<unsigned>(r->abs),
                    static_cast<unsigned>(r->abm),
                    static_cast<unsigned long long>(tf::absolute_position(r->abs, r->abm)));
        for (tf::almc_bit a : tf::all_alarms) {
          if (tf::has_alarm(r->almc, a)) {
            std::printf("  %s (%s)", ts::info(a).symbol, ts::info(a).name);
          }
        }
        std::printf("\n");
        done = true;
      }
    }
    if (!done) {
      std::printf("no response (%s)\n", rx.idle().is_failed() ? "truncated" : "silent");
    }
    usleep(10000);
  }
  close(fd);
  return 0;
}
