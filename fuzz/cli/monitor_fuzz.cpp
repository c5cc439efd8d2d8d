// The bus monitors (tools/motionbus/bus_monitor.hpp: `monitor` and `decode ... capture`) on a
// line of bytes, silences and UART errors. The first byte: bit 0 the protocol (Modbus RTU,
// T-format), bit 1 the output (text, JSON lines), bit 2 Modbus's FC 11 format, bits 3-7 the
// gap (in byte times, 1 to 32). Then operations, each a header byte h and its bytes:
//   h & 3 == 0: (h >> 2) + 1 bytes read from the port at once (monitor's bytes()); the first
//               operation's are handed over at time 0 (bytes waiting when the watch began)
//   h & 3 == 1: a silence of (h >> 2) byte times (tick())
//   h & 3 == 2: one byte a capture's UART decoder found, with a parity error when h & 4, a
//               framing error when h & 8, else none (byte_at())
//   h & 3 == 3: a silence of (h >> 2) * 1000 byte times (tick(), past the response time)
// then end(). Oracles: after end() no byte is held; one output line for each frame settled
// and each missing response (every record printed, one per line), each JSON line an object
// that parses with an "ok" field, its times (time_us, latency_us, request_time_us) no later
// than the end (none wrapped below 0), the lines' time_us rising (a response found missing
// while a frame that began before its deadline was still arriving was once printed after it
// and later than its time); the tally consistent (frames at most the bytes heard,
// garbage bytes at most the bytes heard).

// fuzz-max-len: 1024 (the option byte and 1023 of operations and their bytes: four times the
// 256 bytes the Modbus monitor's listener holds at most, the T-format one's 11; a longer line
// only repeats their states)
#include <cstdint>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "../fuzz_check.hpp"
#include "bus_monitor.hpp"
#include "cli.hpp"

namespace {

template <class Monitor>
void run(Monitor& m, const std::uint8_t* data, std::size_t size, std::uint32_t byte_us,
         std::uint32_t gap_us, bool json) {
  std::ostringstream out;
  std::streambuf* const saved = std::cout.rdbuf(out.rdbuf());
  std::uint64_t now = 0;
  std::uint64_t last = 0;
  std::uint64_t heard = 0;
  std::size_t i = 0;
  while (i < size) {
    const std::uint8_t h = data[i++];
    switch (h & 3U) {
      case 0: {
        std::size_t n = (h >> 2U) + 1U;
        n = n < size - i ? n : size - i;
        if (n == 0) {
          break;
        }
        if (i != 1) {  // not the first operation
          now += std::uint64_t{n} * byte_us;
        }
        m.bytes(data + i, n, now);
        heard += n;
        i += n;
        last = now;
        m.tick(now, 0);
        break;
      }
      case 1:
      case 3: {
        const std::uint64_t silence =
            std::uint64_t{h} / 4U * byte_us * ((h & 3U) == 3U ? 1000U : 1U);
        now += silence;
        m.tick(now, now - last);
        break;
      }
      default: {
        if (i == size) {
          break;
        }
        const char* error =
            (h & 4U) != 0 ? "parity_error" : ((h & 8U) != 0 ? "framing_error" : nullptr);
        m.byte_at(data[i++], now, error);
        now += byte_us;
        last = now;
        ++heard;
        break;
      }
    }
  }
  const std::uint64_t end = now + gap_us;
  m.end(end);
  std::cout.rdbuf(saved);
  MOTIONBUS_FUZZ_CHECK(m.held() == 0);
  const bus_monitor::tally& t = m.counts();
  MOTIONBUS_FUZZ_CHECK(t.frames <= heard);
  MOTIONBUS_FUZZ_CHECK(t.garbage_bytes <= heard);
  MOTIONBUS_FUZZ_CHECK(t.requests + t.responses <= t.frames);
  std::istringstream lines(out.str());
  std::string line;
  std::uint64_t printed = 0;
  std::uint64_t last_time = 0;
  while (std::getline(lines, line)) {
    ++printed;
    if (json) {
      const auto j = nlohmann::json::parse(line, nullptr, false);
      MOTIONBUS_FUZZ_CHECK(!j.is_discarded() && j.is_object() && j.contains("ok"));
      for (const char* key : {"time_us", "latency_us", "request_time_us"}) {
        MOTIONBUS_FUZZ_CHECK(!j.contains(key) || j[key].get<std::uint64_t>() <= end);
      }
      if (j.contains("time_us")) {
        MOTIONBUS_FUZZ_CHECK(j["time_us"].get<std::uint64_t>() >= last_time);
        last_time = j["time_us"].get<std::uint64_t>();
      }
    }
  }
  MOTIONBUS_FUZZ_CHECK(printed == t.frames + t.missing);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  const std::uint8_t mode = data[0];
  const bool json = (mode & 2U) != 0;
  cli::set_output_format(json ? cli::format::json : cli::format::text);
  const std::uint32_t gap_bytes = (mode >> 3U) + 1U;
  if ((mode & 1U) == 0) {
    const std::uint32_t byte_us = 1146;  // 9600 bit/s, 8E1
    const auto fc11 = (mode & 4U) != 0 ? motionbus::modbus::report_id_format::two_bytes_no_count
                                       : motionbus::modbus::report_id_format::standard;
    bus_monitor::modbus_monitor m(fc11, gap_bytes * byte_us, byte_us, 1000000);
    run(m, data + 1, size - 1, byte_us, gap_bytes * byte_us, json);
  } else {
    const std::uint32_t byte_us = 4;  // 2.5 Mbit/s, 8N1
    bus_monitor::tformat_monitor m(gap_bytes * byte_us, byte_us, 1000000);
    run(m, data + 1, size - 1, byte_us, gap_bytes * byte_us, json);
  }
  return 0;
}
