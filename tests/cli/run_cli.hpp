// Runs the motionbus CLI (MOTIONBUS_CLI_PATH) through the shell for the CLI tests.
#ifndef MOTIONBUS_TESTS_RUN_CLI_HPP
#define MOTIONBUS_TESTS_RUN_CLI_HPP

#include <doctest/doctest.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace testcli {

/// The shell words that run the CLI, bounded: a CLI that has not ended after `seconds`
/// (cli_time_limit_s unless told) is stopped (SIGTERM, then SIGKILL 5 s later), status 124 or
/// 137, so that a hang is one failed check, not the suite's time-out.
constexpr int cli_time_limit_s = 30;
inline std::string cli_command(int seconds = cli_time_limit_s) {
  return "timeout --foreground -k 5 " + std::to_string(seconds) + " '" + MOTIONBUS_CLI_PATH + "' ";
}

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
  const int code = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  // timeout(1)'s statuses: the CLI (whose own are 0, 1 and 2) was stopped
  CHECK_MESSAGE((code != 124 && code != 137), "timed out: " << command);
  if (status != nullptr) {
    *status = code;
  }
  return out;
}

/// What ps shows of process `pid` and its children (state, the kernel function it waits in):
/// the evidence a run stopped at its time limit leaves.
inline std::string process_state(pid_t pid) {
  const std::string p = std::to_string(pid);
  return output_of("ps -o pid,ppid,stat,wchan:24,args -p " + p + " --ppid " + p + " 2>&1", nullptr);
}

/// In a child after fork(): it is killed when the test process ends, however that ends (so a
/// device emulator can never outlive the suite holding ctest's output pipe open).
inline void die_with_parent(pid_t parent) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) {  // the parent ended before the line above
    _exit(127);
  }
}

/// Stdout of `motionbus <args>` (args already shell-quoted); stderr is discarded. `stdin_text`,
/// when given, is piped in through printf (so \\n and \\r escapes are expanded).
inline std::string run_as_is(const std::string& args, int* status = nullptr,
                             const std::string& stdin_text = "") {
  std::string command;
  if (!stdin_text.empty()) {
    command = "printf '" + stdin_text + "' | ";
  }
  return output_of(command + cli_command() + args + " 2>/dev/null", status);
}

/// run_as_is with --json: one JSON object per line, as scripts read the tool.
inline std::string run(const std::string& args, int* status = nullptr,
                       const std::string& stdin_text = "") {
  return run_as_is(args + " --json", status, stdin_text);
}

/// The exit status of `motionbus <args>`, killed after `seconds` (status 124 then, as
/// timeout(1) reports it): for a command that would run until stopped when it is wrong.
inline void run_bounded(const std::string& args, int seconds, int* status) {
  const std::string command = cli_command(seconds) + args + " >/dev/null 2>&1";
  const int s = std::system(command.c_str());
  *status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
}

/// Stderr of `motionbus <args>` (stdout discarded): the messages of usage errors.
inline std::string run_stderr(const std::string& args, int* status = nullptr) {
  return output_of(cli_command() + args + " 2>&1 >/dev/null", status);
}

/// The JSON objects of `out`, one a line (blank lines skipped); a line that is not JSON is a
/// string value, so that it can never equal an object.
inline std::vector<nlohmann::json> json_lines(const std::string& out) {
  std::vector<nlohmann::json> lines;
  std::size_t begin = 0;
  while (begin < out.size()) {
    std::size_t end = out.find('\n', begin);
    end = end == std::string::npos ? out.size() : end;
    const std::string line = out.substr(begin, end - begin);
    if (!line.empty()) {
      nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
      lines.push_back(j.is_discarded() ? nlohmann::json("not JSON: " + line) : j);
    }
    begin = end + 1;
  }
  return lines;
}

/// What differs between the JSON lines of `out` and of `expected`: one JSON patch per line
/// (what turns the output into the expectation), for a failed check's message.
inline std::string json_difference(const std::string& out, const std::string& expected) {
  const auto a = json_lines(out);
  const auto b = json_lines(expected);
  std::string d = "output: " + out + "differences:";
  for (std::size_t i = 0; i < a.size() || i < b.size(); ++i) {
    d += " " +
         nlohmann::json::diff(i < a.size() ? a[i] : nullptr, i < b.size() ? b[i] : nullptr).dump();
  }
  return d;
}

/// Every field of the JSON object `fields` is in the single JSON object `out` holds, with the
/// same value.
inline bool has_fields(const std::string& out, const std::string& fields) {
  const auto lines = json_lines(out);
  if (lines.size() != 1 || !lines[0].is_object()) {
    return false;
  }
  const nlohmann::json wanted = nlohmann::json::parse(fields);
  for (const auto& f : wanted.items()) {
    if (!lines[0].contains(f.key()) || lines[0][f.key()] != f.value()) {
      return false;
    }
  }
  return true;
}

}  // namespace testcli

/// The output's JSON lines equal the expected ones (JSON text, one object a line) field by
/// field: every field, its value, no other field; the fields' order and spacing do not count.
#define CHECK_JSON(out, expected)                                              \
  do {                                                                         \
    const std::string out_ = (out);                                            \
    const std::string expected_ = (expected);                                  \
    CHECK_MESSAGE(testcli::json_lines(out_) == testcli::json_lines(expected_), \
                  testcli::json_difference(out_, expected_));                  \
  } while (false)
/// The output's single JSON object has (at least) these fields with these values.
#define CHECK_FIELDS(out, fields)                                         \
  do {                                                                    \
    const std::string out_ = (out);                                       \
    CHECK_MESSAGE(testcli::has_fields(out_, fields), "output: " << out_); \
  } while (false)

namespace testcli {

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
