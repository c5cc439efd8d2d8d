// Linux serial ports through termios2 (arbitrary baud rates). This file must not include
// <termios.h>, whose definitions clash with <asm/termbits.h>.
#include <asm/ioctls.h>
#include <asm/termbits.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <iostream>
#include <thread>

#include "serial.hpp"

extern "C" int ioctl(int fd, unsigned long request, ...);  // NOLINT: <sys/ioctl.h> clashes too

namespace serial {

namespace {
volatile std::sig_atomic_t stop_flag = 0;
void on_signal(int) {
  stop_flag = 1;
}
}  // namespace

port::~port() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

bool port::open(const std::string& path, const settings& s, std::string& warning,
                std::string& error) {
  fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd_ < 0) {
    error = "cannot open " + path + ": " + std::strerror(errno);
    return false;
  }
  struct termios2 t {};
  if (ioctl(fd_, TCGETS2, &t) != 0) {
    warning = "not a terminal: used as it is";
    return true;
  }
  t.c_iflag = 0;
  t.c_oflag = 0;
  t.c_lflag = 0;
  t.c_cflag = CS8 | CREAD | CLOCAL | BOTHER;
  if (s.parity == 'E' || s.parity == 'O') {
    t.c_cflag |= PARENB;
    if (s.parity == 'O') {
      t.c_cflag |= PARODD;
    }
  }
  if (s.stop_bits == 2) {
    t.c_cflag |= CSTOPB;
  }
  t.c_ispeed = s.baud;
  t.c_ospeed = s.baud;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (ioctl(fd_, TCSETS2, &t) != 0) {
    // Keep raw mode at least, at the device's own rate.
    t.c_cflag = (t.c_cflag & ~static_cast<tcflag_t>(CBAUD)) | B38400;
    if (ioctl(fd_, TCSETS2, &t) != 0) {
      warning = "line settings refused: used as it is";
    } else {
      warning = "baud rate refused: device rate kept";
    }
  }
  return true;
}

bool port::write_all(const std::uint8_t* data, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, data + done, size - done);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

long port::read_some(std::uint8_t* buffer, std::size_t capacity, int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) {
    return errno == EINTR ? 0 : -1;
  }
  if (ready == 0) {
    return 0;
  }
  const ssize_t n = ::read(fd_, buffer, capacity);
  if (n < 0) {
    return (errno == EAGAIN || errno == EINTR) ? 0 : -1;
  }
  if (n == 0 && (p.revents & POLLHUP) != 0) {
    return -1;
  }
  return static_cast<long>(n);
}

void port::flush_input() {
  std::uint8_t sink[256];
  while (read_some(sink, sizeof sink, 0) > 0) {
  }
}

bool open_reporting(port& p, const std::string& path, const settings& s) {
  std::string warning;
  std::string error;
  if (!p.open(path, s, warning, error)) {
    std::cerr << "motionbus: " << error << '\n';
    return false;
  }
  if (!warning.empty()) {
    std::cerr << "motionbus: " << path << ": " << warning << '\n';
  }
  return true;
}

std::uint32_t now_us() {
  const auto t = std::chrono::steady_clock::now().time_since_epoch();
  return static_cast<std::uint32_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(t).count() & 0xFFFFFFFF);
}

void sleep_us(std::uint32_t us) {
  std::this_thread::sleep_for(std::chrono::microseconds(us));
}

bool stop_requested() {
  return stop_flag != 0;
}

void install_stop_handler() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

}  // namespace serial
