// T-format through the CLI: decode/encode contract, and the master and the encoder emulator
// talking over a pseudo-terminal pair (this test plays the other end with the library).
#include <doctest/doctest.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "motionbus/devices/ts5700n8500_emulator.hpp"
#include "motionbus/tformat.hpp"
#include "run_cli.hpp"

namespace mb = motionbus;
namespace tf = motionbus::tformat;

namespace {

std::string run_cli(const std::string& args, int* status = nullptr) {
  return testcli::run(args, status);
}

std::string xor_hex(const std::vector<unsigned>& bytes) {
  std::string out;
  unsigned x = 0;
  char b[4];
  for (unsigned v : bytes) {
    x ^= v;
    std::snprintf(b, sizeof b, "%02x", v);
    out += b;
  }
  std::snprintf(b, sizeof b, "%02x", x);
  return out + b;
}

// A pseudo-terminal pair (raw on both sides): the master fd stays here, the slave path goes to
// the CLI.
struct pty_pair : testcli::raw_pty {
  long read_for(std::uint8_t* buffer, std::size_t capacity, int timeout_ms) const {
    pollfd p{master, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0) {
      return 0;
    }
    return read(master, buffer, capacity);
  }
};

}  // namespace

TEST_CASE("decode/encode tformat: fields as JSON integers, errors as codes") {
  int status = 0;
  // ID3: abs 0x012345, enid 0x11, abm 0x1234, almc BE|BA, sf ea1
  auto out = run_cli("decode tformat response " +
                         xor_hex({0x1A, 0x20, 0x45, 0x23, 0x01, 0x11, 0x34, 0x12, 0x00, 0xC0}),
                     &status);
  CHECK(status == 0);
  CHECK_FIELDS(out, "{\"data_id\":3,\"cf\":26,\"sf\":32,\"ea0\":0,\"ea1\":1,\"ca0\":0,\"ca1\":0}");
  CHECK_FIELDS(out,
               "{\"abs\":74565,\"abm\":4660,\"enid\":17,\"almc\":192,\"alarms\":[\"BE\",\"BA\"]}");
  // 23-bit position: refused at the default 17 bits, accepted with --resolution 23 or ENID 0x17
  const std::string abs23 = xor_hex({0x02, 0x00, 0xFF, 0xFF, 0x7F});
  CHECK_JSON(run_cli("decode tformat response " + abs23, &status),
             "{\"ok\":false,\"error\":\"out_of_range\"}\n");
  CHECK(status == 1);
  CHECK_FIELDS(run_cli("decode tformat response " + abs23 + " --resolution 23"),
               "{\"abs\":8388607}");
  CHECK_FIELDS(run_cli("decode tformat response " +
                       xor_hex({0x1A, 0x00, 0xFF, 0xFF, 0x7F, 0x17, 0x00, 0x00, 0x00, 0x00})),
               "{\"abs\":8388607}");
  // EEPROM responses
  CHECK_JSON(
      run_cli("decode tformat response " + xor_hex({0xEA, 0x85, 0x00})),
      "{\"ok\":true,\"data_id\":13,\"cf\":234,\"address\":5,\"busy\":1,\"edf\":0,\"crc\":111}\n");
  // errors
  CHECK_JSON(run_cli("decode tformat response 020000000001"),
             "{\"ok\":false,\"error\":\"crc_mismatch\",\"expected\":2,\"received\":1}\n");
  CHECK_JSON(run_cli("decode tformat response 0200000000"),
             "{\"ok\":false,\"error\":\"truncated\"}\n");
  CHECK_JSON(run_cli("decode tformat response 02000000000200"),
             "{\"ok\":false,\"error\":\"wrong_length\"}\n");
  CHECK_JSON(run_cli("decode tformat response 03"), "{\"ok\":false,\"error\":\"sync_code\"}\n");
  CHECK_JSON(run_cli("decode tformat response 82"), "{\"ok\":false,\"error\":\"parity\"}\n");
  // requests
  CHECK_JSON(run_cli("decode tformat request 1a"), "{\"ok\":true,\"data_id\":3,\"cf\":26}\n");
  CHECK(testcli::run_as_is("decode tformat request ea05ef") ==
        "ok  data_id=13 cf=0xEA address=0x05 crc=0xEF\n");
  CHECK(testcli::run_as_is("decode tformat request ea0564") ==
        "FAIL crc_mismatch  expected=0xEF received=0x64\n");
  CHECK(testcli::run_as_is("encode tformat request --id 6 --address 5 --data 18") ==
        "ok  hex=[32 05 12 25]\n");
  CHECK(run_cli("decode tformat request ea0564") ==  // 0xEA ^ 0x05 = 0xEF: CRC wrong
        "{\"ok\":false,\"error\":\"crc_mismatch\",\"expected\":239,\"received\":100}\n");
  CHECK_JSON(run_cli("decode tformat request ea05ef"),
             "{\"ok\":true,\"data_id\":13,\"cf\":234,\"address\":5,\"crc\":239}\n");
  CHECK_JSON(run_cli("encode tformat request --id 3", &status), "{\"ok\":true,\"hex\":\"1a\"}\n");
  CHECK(status == 0);
  CHECK_JSON(run_cli("encode tformat request --id 6 --address 5 --data 18"),
             "{\"ok\":true,\"hex\":\"32051225\"}\n");
  CHECK_JSON(run_cli("encode tformat request --id D --address 127"),
             "{\"ok\":true,\"hex\":\"ea7f95\"}\n");
  // what the library's builder refuses is a usage error naming the library's code
  CHECK(run_cli("encode tformat request --id 4", &status).empty());
  CHECK(status == 2);
  CHECK(testcli::run_stderr("encode tformat request --id 4").find("unknown_data_id") !=
        std::string::npos);
  CHECK(run_cli("encode tformat request --id D --address 128", &status).empty());
  CHECK(status == 2);
  CHECK(testcli::run_stderr("encode tformat request --id D --address 128").find("out_of_range") !=
        std::string::npos);
  run_cli("encode tformat request", &status);
  CHECK(status == 2);
  run_cli("encode tformat request --id 3 --bogus 1", &status);
  CHECK(status == 2);
}

TEST_CASE("serve tformat-encoder: a master talks to the emulator over a pseudo-terminal") {
  pty_pair pty;
  int started[2] = {-1, -1};  // the emulator's stderr: its first line says the port is open
  REQUIRE(pipe(started) == 0);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    testcli::die_with_parent(parent);
    dup2(started[1], STDERR_FILENO);
    execl(MOTIONBUS_CLI_PATH, "motionbus", "serve", "tformat-encoder", "--device", pty.path.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  close(started[1]);
  struct reaper {  // stops the emulator even when an assertion ends the test case early
    pid_t pid;
    int fd;
    ~reaper() {
      close(fd);
      if (pid > 0) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
      }
    }
  } guard{pid, started[0]};
  // Every request is sent once, after the emulator has opened the port: an answer is waited
  // for (2 s, a loaded machine's allowance), never asked for again.
  std::string banner;
  for (char c = 0; banner.find('\n') == std::string::npos;) {
    pollfd p{started[0], POLLIN, 0};
    REQUIRE(poll(&p, 1, 10000) > 0);
    REQUIRE(read(started[0], &c, 1) == 1);
    banner += c;
  }
  REQUIRE(banner.find("T-format encoder emulator on") != std::string::npos);
  auto transact = [&](tf::data_id id, std::uint8_t address, std::uint8_t data) {
    std::uint8_t req[4] = {};
    const std::size_t n = tf::encode_request(id, address, data, req).value();
    REQUIRE(write(pty.master, req, n) == static_cast<ssize_t>(n));
    tf::receiver rx;
    rx.sent(mb::byte_view(req, n));
    std::uint8_t buffer[32];
    for (long got = 0; (got = pty.read_for(buffer, sizeof buffer, 2000)) > 0;) {
      mb::decode_result<tf::response> answer;
      bool found = false;
      mb::feed_all(rx, mb::byte_view(buffer, static_cast<std::size_t>(got)), [&](const auto& r) {
        answer = r;
        found = true;
        return false;
      });
      if (found) {
        return answer;
      }
    }
    FAIL("no response from the emulator");
    return tf::receiver().feed(mb::byte_view{});
  };
  const auto all = transact(tf::data_id::read_all, 0, 0);
  REQUIRE(all.is_complete());
  CHECK(all->enid == 0x11);
  const auto w = transact(tf::data_id::eeprom_write, 9, 0x77);
  REQUIRE(w.is_complete());
  CHECK(w->edf == 0x77);
  usleep(20000);  // the EEPROM write takes 18 ms
  // the write is read back once the page is specified again (spec §10)
  const auto stale = transact(tf::data_id::eeprom_read, 9, 0);
  REQUIRE(stale.is_complete());
  CHECK(stale->edf == 0x00);
  const auto page = transact(tf::data_id::eeprom_write, 127, 0);
  REQUIRE(page.is_complete());
  usleep(20000);  // busy after the page change
  const auto rd = transact(tf::data_id::eeprom_read, 9, 0);
  REQUIRE(rd.is_complete());
  CHECK(rd->edf == 0x77);
  kill(pid, SIGTERM);
  int status = 0;
  bool exited = false;
  for (int waited_ms = 0; !exited && waited_ms < 10000; waited_ms += 10) {  // it polls each 100 ms
    exited = waitpid(pid, &status, WNOHANG) == pid;
    usleep(exited ? 0 : 10000);
  }
  REQUIRE_MESSAGE(exited, "the emulator did not end within 10 s of SIGTERM; it is:\n"
                              << testcli::process_state(pid));
  guard.pid = -1;
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
}

TEST_CASE("read tformat: one transaction with an encoder on a pseudo-terminal") {
  pty_pair pty;
  std::atomic<bool> done{false};
  std::thread encoder([&] {
    motionbus::devices::ts5700n8500::emulator enc;
    enc.set_position(0x1ABCD, 42);
    enc.set_condition(tf::almc_bit::ba, true);
    std::uint8_t frame[8] = {};
    std::size_t size = 0;
    while (!done) {
      std::uint8_t byte = 0;
      if (pty.read_for(&byte, 1, 10) != 1) {
        continue;
      }
      frame[size++] = byte;
      if (tf::decode_request(mb::byte_view(frame, size)).is_incomplete() && size < 4) {
        continue;
      }
      const motionbus::devices::ts5700n8500::reply r = enc.respond(mb::byte_view(frame, size), 0);
      size = 0;
      if (write(pty.master, r.bytes, r.size) != static_cast<ssize_t>(r.size)) {
        break;
      }
    }
  });
  int status = 0;
  const std::string out =
      run_cli("read tformat --device " + pty.path + " --id 3 --timeout-ms 2000", &status);
  // and as a person reads it: hex where the specification writes hex, the alarm by name
  int text_status = 0;
  const std::string text = testcli::run_as_is(
      "read tformat --device " + pty.path + " --id 3 --timeout-ms 2000", &text_status);
  done = true;
  encoder.join();
  CHECK(text_status == 0);
  CHECK(text.find("ok  data_id=3 cf=0x1A sf=0x20") == 0);
  CHECK(text.find("abs=109517 abm=42 enid=0x11 almc=0x80 alarms=\"BA battery alarm\" crc=0x") !=
        std::string::npos);
  CHECK(status == 0);
  CHECK_FIELDS(out, "{\"ok\":true,\"data_id\":3}");
  CHECK_FIELDS(out, "{\"abs\":109517,\"abm\":42,\"enid\":17,\"almc\":128,\"alarms\":[\"BA\"]}");
}
