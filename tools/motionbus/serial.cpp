// Serial ports for the CLI through libserialport (Linux, macOS, Windows): 8 data bits, the
// parity and stop bits asked for, any baud rate the driver takes (on Linux libserialport sets a
// non-standard rate such as T-format's 2.5 Mbaud through termios2). libserialport does not open
// pseudo-terminals (it looks each port up among the system's serial devices; its maintainers
// keep ptys out of scope: sigrokproject/libserialport pull request 4), so on POSIX systems a
// terminal it does not know is opened here as a plain raw terminal: that is how the tests and
// the demo reach the emulators over socat's pty pairs. Line speed and parity mean nothing on a
// pty.
#include "serial.hpp"

#include <libserialport.h>

#include <chrono>
#include <csignal>
#include <thread>

#ifndef _WIN32
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#endif

namespace serial {

namespace {

volatile std::sig_atomic_t stop_flag = 0;
void on_signal(int) {
  stop_flag = 1;
}

std::string last_error() {
  char* m = sp_last_error_message();
  std::string text = m != nullptr ? m : "unknown error";
  sp_free_error_message(m);
  return text;
}

}  // namespace

port::~port() {
  close();
}

void port::close() {
  if (sp_ != nullptr) {
    sp_close(sp_);
    sp_free_port(sp_);
    sp_ = nullptr;
  }
#ifndef _WIN32
  if (pty_fd_ >= 0) {
    ::close(pty_fd_);
    pty_fd_ = -1;
  }
#endif
}

bool port::open(const std::string& path, const settings& s, std::string& warning,
                std::string& error) {
  close();
  sp_port* p = nullptr;
  if (sp_get_port_by_name(path.c_str(), &p) == SP_OK) {
    sp_ = p;
    if (sp_open(sp_, SP_MODE_READ_WRITE) != SP_OK) {
      error = "cannot open " + path + ": " + last_error();
      close();
      return false;
    }
    const sp_parity parity = s.parity == 'E'   ? SP_PARITY_EVEN
                             : s.parity == 'O' ? SP_PARITY_ODD
                                               : SP_PARITY_NONE;
    if (sp_set_baudrate(sp_, static_cast<int>(s.baud)) != SP_OK) {
      error = path + ": baud rate " + std::to_string(s.baud) + " refused: " + last_error();
      close();
      return false;
    }
    if (sp_set_bits(sp_, 8) != SP_OK || sp_set_parity(sp_, parity) != SP_OK ||
        sp_set_stopbits(sp_, static_cast<int>(s.stop_bits)) != SP_OK ||
        sp_set_flowcontrol(sp_, SP_FLOWCONTROL_NONE) != SP_OK) {
      error = path + ": line settings refused: " + last_error();
      close();
      return false;
    }
    // A driver may accept a rate it cannot make and keep another (a PC's 16550 UART at
    // 2.5 Mbaud): read back what the line runs at.
    sp_port_config* config = nullptr;
    int actual = 0;
    if (sp_new_config(&config) == SP_OK) {
      if (sp_get_config(sp_, config) == SP_OK && sp_get_config_baudrate(config, &actual) == SP_OK &&
          actual != static_cast<int>(s.baud)) {
        warning = "the driver runs the line at " + std::to_string(actual) + " baud, not " +
                  std::to_string(s.baud);
      }
      sp_free_config(config);
    }
    return true;
  }
#ifndef _WIN32
  // Not a serial device libserialport knows: a pseudo-terminal, opened as a raw terminal.
  pty_fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (pty_fd_ < 0) {
    error = "cannot open " + path + ": " + std::strerror(errno);
    return false;
  }
  termios t{};
  if (::tcgetattr(pty_fd_, &t) != 0) {
    warning = "not a terminal: used as it is";
    return true;
  }
  ::cfmakeraw(&t);
  t.c_cflag |= CREAD | CLOCAL;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (::tcsetattr(pty_fd_, TCSANOW, &t) != 0) {
    warning = "raw mode refused: used as it is";
  }
  return true;
#else
  error = "cannot open " + path + ": " + last_error();
  return false;
#endif
}

int port::native_handle() const {
#ifndef _WIN32
  if (sp_ != nullptr) {
    int fd = -1;
    return sp_get_port_handle(sp_, &fd) == SP_OK ? fd : -1;
  }
  return pty_fd_;
#else
  return -1;  // a HANDLE, not a descriptor: the gateway needs a POSIX host
#endif
}

bool port::write_all(const std::uint8_t* data, std::size_t size) {
  if (sp_ != nullptr) {
    // timeout 0: until every byte is handed to the driver; then until it has left
    return sp_blocking_write(sp_, data, size, 0) == static_cast<int>(size) &&
           sp_drain(sp_) == SP_OK;
  }
#ifndef _WIN32
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(pty_fd_, data + done, size - done);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
#else
  return false;
#endif
}

long port::read_some(std::uint8_t* buffer, std::size_t capacity, int timeout_ms) {
  if (sp_ != nullptr) {
    // libserialport's timeout 0 means "wait for ever": a zero wait is a non-blocking read
    const int n = timeout_ms <= 0 ? sp_nonblocking_read(sp_, buffer, capacity)
                                  : sp_blocking_read_next(sp_, buffer, capacity,
                                                          static_cast<unsigned>(timeout_ms));
    return n < 0 ? -1 : static_cast<long>(n);
  }
#ifndef _WIN32
  pollfd p{pty_fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) {
    return errno == EINTR ? 0 : -1;
  }
  if (ready == 0) {
    return 0;
  }
  const ssize_t n = ::read(pty_fd_, buffer, capacity);
  if (n < 0) {
    return (errno == EAGAIN || errno == EINTR) ? 0 : -1;
  }
  if (n == 0 && (p.revents & POLLHUP) != 0) {
    return -1;
  }
  return static_cast<long>(n);
#else
  return -1;
#endif
}

void port::flush_input() {
  if (sp_ != nullptr) {
    sp_flush(sp_, SP_BUF_INPUT);
    return;
  }
  std::uint8_t sink[256];
  while (read_some(sink, sizeof sink, 0) > 0) {
  }
}

std::uint32_t now_us() {
  const auto t = std::chrono::steady_clock::now().time_since_epoch();
  return static_cast<std::uint32_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(t).count() & 0xFFFFFFFF);
}

std::uint64_t now_us64() {
  const auto t = std::chrono::steady_clock::now().time_since_epoch();
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(t).count());
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
