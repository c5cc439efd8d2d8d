// Runs the motionbus CLI (MOTIONBUS_CLI_PATH) through the shell for the CLI tests.
#ifndef MOTIONBUS_TESTS_RUN_CLI_HPP
#define MOTIONBUS_TESTS_RUN_CLI_HPP

#include <doctest/doctest.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace testcli {

/// What the shell command prints on its standard output, and its exit status.
inline std::string output_of(const std::string& command, int* status) {
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string out;
  char buffer[512];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) {
    out.append(buffer, n);
  }
  const int s = pclose(pipe);
  if (status != nullptr) {
    *status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  }
  return out;
}

/// Stdout of `motionbus <args>` (args already shell-quoted); stderr is discarded. `stdin_text`,
/// when given, is piped in through printf (so \\n and \\r escapes are expanded).
inline std::string run_as_is(const std::string& args, int* status = nullptr,
                             const std::string& stdin_text = "") {
  std::string command;
  if (!stdin_text.empty()) {
    command = "printf '" + stdin_text + "' | ";
  }
  return output_of(command + "'" + MOTIONBUS_CLI_PATH + "' " + args + " 2>/dev/null", status);
}

/// run_as_is with --json: one JSON object per line, as scripts read the tool.
inline std::string run(const std::string& args, int* status = nullptr,
                       const std::string& stdin_text = "") {
  return run_as_is(args + " --json", status, stdin_text);
}

/// The exit status of `motionbus <args>`, killed after `seconds` (status 124 then, as
/// timeout(1) reports it): for a command that would run until stopped when it is wrong.
inline void run_bounded(const std::string& args, int seconds, int* status) {
  const std::string command = "timeout " + std::to_string(seconds) + " '" + MOTIONBUS_CLI_PATH +
                              "' " + args + " >/dev/null 2>&1";
  const int s = std::system(command.c_str());
  *status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
}

/// Stderr of `motionbus <args>` (stdout discarded): the messages of usage errors.
inline std::string run_stderr(const std::string& args, int* status = nullptr) {
  return output_of(std::string("'") + MOTIONBUS_CLI_PATH + "' " + args + " 2>&1 >/dev/null",
                   status);
}

/// A pseudo-terminal in raw mode: `master` for the test's device, `path` for the CLI. Raw from
/// here too, so that nothing is echoed before the CLI sets it; `keep` holds the slave side
/// open: with no slave open, the master side reads as hung up (between CLI runs).
struct raw_pty {
  int master = -1;
  int keep = -1;
  std::string path;
  raw_pty() {
    master = posix_openpt(O_RDWR | O_NOCTTY);
    REQUIRE(master >= 0);
    REQUIRE(grantpt(master) == 0);
    REQUIRE(unlockpt(master) == 0);
    path = ptsname(master);
    keep = open(path.c_str(), O_RDWR | O_NOCTTY);
    REQUIRE(keep >= 0);
    termios t{};
    tcgetattr(keep, &t);
    cfmakeraw(&t);
    tcsetattr(keep, TCSANOW, &t);
  }
  raw_pty(const raw_pty&) = delete;
  raw_pty& operator=(const raw_pty&) = delete;
  ~raw_pty() {
    close(keep);
    close(master);
  }
};

/// A device on a pseudo-terminal that answers each burst of bytes (ended by 10 ms of silence)
/// with `reply`, whatever it was; it keeps every byte it received.
class canned_device {
 public:
  explicit canned_device(std::vector<std::uint8_t> reply) : reply_(std::move(reply)) {
    thread_ = std::thread([this] { loop(); });
  }
  canned_device(const canned_device&) = delete;
  canned_device& operator=(const canned_device&) = delete;
  ~canned_device() {
    stop_ = true;
    thread_.join();
  }
  const std::string& path() const { return pty_.path; }
  std::vector<std::uint8_t> received() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return received_;
  }

 private:
  void loop() {
    bool pending = false;
    while (!stop_) {
      pollfd p{pty_.master, POLLIN, 0};
      if (poll(&p, 1, 10) > 0) {
        std::uint8_t buffer[256];
        const long n = read(pty_.master, buffer, sizeof buffer);
        if (n > 0) {
          const std::lock_guard<std::mutex> lock(mutex_);
          received_.insert(received_.end(), buffer, buffer + n);
          pending = true;
        }
      } else if (pending) {
        pending = false;
        if (!reply_.empty()) {
          REQUIRE(write(pty_.master, reply_.data(), reply_.size()) ==
                  static_cast<long>(reply_.size()));
        }
      }
    }
  }

  raw_pty pty_;
  std::vector<std::uint8_t> reply_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::vector<std::uint8_t> received_;
  std::thread thread_;
};

}  // namespace testcli

#endif
