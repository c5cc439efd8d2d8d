// read tformat --watch against the TS5700N8500 emulator on a pseudo-terminal pair, the emulator
// driven by this test read by read (a simulated axis: its position before each request is
// known here): the continuous position across the multi-turn counter's wrap (ID3) and the
// single-turn rollover backwards (ID0), an injected impossible jump, the link lost (requests
// left unanswered, a corrupted CRC) and restored, device alarms; through a pipe (a JSON object
// per read, a text line per read) and under a terminal (the CLI's standard output a
// pseudo-terminal: one live line rewritten in place). Also monitor --duration past 4294 s.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "motionbus/devices/ts5700n8500_emulator.hpp"
#include "motionbus/tformat.hpp"
#include "run_cli.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;
namespace ts = motionbus::devices::ts5700n8500;

namespace {

// What the emulator does with request k (1 first).
enum class act : std::uint8_t { answer, silent, bad_crc };
struct step {
  std::uint64_t reading = 0;  ///< the encoder's reading (multi-turn << 17 | single-turn)
  act action = act::answer;
  bool alarm = false;  ///< BA present
};

// The emulator on a pseudo-terminal: before answering request k it is set to script(k).
class scripted_encoder {
 public:
  explicit scripted_encoder(std::function<step(std::uint64_t)> script)
      : script_(std::move(script)) {
    thread_ = std::thread([this] { loop(); });
  }
  scripted_encoder(const scripted_encoder&) = delete;
  scripted_encoder& operator=(const scripted_encoder&) = delete;
  ~scripted_encoder() {
    stop_ = true;
    thread_.join();
  }
  const std::string& path() const { return pty_.path; }
  std::uint64_t requests() const { return requests_; }

 private:
  void loop() {
    ts::emulator enc;
    std::uint8_t frame[tf::max_request_size] = {};
    std::size_t size = 0;
    while (!stop_) {
      pollfd p{pty_.master, POLLIN, 0};
      std::uint8_t byte = 0;
      if (poll(&p, 1, 10) <= 0 || read(pty_.master, &byte, 1) != 1) {
        continue;
      }
      frame[size++] = byte;
      if (tf::decode_request(mb::byte_view(frame, size)).is_incomplete() &&
          size < tf::max_request_size) {
        continue;
      }
      const step s = script_(++requests_);
      enc.set_position(static_cast<std::uint32_t>(s.reading & 0x1FFFFU),
                       static_cast<std::uint32_t>(s.reading >> 17U));
      enc.set_condition(tf::almc_bit::ba, s.alarm);
      ts::reply r = enc.respond(mb::byte_view(frame, size), 0);
      size = 0;
      if (s.action == act::silent || r.size == 0) {
        continue;
      }
      if (s.action == act::bad_crc) {
        r.bytes[r.size - 1] ^= 0x5A;
      }
      if (write(pty_.master, r.bytes, r.size) != static_cast<ssize_t>(r.size)) {
        break;
      }
    }
  }

  testcli::raw_pty pty_;
  std::function<step(std::uint64_t)> script_;
  std::atomic<std::uint64_t> requests_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// The reading of a continuous position p (any sign) on an encoder of 2^bits counts.
std::uint64_t reading_of(std::int64_t p, unsigned bits) {
  const std::int64_t m = std::int64_t{1} << bits;
  return static_cast<std::uint64_t>(((p % m) + m) % m);
}

// The JSON objects of a run: the reads (by "read" number, 1 first) and the summary.
struct watch_run {
  std::vector<nlohmann::json> reads;
  nlohmann::json summary;
  int status = -1;
};

watch_run run_watch(const std::string& args) {
  watch_run w;
  const std::string out = testcli::run(args, &w.status);
  for (const nlohmann::json& j : testcli::json_lines(out)) {
    REQUIRE_MESSAGE(j.is_object(), out);
    if (j.contains("summary")) {
      w.summary = j;
    } else {
      REQUIRE(j.at("read").get<std::uint64_t>() == w.reads.size() + 1);
      w.reads.push_back(j);
    }
  }
  return w;
}

// Starts the CLI with `args`, its standard output on `out_fd` and its stderr discarded: its pid.
pid_t spawn_cli(const std::vector<std::string>& args, int out_fd) {
  const int null = open("/dev/null", O_WRONLY);
  REQUIRE(null >= 0);
  std::vector<char*> argv;  // made before fork(): the child only calls async-signal-safe code
  argv.push_back(const_cast<char*>("motionbus"));
  for (const std::string& a : args) {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    testcli::die_with_parent(parent);
    if (dup2(out_fd, STDOUT_FILENO) < 0 || dup2(null, STDERR_FILENO) < 0) {
      _exit(127);
    }
    execv(MOTIONBUS_CLI_PATH, argv.data());
    _exit(127);
  }
  close(null);
  return pid;
}

// Reads `fd` until `ended()` says the CLI is done; `on_output` sees what was read so far. A CLI
// still running after testcli::cli_time_limit_s seconds is killed and the run fails.
template <typename Ended, typename OnOutput>
std::string read_cli_output(int fd, pid_t pid, Ended ended, OnOutput on_output) {
  const auto start = std::chrono::steady_clock::now();
  bool killed = false;
  std::string state;  // ps of the CLI when it was killed
  std::string out;
  for (;;) {
    if (!killed && std::chrono::steady_clock::now() - start >
                       std::chrono::seconds(testcli::cli_time_limit_s)) {
      state = testcli::process_state(pid);
      kill(pid, SIGKILL);
      killed = true;
    }
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 50) > 0 && (p.revents & POLLIN) != 0) {
      char buffer[512];
      const ssize_t n = read(fd, buffer, sizeof buffer);
      if (n > 0) {
        out.append(buffer, static_cast<std::size_t>(n));
        on_output(out);
        continue;
      }
    }
    if (ended(p)) {
      break;
    }
  }
  CHECK_MESSAGE(!killed, "the CLI did not end within " << testcli::cli_time_limit_s
                                                       << " s; it was:\n"
                                                       << state);
  return out;
}

int exit_status(int s) {
  return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
}

// Runs the CLI with its standard output on a new pseudo-terminal (stderr discarded); returns
// what the terminal received and the exit status.
std::string run_on_terminal(const std::vector<std::string>& args, int* status) {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  REQUIRE(master >= 0);
  REQUIRE(grantpt(master) == 0);
  REQUIRE(unlockpt(master) == 0);
  // the terminal's slave side stays open here too, so that its output is read to the end
  // (with no slave open the master side reads as hung up)
  const int slave = open(ptsname(master), O_RDWR | O_NOCTTY);
  REQUIRE(slave >= 0);
  const pid_t pid = spawn_cli(args, slave);
  int s = 0;
  bool exited = false;
  // read until the child has exited and nothing more arrives for 50 ms
  const std::string out = read_cli_output(
      master, pid,
      [&](const pollfd&) {
        if (exited) {
          return true;
        }
        exited = waitpid(pid, &s, WNOHANG) == pid;
        return false;
      },
      [](const std::string&) {});
  close(slave);
  close(master);
  *status = exit_status(s);
  return out;
}

// Runs the CLI with its standard output on a pipe (stderr discarded) and interrupts it (SIGINT)
// once it has printed `lines` lines: what it printed to the end, and its exit status.
std::string run_interrupted(const std::vector<std::string>& args, std::size_t lines, int* status) {
  int out_pipe[2] = {-1, -1};
  REQUIRE(pipe2(out_pipe, O_CLOEXEC) == 0);
  const pid_t pid = spawn_cli(args, out_pipe[1]);
  close(out_pipe[1]);
  bool interrupted = false;
  const std::string out = read_cli_output(
      out_pipe[0], pid,
      // the pipe reads as hung up, or at its end, once the CLI has ended
      [](const pollfd& p) { return (p.revents & (POLLHUP | POLLIN)) != 0; },
      [&](const std::string& so_far) {
        if (!interrupted &&
            static_cast<std::size_t>(std::count(so_far.begin(), so_far.end(), '\n')) >= lines) {
          kill(pid, SIGINT);
          interrupted = true;
        }
      });
  close(out_pipe[0]);
  int s = 0;
  waitpid(pid, &s, 0);
  *status = exit_status(s);
  return out;
}

}  // namespace

TEST_CASE("read tformat --watch --json: ID3 across the multi-turn wrap, link lost and restored") {
  // A simulated axis turning 100000 counts a read; it crosses the 33-bit reading's wrap
  // (the multi-turn counter 65535 -> 0) between reads 13 and 14.
  const std::int64_t step_counts = 100000;
  const std::int64_t p0 = (std::int64_t{1} << 33) - 1250000;
  const auto position = [&](std::uint64_t k) {
    return p0 + static_cast<std::int64_t>(k - 1) * step_counts;
  };
  scripted_encoder enc([&](std::uint64_t k) {
    step s;
    s.reading = reading_of(position(k), 33);
    if (k >= 7 && k <= 10) {
      s.action = act::silent;  // four reads unanswered
    } else if (k == 11) {
      s.action = act::bad_crc;
    } else if (k == 16) {
      s.reading = reading_of(position(k) + (std::int64_t{1} << 31), 33);  // a glitch
    }
    s.alarm = k >= 19;
    return s;
  });
  const watch_run w = run_watch("read tformat --device " + enc.path() +
                                " --id 3 --watch --count 20 --interval-ms 10 --timeout-ms 500 "
                                "--max-step 150000");
  CHECK(w.status == 0);
  CHECK(enc.requests() == 20);
  REQUIRE(w.reads.size() == 20);
  const auto at = [&](std::size_t k) -> const nlohmann::json& { return w.reads.at(k - 1); };
  // seeded by the first reading, the link proven after three good reads
  CHECK(at(1)["ok"] == true);
  CHECK(at(1)["position_status"] == "seeded");
  CHECK(at(1)["counts"] == position(1));
  CHECK(at(1)["link"] == "lost");
  CHECK(at(3)["event"] == "restored");
  CHECK(at(3)["link"] == "up");
  for (std::size_t k = 2; k <= 6; ++k) {
    CAPTURE(k);
    CHECK(at(k)["position_status"] == "accepted");
    CHECK(at(k)["counts"] == position(k));
    CHECK(at(k)["step"] == step_counts);
    CHECK(at(k)["outcome"] == "ok");
  }
  // speed: the step over the time between the two reads, in turns per minute
  const double dt = at(6)["time_us"].get<double>() - at(5)["time_us"].get<double>();
  CHECK(at(6)["speed_rpm"].get<double>() ==
        doctest::Approx(100000.0 * 60e6 / (dt * 131072.0)).epsilon(1e-9));
  // four timeouts, then a CRC error: lost at the third failure
  for (std::size_t k = 7; k <= 10; ++k) {
    CAPTURE(k);
    CHECK(at(k)["ok"] == false);
    CHECK(at(k)["error"] == "timeout");
    CHECK(at(k)["outcome"] == "timeout");
    CHECK(at(k)["position_status"] == "no_reading");
    CHECK(at(k)["counts"] == position(6));  // held
  }
  CHECK(at(8)["link"] == "up");
  CHECK(at(9)["event"] == "lost");
  CHECK(at(9)["link"] == "lost");
  CHECK(at(11)["error"] == "crc_mismatch");
  CHECK(at(11)["outcome"] == "crc_error");
  CHECK(at(11)["counters"]["crc_errors"] == 1);
  CHECK(at(11)["counters"]["timeouts"] == 4);
  // back: the axis moved six reads' worth meanwhile, within six periods' plausible step
  CHECK(at(12)["position_status"] == "accepted");
  CHECK(at(12)["counts"] == position(12));
  CHECK(at(12)["step"] == 6 * step_counts);
  CHECK(at(12)["link"] == "lost");
  CHECK(at(14)["event"] == "restored");
  // across the multi-turn wrap: the reading starts again at 0, the position runs on
  CHECK(at(13)["abm"] == 65535);
  CHECK(at(14)["abm"] == 0);
  CHECK(at(14)["counts"] == position(14));
  CHECK(at(14)["counts"].get<std::int64_t>() > (std::int64_t{1} << 33));
  CHECK(at(15)["counts"] == position(15));
  // the glitch is reported and not applied; the next reading is on the trajectory again
  CHECK(at(16)["ok"] == true);
  CHECK(at(16)["position_status"] == "implausible_step");
  CHECK(at(16)["counts"] == position(15));
  CHECK(at(16)["counters"]["implausible_steps"] == 1);
  CHECK(at(17)["position_status"] == "accepted");
  CHECK(at(17)["counts"] == position(17));
  // a device alarm: a good frame for the link, counted
  CHECK(at(18)["outcome"] == "ok");
  CHECK(at(19)["outcome"] == "alarm");
  CHECK(at(19)["almc"] == 0x80);
  CHECK(at(20)["counts"] == position(20));
  CHECK(at(20)["turns"] == position(20) >> 17);
  CHECK(at(20)["within_turn"] == (position(20) & 0x1FFFF));
  CHECK(at(20)["revolutions"].get<double>() ==
        doctest::Approx(static_cast<double>(position(20)) / 131072.0));
  CHECK(at(20)["degrees"].get<double>() ==
        doctest::Approx(static_cast<double>(position(20)) / 131072.0 * 360.0));
  const nlohmann::json& c = w.summary;
  CHECK(c["reads"] == 20);
  CHECK(c["link"] == "up");
  CHECK(c["frames"] == 20);
  CHECK(c["good"] == 15);
  CHECK(c["timeouts"] == 4);
  CHECK(c["crc_errors"] == 1);
  CHECK(c["invalid"] == 0);
  CHECK(c["alarms"] == 2);
  CHECK(c["losses"] == 1);
  CHECK(c["implausible_steps"] == 1);
  CHECK(c["counts"] == position(20));
}

TEST_CASE(
    "read tformat --watch: ID0 single-turn backwards across the rollover, a text line per "
    "read through a pipe") {
  // 45000 counts back a read from 1000: below zero, then around the 17-bit single-turn value.
  const auto position = [](std::uint64_t k) {
    return 1000 - static_cast<std::int64_t>(k - 1) * 45000;
  };
  scripted_encoder enc([&](std::uint64_t k) {
    step s;
    s.reading = reading_of(position(k), 17);
    return s;
  });
  const std::string args =
      "read tformat --device " + enc.path() + " --id 0 --watch --interval-ms 5 --timeout-ms 500";
  const watch_run w = run_watch(args + " --count 8");
  CHECK(w.status == 0);
  REQUIRE(w.reads.size() == 8);
  for (std::size_t k = 1; k <= 8; ++k) {
    CAPTURE(k);
    CHECK(w.reads[k - 1]["counts"] == position(k));
    CHECK(w.reads[k - 1]["abs"] == reading_of(position(k), 17));
  }
  CHECK(w.reads[7]["turns"] == -3);  // 1000 - 7 x 45000 = -314000: turn -3
  CHECK(w.reads[7]["speed_rpm"].get<double>() < 0);
  CHECK(w.summary["counts"] == position(8));
  // not a terminal, no --json: a line per read, nothing rewritten in place
  int status = 0;
  const std::string text = testcli::run_as_is(args + " --count 3", &status);
  CHECK(status == 0);  // three good reads prove the link: up at the end
  std::vector<std::string> lines;
  for (std::size_t b = 0; b < text.size();) {
    const std::size_t e = text.find('\n', b);
    lines.push_back(text.substr(b, e - b));
    b = e == std::string::npos ? text.size() : e + 1;
  }
  REQUIRE(lines.size() == 4);
  for (std::size_t k = 1; k <= 3; ++k) {
    CAPTURE(lines[k - 1]);
    CHECK(lines[k - 1].find("read=" + std::to_string(k) + " time_us=") == 0);
    CHECK(lines[k - 1].find("  ok  outcome=ok abs=") != std::string::npos);
  }
  CHECK(lines[3].find("# summary=watch reads=3 link=up") == 0);
  CHECK(text.find('\r') == std::string::npos);
  CHECK(text.find('\x1b') == std::string::npos);
  // no --count: it reads until interrupted (SIGINT once it has printed four reads), then
  // prints the summary
  const std::string interrupted =
      run_interrupted({"read", "tformat", "--device", enc.path(), "--id", "0", "--watch",
                       "--interval-ms", "5", "--timeout-ms", "500", "--json"},
                      4, &status);
  CHECK(status == 0);
  const auto objects = testcli::json_lines(interrupted);
  REQUIRE(objects.size() >= 5);
  const nlohmann::json& last = objects.back();
  CHECK(last["summary"] == "watch");
  CHECK(last["reads"] == objects.size() - 1);
  CHECK(last["link"] == "up");
}

TEST_CASE("read tformat --watch under a terminal: one live line, rewritten in place") {
  const auto position = [](std::uint64_t k) { return static_cast<std::int64_t>(k) * 30000; };
  scripted_encoder enc([&](std::uint64_t k) {
    step s;
    s.reading = reading_of(position(k), 33);
    s.action = k == 4 || k == 5 ? act::silent : act::answer;
    return s;
  });
  int status = 0;
  const std::string out = run_on_terminal(
      {"read", "tformat", "--device", enc.path(), "--id", "3", "--watch", "--count", "7",
       "--interval-ms", "5", "--timeout-ms", "500", "--lose-after", "2", "--restore-after", "1"},
      &status);
  CHECK(status == 0);
  // each read rewrites the line: carriage return and "erase to the end of the line"
  const std::string refresh = "\r\x1b[K";
  std::vector<std::string> shown;
  for (std::size_t b = out.find(refresh); b != std::string::npos;) {
    const std::size_t e = out.find(refresh, b + refresh.size());
    shown.push_back(
        out.substr(b + refresh.size(), e == std::string::npos ? e : e - b - refresh.size()));
    b = e;
  }
  REQUIRE_MESSAGE(shown.size() == 7, out);
  for (std::size_t k = 1; k <= 7; ++k) {
    CAPTURE(shown[k - 1]);
    CHECK(shown[k - 1].find("read " + std::to_string(k) + "  ") == 0);
    if (k < 7) {
      CHECK(shown[k - 1].find('\n') == std::string::npos);  // no new line between reads
    }
  }
  CHECK(shown[0].find("pos 30000 ") != std::string::npos);
  CHECK(shown[0].find("link up") != std::string::npos);
  CHECK(shown[3].find("link up") != std::string::npos);
  CHECK(shown[3].find("timeouts 1 ") != std::string::npos);
  CHECK(shown[4].find("link lost") != std::string::npos);
  CHECK(shown[4].find("last timeout") != std::string::npos);
  CHECK(shown[4].find("pos 90000 ") != std::string::npos);  // held at read 3's
  CHECK(shown[6].find("pos 210000 ") != std::string::npos);
  CHECK(shown[6].find("link up") != std::string::npos);
  CHECK(shown[6].find("timeouts 2 ") != std::string::npos);
  // the live line ends, then the summary (the terminal turns \n into \r\n)
  CHECK(shown[6].find("\r\n# summary=watch reads=7 link=up") != std::string::npos);
}

TEST_CASE("read tformat --watch: usage errors") {
  int status = 0;
  testcli::run_stderr("read tformat --device /dev/null --id 2 --watch", &status);
  CHECK(status == 2);
  const std::string m = testcli::run_stderr(
      "read tformat --device /dev/null --id 0 --watch --max-step 65536", &status);
  CHECK(status == 2);
  CHECK(m.find("at most 65535 counts") != std::string::npos);
  testcli::run_stderr("read tformat --device /dev/null --id 3 --interval-ms 5", &status);
  CHECK(status == 2);
  testcli::run_stderr("read tformat --device /dev/null --id 3 --watch --interval-ms 0", &status);
  CHECK(status == 2);
}

TEST_CASE("monitor --duration: past 4294 s (its microseconds above 2^32) it does not stop early") {
  testcli::raw_pty pty;
  int status = 0;
  // 4295 s: the 32-bit product was 32.7 ms; the monitor must still run when killed after 1 s
  testcli::run_bounded("monitor tformat --device " + pty.path + " --duration 4295", 1, &status);
  CHECK(status == 124);
  // and a short duration still ends the monitor by itself
  testcli::run_bounded("monitor tformat --device " + pty.path + " --duration 1", 10, &status);
  CHECK(status == 0);
}
