// Recordings for the CLI: sigrok session files (a zip archive, read with libzip: a "metadata"
// INI file naming the probes, the sample rate and the sample size, then the samples in chunks
// "logic-1-1", "logic-1-2", ...), VCD (IEEE 1364 §18: $timescale, $scope, $var, then "#time"
// and value changes) and CSV (a header row, a time column and one column per channel, as logic
// analyzer software exports it).
#include "capture.hpp"

#include <zip.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "cli.hpp"

namespace capture {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t\r\n\"");
  const std::size_t e = s.find_last_not_of(" \t\r\n\"");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw cli::usage_error{path + ": " + why};
}

void append(channel& c, double t, bool level) {
  if (c.levels.empty() || c.levels.back() != level) {
    c.times.push_back(t);
    c.levels.push_back(level);
  }
}

// A unit's factor to seconds: "s", "ms", "us", "ns", "ps", "fs" (and µs).
double seconds_per(const std::string& unit_text, bool& ok) {
  const std::string u = lower(trim(unit_text));
  ok = true;
  if (u == "s" || u.empty()) {
    return 1.0;
  }
  if (u == "ms") {
    return 1e-3;
  }
  if (u == "us" || u == "\xC2\xB5s") {
    return 1e-6;
  }
  if (u == "ns") {
    return 1e-9;
  }
  if (u == "ps") {
    return 1e-12;
  }
  if (u == "fs") {
    return 1e-15;
  }
  ok = false;
  return 1.0;
}

// A number of the file (a time, a timescale, a sample rate): the whole of `text` a finite,
// non-negative decimal number (std::strtod: the C locale's decimal point), else a usage error
// naming `what` and the text.
double number_in(const std::string& path, const std::string& text, const std::string& what) {
  const char* begin = text.c_str();
  char* stop = nullptr;
  const double v = text.empty() ? 0.0 : std::strtod(begin, &stop);
  if (text.empty() || stop != begin + text.size() ||
      std::isspace(static_cast<unsigned char>(text[0])) != 0 || !std::isfinite(v)) {
    fail(path, what + " '" + text + "' is not a number");
  }
  if (v < 0) {
    fail(path, what + " '" + text + "' is negative");
  }
  return v;
}

// The longest recording read, in seconds.
constexpr double max_recording_s = 1e6;

// --- VCD -------------------------------------------------------------------------------------

recording read_vcd(std::istream& in, const std::string& path) {
  recording r;
  r.format = "vcd";
  std::map<std::string, std::vector<std::size_t>> by_id;  // an id may name several variables
  std::vector<std::string> scope;
  double timescale = 1e-9;
  double now = 0;
  bool in_definitions = true;
  std::string token;
  // The words of a section up to its $end; a file that ends first is cut short.
  auto read_until_end = [&](std::vector<std::string>& words, const std::string& section) {
    words.clear();
    while (in >> token) {
      if (token == "$end") {
        return;
      }
      words.push_back(token);
    }
    fail(path, "the file ends inside " + section + " (no $end)");
  };
  std::vector<std::string> words;
  while (in >> token) {
    if (in_definitions) {
      if (token == "$timescale") {
        read_until_end(words, token);
        std::string joined;
        for (const auto& w : words) {
          joined += w;
        }
        std::size_t digits = 0;
        while (digits < joined.size() && std::isdigit(static_cast<unsigned char>(joined[digits]))) {
          ++digits;
        }
        bool ok = false;
        const double unit = seconds_per(joined.substr(digits), ok);
        if (digits == 0 || !ok) {
          fail(path, "unreadable $timescale '" + joined + "'");
        }
        timescale = number_in(path, joined.substr(0, digits), "the $timescale") * unit;
        if (!(timescale > 0)) {
          fail(path, "the $timescale '" + joined + "' is not above zero");
        }
      } else if (token == "$scope") {
        read_until_end(words, token);
        scope.push_back(words.size() >= 2 ? words[1] : "");
      } else if (token == "$upscope") {
        read_until_end(words, token);
        if (!scope.empty()) {
          scope.pop_back();
        }
      } else if (token == "$var") {
        read_until_end(words, token);  // type size id reference [index]
        if (words.size() < 4) {
          fail(path, "a $var without its reference");
        }
        if (words[1] == "1") {
          channel c;
          c.name = words[3];
          std::string full;
          for (const auto& sc : scope) {
            full += sc + ".";
          }
          r.channels.push_back(c);
          by_id[words[2]].push_back(r.channels.size() - 1);
          if (!full.empty()) {
            channel alias;
            alias.name = full + words[3];
            r.channels.push_back(alias);
            by_id[words[2]].push_back(r.channels.size() - 1);
          }
        }
      } else if (token == "$enddefinitions") {
        read_until_end(words, token);
        in_definitions = false;
      } else if (token[0] == '$') {
        read_until_end(words, token);  // $date, $version, $comment
      } else {
        fail(path, "'" + token + "' among the definitions (before $enddefinitions)");
      }
      continue;
    }
    const char first = token[0];
    if (first == '#') {
      const double t = number_in(path, token.substr(1), "the time") * timescale;
      if (!std::isfinite(t)) {
        fail(path, "the time '" + token + "' is out of range");
      }
      if (t < now) {
        fail(path, "the time '" + token + "' goes back (times rise in a VCD file)");
      }
      now = t;
      r.end = std::max(r.end, now);
    } else if (first == '0' || first == '1' || first == 'x' || first == 'X' || first == 'z' ||
               first == 'Z') {
      // x and z read as high: a released (pulled-up) line
      const auto it = by_id.find(token.substr(1));
      if (it != by_id.end()) {
        for (const std::size_t i : it->second) {
          append(r.channels[i], now, first != '0');
        }
      }
    } else if (first == 'b' || first == 'B' || first == 'r' || first == 'R') {
      if (!(in >> token)) {  // a vector or real value and its id: not a 1-bit channel
        fail(path, "the file ends inside a vector value (no identifier)");
      }
    } else if (token == "$dumpvars" || token == "$end" || token == "$dumpall" ||
               token == "$dumpon" || token == "$dumpoff") {
      continue;
    } else if (first == '$') {
      read_until_end(words, token);
    } else {
      fail(path, "'" + token + "' is neither a time, a value change nor a section");
    }
  }
  if (in_definitions) {
    fail(path, "no $enddefinitions (not a VCD file, or cut short)");
  }
  if (r.channels.empty()) {
    fail(path, "no 1-bit variable ($var ... 1 ...) in the VCD file");
  }
  return r;
}

// --- CSV -------------------------------------------------------------------------------------

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream s(line);
  while (std::getline(s, cell, ',')) {
    out.push_back(trim(cell));
  }
  if (!line.empty() && line.back() == ',') {
    out.emplace_back();  // an empty last cell
  }
  return out;
}

recording read_csv(std::istream& in, const std::string& path) {
  recording r;
  r.format = "csv";
  std::string line;
  double unit = 1.0;
  bool header = false;
  double last = 0;
  std::size_t row = 0;
  while (std::getline(in, line)) {
    ++row;
    const std::string t = trim(line);
    if (t.empty() || t[0] == ';' || t[0] == '#') {
      continue;
    }
    const std::vector<std::string> cells = split_csv(t);
    if (!header) {
      if (cells.size() < 2) {
        fail(path, "the header needs a time column and a channel");
      }
      // "Time [s]", "Time(us)", "time_ns": the unit in brackets, parentheses or a suffix
      const std::string h = lower(cells[0]);
      const std::size_t open = h.find_first_of("[(");
      bool ok = true;
      if (open != std::string::npos) {
        const std::size_t close = h.find_first_of("])", open);
        if (close == std::string::npos) {
          fail(path, "the time unit in '" + cells[0] + "' is not closed");
        }
        unit = seconds_per(h.substr(open + 1, close - open - 1), ok);
      } else if (h.size() > 5 && h.compare(0, 5, "time_") == 0) {
        unit = seconds_per(h.substr(5), ok);
      }
      if (!ok) {
        fail(path, "unknown time unit in '" + cells[0] + "'");
      }
      for (std::size_t i = 1; i < cells.size(); ++i) {
        if (cells[i].empty()) {
          fail(path, "the header's column " + std::to_string(i + 1) + " has no channel name");
        }
        channel c;
        c.name = cells[i];
        r.channels.push_back(c);
      }
      header = true;
      continue;
    }
    const std::string where = "row " + std::to_string(row);
    if (cells.size() != r.channels.size() + 1) {
      fail(path, where + " has " + std::to_string(cells.size()) + " cells, the header " +
                     std::to_string(r.channels.size() + 1));
    }
    const double time = number_in(path, cells[0], where + ": the time") * unit;
    if (time < last) {
      fail(path, where + ": the time '" + cells[0] + "' goes back (times rise in a recording)");
    }
    last = time;
    for (std::size_t i = 0; i < r.channels.size(); ++i) {
      if (cells[i + 1] != "0" && cells[i + 1] != "1") {
        fail(path, where + ": the level '" + cells[i + 1] + "' of '" + r.channels[i].name +
                       "' is not 0 or 1");
      }
      append(r.channels[i], time, cells[i + 1] == "1");
    }
    r.end = std::max(r.end, time);
  }
  if (!header) {
    fail(path, "no header row");
  }
  return r;
}

// --- sigrok session files --------------------------------------------------------------------

// The largest member read from a session file (sigrok writes its samples in chunks of a few MB).
constexpr zip_uint64_t max_member = 1ULL << 30;

struct zip_closer {
  void operator()(zip_t* z) const { zip_close(z); }
};

// The member `name` of the archive in `out`, as far as it reads; false when there is none or
// it cannot be read whole (a member larger than max_member: a usage error).
bool read_member(zip_t* z, const std::string& path, const std::string& name, std::string& out) {
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat(z, name.c_str(), 0, &st) != 0) {
    return false;
  }
  if ((st.valid & ZIP_STAT_SIZE) != 0 && st.size > max_member) {
    fail(path, "the member '" + name + "' is larger than 1 GiB");
  }
  zip_file_t* f = zip_fopen(z, name.c_str(), 0);
  if (f == nullptr) {
    return false;
  }
  out.clear();
  char block[65536];
  zip_int64_t n = 0;
  while ((n = zip_fread(f, block, sizeof block)) > 0 &&
         out.size() + static_cast<std::size_t>(n) <= max_member) {
    out.append(block, static_cast<std::size_t>(n));
  }
  zip_fclose(f);
  if (n < 0) {
    fail(path, "the member '" + name + "' cannot be read (a damaged archive)");
  }
  if (n > 0) {
    fail(path, "the member '" + name + "' is larger than 1 GiB");
  }
  return true;
}

// "1 MHz", "500 kHz", "24000000": samples per second, 1 Hz to 1 THz.
double rate_of(const std::string& text, bool& ok) {
  std::istringstream s(text);
  double v = 0;
  std::string unit;
  ok = static_cast<bool>(s >> v);
  s >> unit;
  std::string rest;
  ok = ok && !(s >> rest);
  unit = lower(unit);
  const double f = unit == "ghz" ? 1e9 : unit == "mhz" ? 1e6 : unit == "khz" ? 1e3 : 1.0;
  ok = ok && (unit.empty() || unit == "hz" || f != 1.0) && v * f >= 1.0 && v * f <= 1e12;
  return v * f;
}

// A count of the metadata: decimal digits only, at most 4 of them; -1 otherwise.
int small_count(const std::string& text) {
  if (text.empty() || text.size() > 4 ||
      !std::all_of(text.begin(), text.end(),
                   [](unsigned char c) { return std::isdigit(c) != 0; })) {
    return -1;
  }
  return std::atoi(text.c_str());
}

recording read_sr(const std::string& data, const std::string& path) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(data.data(), data.size(), 0, &error);
  if (source == nullptr) {
    zip_error_fini(&error);
    fail(path, "not a sigrok session file (not a zip archive)");
  }
  std::unique_ptr<zip_t, zip_closer> z(zip_open_from_source(source, ZIP_RDONLY, &error));
  zip_error_fini(&error);
  if (!z) {
    zip_source_free(source);
    fail(path, "not a sigrok session file (not a zip archive)");
  }
  std::string metadata;
  if (!read_member(z.get(), path, "metadata", metadata)) {
    fail(path, "no metadata in the session file");
  }
  return read_session(
      metadata,
      [&](const std::string& name, std::string& out) {
        return read_member(z.get(), path, name, out);
      },
      path);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    fail(path, "cannot open");
  }
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) {
    fail(path, "cannot read");
  }
  return s.str();
}

std::size_t index_at(const channel& c, double t, bool inclusive) {
  // the last change at or before t (inclusive) or before t
  const auto it = inclusive ? std::upper_bound(c.times.begin(), c.times.end(), t)
                            : std::lower_bound(c.times.begin(), c.times.end(), t);
  return static_cast<std::size_t>(it - c.times.begin());
}

}  // namespace

recording read_session(const std::string& metadata, const session_member& member,
                       const std::string& path) {
  std::map<std::string, std::string> device;  // the keys of [device 1]
  std::istringstream m(metadata);
  std::string line;
  std::string section;
  while (std::getline(m, line)) {
    line = trim(line);
    if (!line.empty() && line[0] == '[') {
      section = line;
    } else if (section == "[device 1]" && line.find('=') != std::string::npos) {
      device[trim(line.substr(0, line.find('=')))] = trim(line.substr(line.find('=') + 1));
    }
  }
  bool ok = false;
  const double rate = rate_of(device["samplerate"], ok);
  if (!ok) {
    fail(path, "unreadable samplerate '" + device["samplerate"] + "' (1 Hz to 1 THz)");
  }
  const int probes = small_count(device["total probes"]);
  const int unitsize = small_count(device["unitsize"]);
  if (probes < 1 || unitsize < 1 || unitsize > 8 || probes > unitsize * 8) {
    fail(path, "unreadable probes or unitsize ('" + device["total probes"] + "', '" +
                   device["unitsize"] + "': 1 to 8 bytes a sample, a probe a bit)");
  }
  recording r;
  r.format = "sr";
  for (int p = 1; p <= probes; ++p) {
    channel c;
    c.name = device["probe" + std::to_string(p)];
    r.channels.push_back(c);
  }
  const std::string base = device.count("capturefile") != 0 ? device["capturefile"] : "logic-1";
  std::string chunk;
  std::uint64_t sample = 0;
  auto take = [&](const std::string& data) {
    if (data.size() % static_cast<std::size_t>(unitsize) != 0) {
      fail(path, "a chunk of samples is not a whole number of " + std::to_string(unitsize) +
                     "-byte samples");
    }
    const std::size_t n = data.size() / static_cast<std::size_t>(unitsize);
    for (std::size_t i = 0; i < n; ++i, ++sample) {
      std::uint64_t bits = 0;
      for (int b = 0; b < unitsize; ++b) {
        bits |= static_cast<std::uint64_t>(static_cast<unsigned char>(
                    data[i * static_cast<std::size_t>(unitsize) + static_cast<std::size_t>(b)]))
                << (8 * b);
      }
      const double t = static_cast<double>(sample) / rate;
      for (int p = 0; p < probes; ++p) {
        append(r.channels[static_cast<std::size_t>(p)], t, ((bits >> p) & 1U) != 0U);
      }
    }
  };
  if (member(base, chunk)) {
    take(chunk);  // one unsplit member (older files)
  }
  for (int k = 1; member(base + "-" + std::to_string(k), chunk); ++k) {
    take(chunk);
  }
  if (sample == 0) {
    fail(path, "no samples in the session file");
  }
  r.end = static_cast<double>(sample - 1) / rate;
  return r;
}

recording parse(const std::string& format, const std::string& data, const std::string& path) {
  try {
    recording r;
    if (format == "vcd") {
      std::istringstream in(data);
      r = read_vcd(in, path);
    } else if (format == "csv") {
      std::istringstream in(data);
      r = read_csv(in, path);
    } else if (format == "sr") {
      r = read_sr(data, path);
    } else {
      throw cli::usage_error{path + ": a recording is a .sr, .vcd or .csv file"};
    }
    // a double holds a time to better than a nanosecond up to 10^6 s (about 11 days); later
    // times would merge a UART's bits
    if (r.end > max_recording_s) {
      fail(path, "the recording lasts more than 10^6 s (its times would lose their nanoseconds)");
    }
    return r;
  } catch (const std::logic_error&) {  // a library's refusal of a malformed number
    fail(path, "a number in the file cannot be read");
  }
}

bool channel::level_before(double t) const {
  const std::size_t i = index_at(*this, t, false);
  return i == 0 ? (levels.empty() || levels[0]) : levels[i - 1];
}

bool channel::level_at(double t) const {
  const std::size_t i = index_at(*this, t, true);
  return i == 0 ? (levels.empty() || levels[0]) : levels[i - 1];
}

const channel& recording::find(const std::string& name) const {
  std::string names;
  for (const channel& c : channels) {
    if (c.name == name) {
      return c;
    }
    names += (names.empty() ? "" : ", ") + c.name;
  }
  throw cli::usage_error{"no channel '" + name + "' in the recording (it has: " + names + ")"};
}

recording load(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::string ext = dot == std::string::npos ? "" : lower(path.substr(dot + 1));
  if (ext != "vcd" && ext != "csv" && ext != "sr") {
    throw cli::usage_error{path + ": a recording is a .sr, .vcd or .csv file"};
  }
  return parse(ext, read_file(path), path);
}

std::vector<uart_byte> decode_uart(const channel& line, double baud, char parity,
                                   unsigned stop_bits) {
  std::vector<uart_byte> out;
  const double bit = 1.0 / baud;
  const unsigned parity_bits = parity == 'N' ? 0U : 1U;
  double from = line.times.empty() ? 0 : line.times[0];
  for (std::size_t i = 1; i < line.times.size(); ++i) {
    if (line.levels[i] || !line.levels[i - 1] || line.times[i] < from) {
      continue;  // not a falling edge, or inside the last byte
    }
    const double start = line.times[i];
    if (line.level_at(start + bit / 2)) {
      continue;  // a glitch, not a start bit
    }
    uart_byte b;
    b.start = start;
    unsigned ones = 0;
    for (unsigned k = 0; k < 8; ++k) {
      if (line.level_at(start + (1.5 + k) * bit)) {
        b.value = static_cast<std::uint8_t>(b.value | (1U << k));
        ++ones;
      }
    }
    if (parity_bits != 0U) {
      const bool p = line.level_at(start + 9.5 * bit);
      ones += p ? 1U : 0U;
      b.parity_error = (parity == 'E') ? (ones % 2U != 0U) : (ones % 2U == 0U);
    }
    for (unsigned s = 0; s < stop_bits; ++s) {
      if (!line.level_at(start + (9.5 + parity_bits + s) * bit)) {
        b.framing_error = true;
      }
    }
    b.end = start + (9.0 + parity_bits + stop_bits) * bit;
    from = start + (9.5 + parity_bits) * bit;  // the next start bit may follow the stop bit
    out.push_back(b);
  }
  return out;
}

void uart_levels(const std::vector<std::uint8_t>& bytes, double baud, char parity,
                 unsigned stop_bits, double start, channel& line) {
  const double bit = 1.0 / baud;
  append(line, 0, true);
  double t = start;
  for (const std::uint8_t v : bytes) {
    std::vector<bool> bits = {false};
    unsigned ones = 0;
    for (unsigned k = 0; k < 8; ++k) {
      bits.push_back(((v >> k) & 1U) != 0U);
      ones += (v >> k) & 1U;
    }
    if (parity == 'E') {
      bits.push_back(ones % 2U != 0U);
    } else if (parity == 'O') {
      bits.push_back(ones % 2U == 0U);
    }
    for (unsigned s = 0; s < stop_bits; ++s) {
      bits.push_back(true);
    }
    for (const bool b : bits) {
      append(line, t, b);
      t += bit;
    }
  }
  append(line, t, true);
}

void biss_levels(const std::vector<std::uint8_t>& bits, double clock_hz, double start, channel& ma,
                 channel& slo) {
  const double period = 1.0 / clock_hz;
  append(ma, 0, true);
  append(slo, 0, true);
  double t = start;
  for (const std::uint8_t b : bits) {
    append(ma, t, false);
    append(slo, t, b != 0U);
    append(ma, t + period / 2, true);
    t += period;
  }
  append(slo, t + period, true);
}

void write_vcd_file(const std::string& path, const std::vector<channel>& channels) {
  std::ofstream out(path);
  if (!out) {
    throw cli::usage_error{"cannot write " + path};
  }
  write_vcd(out, channels);
  if (!out) {
    throw cli::usage_error{"cannot write " + path};
  }
}

void write_vcd(std::ostream& out, const std::vector<channel>& channels) {
  out << "$version motionbus $end\n$timescale 1 ns $end\n$scope module motionbus $end\n";
  for (std::size_t i = 0; i < channels.size(); ++i) {
    out << "$var wire 1 " << static_cast<char>('!' + i) << ' ' << channels[i].name << " $end\n";
  }
  out << "$upscope $end\n$enddefinitions $end\n";
  std::map<long long, std::vector<std::pair<std::size_t, bool>>> changes;
  for (std::size_t i = 0; i < channels.size(); ++i) {
    for (std::size_t k = 0; k < channels[i].times.size(); ++k) {
      changes[std::llround(channels[i].times[k] * 1e9)].emplace_back(i, channels[i].levels[k]);
    }
  }
  bool first = true;
  for (const auto& c : changes) {
    out << '#' << c.first << '\n';
    if (first) {
      out << "$dumpvars\n";
    }
    for (const auto& v : c.second) {
      out << (v.second ? '1' : '0') << static_cast<char>('!' + v.first) << '\n';
    }
    if (first) {
      out << "$end\n";
      first = false;
    }
  }
}

}  // namespace capture
