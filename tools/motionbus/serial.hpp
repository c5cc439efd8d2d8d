// Serial ports for the CLI, through libserialport (Linux, macOS, Windows; serial.cpp says how a
// pseudo-terminal is opened): 8 data bits at any baud rate the driver takes (2.5 Mbaud for
// T-format on a USB-RS485 adapter), reads with a timeout, a microsecond clock.
#ifndef MOTIONBUS_TOOLS_SERIAL_HPP
#define MOTIONBUS_TOOLS_SERIAL_HPP

#include <cstddef>
#include <cstdint>
#include <string>

struct sp_port;

namespace serial {

struct settings {
  unsigned baud = 115200;
  char parity = 'N';  ///< 'N', 'E' or 'O'
  unsigned stop_bits = 1;
};

/// An open port. Closed on destruction.
class port {
 public:
  port() = default;
  port(const port&) = delete;
  port& operator=(const port&) = delete;
  ~port();

  /// Opens `path` in raw 8-bit mode with `s`. When the device refuses the line settings (a
  /// pseudo-terminal may), it is used as it is and `warning` says so. False on failure to open
  /// (`error` says why).
  bool open(const std::string& path, const settings& s, std::string& warning, std::string& error);
  bool write_all(const std::uint8_t* data, std::size_t size);
  /// Reads what is available within `timeout_ms`: bytes read, 0 on timeout, -1 on error.
  long read_some(std::uint8_t* buffer, std::size_t capacity, int timeout_ms);
  /// Discards unread input.
  void flush_input();
  void close();
  /// The open port's file descriptor (POSIX), for an event loop to wait on; -1 when closed.
  int native_handle() const;

 private:
  sp_port* sp_ = nullptr;
  int pty_fd_ = -1;  // a pseudo-terminal, which libserialport does not open (POSIX only)
};

/// Monotonic microseconds (wraps at 2^32, after 71.6 minutes: for short intervals).
std::uint32_t now_us();
/// Monotonic microseconds, 64-bit (no wrap in practice): for durations and long runs.
std::uint64_t now_us64();
/// Sleeps at least `us` microseconds.
void sleep_us(std::uint32_t us);

/// Set by SIGINT/SIGTERM once install_stop_handler() ran.
bool stop_requested();
void install_stop_handler();

}  // namespace serial

#endif
