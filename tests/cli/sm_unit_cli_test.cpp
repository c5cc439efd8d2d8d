// `motionbus read sm-unit` and `read modbus --fc11 sm` against an SM unit on a pseudo-terminal,
// with timestamps taken on the unit's side: the 0.1 s between commands (SM unit guideline §3),
// no login for a read that does not need it, login restored after one that does (§6), and the
// FC11 reply in the unit's layout (§11) whatever its version bytes.
#include <doctest/doctest.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "motionbus/devices/sm_unit.hpp"
#include "motionbus/devices/sm_unit_emulator.hpp"
#include "motionbus/modbus.hpp"
#include "run_cli.hpp"

namespace mb = motionbus;
namespace mo = motionbus::modbus;
namespace sm = motionbus::devices::sm_unit;

namespace {

using clock_type = std::chrono::steady_clock;

struct request_seen {
  std::uint8_t function = 0;
  std::uint16_t address = 0;
  clock_type::time_point first_byte;  // when its first byte arrived
  clock_type::time_point replied;     // when the reply was written
};

// The unit: the SM unit emulator behind the server dispatch, on the master side of a pty, with
// FC11 answered as version 2.3 (`01 11 02 03 10 BC`: upper byte other than 1).
class unit_on_pty {
 public:
  unit_on_pty() {
    thread_ = std::thread([this] { loop(); });
  }
  ~unit_on_pty() {
    stop_ = true;
    thread_.join();
  }
  const std::string& device() const { return pty_.path; }
  std::vector<request_seen> take() {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<request_seen> out;
    out.swap(seen_);
    return out;
  }
  bool logged_in() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return unit_.logged_in();
  }
  // Serves one request ADU directly (setting up the unit's state).
  void serve(const std::vector<std::uint8_t>& adu) {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::uint8_t out[256] = {};
    REQUIRE(mo::serve_rtu(unit_, 1, mb::byte_view(adu.data(), adu.size()), out).ok());
  }

 private:
  void loop() {
    mo::rtu_framer rx(mo::framer_role::server, {1});
    clock_type::time_point start{};
    while (!stop_) {
      pollfd p{pty_.master, POLLIN, 0};
      std::uint8_t buffer[256];
      long n = 0;
      if (poll(&p, 1, 5) > 0) {
        n = read(pty_.master, buffer, sizeof buffer);
      }
      if (n < 0) {
        n = 0;
      }
      if (n > 0 && rx.pending() == 0) {
        start = clock_type::now();
      }
      mb::byte_view in(buffer, static_cast<std::size_t>(n));
      for (;;) {
        auto r = n == 0 ? rx.idle() : rx.feed(in);
        if (r.is_incomplete()) {
          break;
        }
        in = in.subspan(n == 0 ? 0 : r.consumed());
        if (r.is_complete()) {
          answer(r.value(), start);
          start = clock_type::now();  // a following frame in the same read starts now
        }
        if (n == 0) {
          break;
        }
      }
    }
  }
  void answer(const mo::rtu_frame& frame, clock_type::time_point first_byte) {
    std::uint8_t out[256] = {};
    std::size_t size = 0;
    request_seen s;
    s.function = frame.pdu[0];
    s.address = frame.pdu.size() >= 3U ? mo::register_at(frame.pdu.subspan(1), 0) : 0;
    s.first_byte = first_byte;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (frame.pdu[0] == 0x11) {
        const std::uint8_t version[] = {0x01, 0x11, 0x02, 0x03, 0x10, 0xBC};
        size = sizeof version;
        std::copy(version, version + size, out);
      } else {
        const mb::byte_view adu(frame.pdu.data() - 1, frame.pdu.size() + 3U);
        size = mo::serve_rtu(unit_, 1, adu, out).value_or(0);
      }
    }
    // Taken before the write: the CLI cannot read the reply before it (after the write, this
    // thread may be descheduled while the CLI already reads and starts its 0.1 s). Recorded
    // before the write too: after it the CLI may read the reply, end, and the test take() the
    // requests before this one is in (a CI run saw one request of two).
    s.replied = clock_type::now();
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      seen_.push_back(s);
    }
    if (size > 0U) {
      REQUIRE(write(pty_.master, out, size) == static_cast<long>(size));
    }
  }

  testcli::raw_pty pty_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  sm::emulator unit_;
  std::vector<request_seen> seen_;
  std::thread thread_;
};

double gap_ms(const request_seen& before, const request_seen& after) {
  return std::chrono::duration<double, std::milli>(after.first_byte - before.replied).count();
}

void check_paced(const std::vector<request_seen>& seen) {
  for (std::size_t i = 1; i < seen.size(); ++i) {
    CAPTURE(i);
    CHECK(gap_ms(seen[i - 1], seen[i]) >= 100.0);  // §3: at least 0.1 s between commands
  }
}

}  // namespace

TEST_CASE("read sm-unit: paced 0.1 s, no login to read data, FC11 in the unit's layout") {
  unit_on_pty unit;
  int status = 0;
  const std::string out = testcli::run("read sm-unit --device '" + unit.device() + "'", &status);
  CHECK(status == 0);
  CHECK_FIELDS(out, R"({"ok":true,"slave":1,"version":"2.0.3"})");
  CHECK(testcli::json_lines(out).at(0)["voltage"]["value"].is_number());
  const auto seen = unit.take();
  // and as a person reads it: values with their units
  std::this_thread::sleep_for(std::chrono::milliseconds(120));
  const std::string text =
      testcli::run_as_is("read sm-unit --device '" + unit.device() + "'", &status);
  CHECK(status == 0);
  CHECK(text.find("ok  slave=1 version=2.0.3 voltage=") == 0);
  CHECK(text.find(" V current=") != std::string::npos);
  CHECK(text.find(" degC ") != std::string::npos);
  (void)unit.take();
  REQUIRE(seen.size() == 2);
  CHECK(seen[0].function == 0x04);
  CHECK(seen[0].address == sm::input::instantaneous);
  CHECK(seen[1].function == 0x11);
  check_paced(seen);
  CHECK(unit.logged_in());  // as it was: nothing written

  // logged out: a data read still writes nothing
  std::uint8_t adu[64] = {};
  const auto pw = mb::byte_view(reinterpret_cast<const std::uint8_t*>("password"), 8);
  const std::size_t k = sm::login(1, pw, adu).value();
  unit.serve(std::vector<std::uint8_t>(adu, adu + k));
  REQUIRE(!unit.logged_in());
  CHECK_FIELDS(testcli::run("read sm-unit --device '" + unit.device() + "'", &status),
               "{\"version\":\"2.0.3\"}");
  for (const auto& s : unit.take()) {
    CHECK(s.function != 0x10);
  }
  CHECK(!unit.logged_in());
}

TEST_CASE("read sm-unit --read password: logs in only when needed, restores the state") {
  unit_on_pty unit;
  int status = 0;
  // logged in (power-on state): status, then the password block; no login written
  std::string out =
      testcli::run("read sm-unit --read password --device '" + unit.device() + "'", &status);
  CHECK(status == 0);
  CHECK_JSON(out,
             "{\"ok\":true,\"slave\":1,\"logged_in\":true,\"logged_in_by_read\":false,"
             "\"login_restored\":false,\"password\":\"password\"}\n");
  auto seen = unit.take();
  REQUIRE(seen.size() == 2);
  CHECK(seen[0].function == 0x04);
  CHECK(seen[0].address == sm::input::login_status);
  CHECK(seen[1].function == 0x03);
  CHECK(seen[1].address == sm::holding::password);
  check_paced(seen);
  // logged out: status, login, password, logout, each 0.1 s after the previous reply
  std::uint8_t adu[64] = {};
  const auto pw = mb::byte_view(reinterpret_cast<const std::uint8_t*>("password"), 8);
  const std::size_t k = sm::login(1, pw, adu).value();
  unit.serve(std::vector<std::uint8_t>(adu, adu + k));
  REQUIRE(!unit.logged_in());
  out = testcli::run("read sm-unit --read password --device '" + unit.device() + "'", &status);
  CHECK(status == 0);
  CHECK_JSON(out,
             "{\"ok\":true,\"slave\":1,\"logged_in\":false,\"logged_in_by_read\":true,"
             "\"login_restored\":true,\"password\":\"password\"}\n");
  seen = unit.take();
  REQUIRE(seen.size() == 4);
  CHECK(seen[1].function == 0x10);
  CHECK(seen[1].address == sm::holding::login);
  CHECK(seen[2].function == 0x03);
  CHECK(seen[3].function == 0x10);
  check_paced(seen);
  CHECK(!unit.logged_in());  // as found
}

TEST_CASE("read modbus --fc11 sm: the two-byte version reply is framed and decoded") {
  unit_on_pty unit;
  int status = 0;
  const std::string dev = " --device '" + unit.device() + "'";
  CHECK_JSON(testcli::run("read modbus --slave 1 --function 17 --fc11 sm" + dev, &status),
             "{\"ok\":true,\"slave\":1,\"function\":17,\"version_upper\":2,\"version_lower\":3,"
             "\"version\":\"2.0.3\",\"crc\":48144}\n");
  CHECK(status == 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(120));
  CHECK(testcli::run_as_is("read modbus --slave 1 --function 17 --fc11 sm" + dev, &status) ==
        "ok  slave=1 function=0x11 version_upper=2 version_lower=3 version=2.0.3 crc=0xBC10\n");
  CHECK(status == 0);
  // in the standard layout, 02 is a byte count with one byte present: the silence ends the
  // frame and the count is refused
  CHECK_JSON(testcli::run("read modbus --slave 1 --function 17 --timeout-ms 300" + dev, &status),
             "{\"ok\":false,\"error\":\"byte_count_mismatch\"}\n");
  CHECK(status == 1);
  CHECK(testcli::run("read modbus --slave 1 --function 17 --fc11 other" + dev, &status).empty());
  CHECK(status == 2);
}

TEST_CASE(
    "read sm-unit: an address outside 1..16 or a bad password is a usage error, nothing sent") {
  unit_on_pty unit;
  const std::string dev = " --device '" + unit.device() + "'";
  // SM unit guideline §2: slave addresses 1-16; §10: passwords of 8 to 16 characters 0x21..0x7E
  for (const char* args :
       {"--slave 17", "--slave 247", "--slave 0", "--read password --password abcd",
        "--read password --password abcdefghijklmnopq", "--read password --password 'pass word'",
        "--password short"}) {
    CAPTURE(args);
    int status = 0;
    CHECK(testcli::run(std::string("read sm-unit ") + args + dev, &status).empty());
    CHECK(status == 2);
  }
  CHECK(testcli::run_stderr("read sm-unit --slave 17" + dev).find("1..16") != std::string::npos);
  CHECK(unit.take().empty());
  // the emulator refuses it too (bounded: an emulator that starts would serve until killed)
  int status = 0;
  testcli::run_bounded("serve sm-unit --slave 17" + dev, 5, &status);
  CHECK(status == 2);
  // the help says what the unit takes
  const std::string help = testcli::run_as_is("read sm-unit --help", &status);
  CHECK(status == 0);
  CHECK(help.find("8 to 16 characters") != std::string::npos);
  CHECK(help.find("4 characters") == std::string::npos);
}
