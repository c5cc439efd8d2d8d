// The CLI's sigrok session reader (tools/motionbus/capture.cpp). An input that starts with
// "PK" is a whole .sr file (a zip archive, read through libzip from memory); any other is a
// session without its archive, so that mutations reach the session's own parsing: the
// metadata text up to the first NUL byte, then a byte n, then the samples, cut into
// (n & 3) + 1 members named "<capturefile>-1", "-2", ... (and, when n & 4, the first of them
// named "<capturefile>" alone, as older files have it). Either way: a recording that keeps its
// promises, or a usage error naming what is wrong (recording_oracle.hpp).
#include <algorithm>
#include <string>
#include <vector>

#include "recording_oracle.hpp"

namespace {

void check_session(const std::string& input) {
  const std::size_t nul = input.find('\0');
  const std::string metadata = input.substr(0, nul);
  const std::string rest = nul == std::string::npos ? "" : input.substr(nul + 1);
  const unsigned n = rest.empty() ? 0U : static_cast<unsigned char>(rest[0]);
  const std::string samples = rest.empty() ? "" : rest.substr(1);
  const std::size_t count = (n & 3U) + 1U;
  std::vector<std::string> members;
  const std::size_t piece = (samples.size() + count - 1) / count;
  for (std::size_t i = 0; i < count && piece > 0; ++i) {
    members.push_back(samples.substr(std::min(samples.size(), i * piece), piece));
  }
  const bool unsplit = (n & 4U) != 0U;
  const std::string path = "input.sr";
  const capture::session_member member = [&](const std::string& name, std::string& out) {
    // the member's number after the last '-' (the capturefile's own name: "unsplit")
    const std::size_t dash = name.find_last_of('-');
    const std::string tail = dash == std::string::npos ? "" : name.substr(dash + 1);
    if (!tail.empty() && tail.size() < 3 &&
        std::all_of(tail.begin(), tail.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      const std::size_t k = static_cast<std::size_t>(std::stoi(tail));
      const std::size_t at = unsplit ? k : k - 1;
      if (k >= 1 && at < members.size()) {
        out = members[at];
        return true;
      }
      return false;
    }
    if (unsplit && !members.empty()) {
      out = members[0];
      return true;
    }
    return false;
  };
  try {
    const capture::recording r = capture::read_session(metadata, member, path);
    MOTIONBUS_FUZZ_CHECK(r.format == "sr");
    MOTIONBUS_FUZZ_CHECK(!r.channels.empty() && r.channels.size() <= 64);
    MOTIONBUS_FUZZ_CHECK(std::isfinite(r.end) && r.end >= 0);
    for (const capture::channel& c : r.channels) {
      fuzz_cli::check_channel(c, r.end);
      MOTIONBUS_FUZZ_CHECK(!c.times.empty() && c.times[0] == 0);  // every sample's level
    }
  } catch (const cli::usage_error& e) {
    MOTIONBUS_FUZZ_CHECK(e.message.rfind(path + ": ", 0) == 0);
    MOTIONBUS_FUZZ_CHECK(e.message.size() > path.size() + 2);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  if (input.rfind("PK", 0) == 0) {
    fuzz_cli::check_recording("sr", input);
  } else {
    check_session(input);
  }
  return 0;
}
