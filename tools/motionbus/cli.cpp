// Shared pieces of the motionbus CLI.
#include "cli.hpp"

#include <nlohmann/json.hpp>

#include <cctype>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <utility>

namespace cli {

namespace {

std::string hex_text(std::int64_t value, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%0*llX", digits, static_cast<unsigned long long>(value));
  return buf;
}

format& current_format() {
  static format f = format::text;
  return f;
}

}  // namespace

format output_format() {
  return current_format();
}
void set_output_format(format f) {
  current_format() = f;
}

record::record() = default;
record::~record() = default;
record::record(const record& other)
    : json_(other.json_ ? std::make_unique<nlohmann::ordered_json>(*other.json_) : nullptr),
      text_(other.text_) {}
record& record::operator=(const record& other) {
  if (this != &other) {
    record copy(other);
    *this = std::move(copy);
  }
  return *this;
}
record::record(record&& other) noexcept = default;
record& record::operator=(record&& other) noexcept = default;

const nlohmann::ordered_json& record::json() const {
  static const nlohmann::ordered_json no_fields = nlohmann::ordered_json::object();
  return json_ ? *json_ : no_fields;
}
nlohmann::ordered_json& record::fields_json() {
  if (!json_) {
    json_ = std::make_unique<nlohmann::ordered_json>(nlohmann::ordered_json::object());
  }
  return *json_;
}

record& record::add_integer(const std::string& key, std::int64_t value) {
  fields_json()[key] = value;
  text_.emplace_back(key, std::to_string(value));
  return *this;
}
record& record::add_hex(const std::string& key, std::int64_t value, int digits) {
  fields_json()[key] = value;
  text_.emplace_back(key, hex_text(value, digits));
  return *this;
}
record& record::quantity(const std::string& key, double value, const std::string& unit) {
  fields_json()[key] = value;
  std::ostringstream s;
  s << value << ' ' << unit;
  text_.emplace_back(key, s.str());
  return *this;
}
record& record::measured(const std::string& key, double value, const std::string& unit,
                         std::int64_t raw) {
  fields_json()[key] = nlohmann::ordered_json{{"value", value}, {"unit", unit}, {"raw", raw}};
  std::ostringstream s;
  s << value << (unit.empty() ? "" : " ") << unit;
  text_.emplace_back(key, s.str());
  return *this;
}
record& record::add(const std::string& key, const std::string& value) {
  fields_json()[key] = value;
  const bool quote = value.empty() || value.find(' ') != std::string::npos;
  text_.emplace_back(key, quote ? "\"" + value + "\"" : value);
  return *this;
}
record& record::add(const std::string& key, const char* value) {
  return add(key, std::string(value));
}
record& record::add_bool(const std::string& key, bool value) {
  fields_json()[key] = value;
  text_.emplace_back(key, value ? "yes" : "no");
  return *this;
}
record& record::add(const std::string& key, const std::vector<std::int64_t>& values) {
  fields_json()[key] = values;
  std::string t;
  for (const std::int64_t v : values) {
    t += (t.empty() ? "" : ",") + std::to_string(v);
  }
  text_.emplace_back(key, values.empty() ? "-" : t);
  return *this;
}
record& record::add(const std::string& key, const std::vector<std::string>& values) {
  fields_json()[key] = values;
  std::string t;
  for (const std::string& v : values) {
    t += (t.empty() ? "" : ",") + v;
  }
  text_.emplace_back(key, values.empty() ? "none" : t);
  return *this;
}
record& record::add(const std::string& key, const std::vector<std::string>& values,
                    const std::string& text) {
  fields_json()[key] = values;
  text_.emplace_back(key, text);
  return *this;
}
record& record::bytes(const std::string& key, const std::uint8_t* data, std::size_t size) {
  fields_json()[key] = to_hex(data, size);
  std::string t;
  for (std::size_t i = 0; i < size; ++i) {
    char buf[4];
    std::snprintf(buf, sizeof buf, "%02X", static_cast<unsigned>(data[i]));
    t += (i == 0 ? "" : " ") + std::string(buf);
  }
  text_.emplace_back(key, size == 0 ? "-" : "[" + t + "]");
  return *this;
}
record& record::add(const std::string& key, const nlohmann::ordered_json& value,
                    const std::string& text) {
  fields_json()[key] = value;
  text_.emplace_back(key, text);
  return *this;
}
record& record::append(const record& other) {
  for (const auto& item : other.json().items()) {
    fields_json()[item.key()] = item.value();
  }
  text_.insert(text_.end(), other.text_.begin(), other.text_.end());
  return *this;
}
std::string record::text() const {
  std::string out;
  for (const auto& f : text_) {
    out += (out.empty() ? "" : " ") + f.first + "=" + f.second;
  }
  return out;
}

void print(const outcome& o, const record& prefix) {
  if (output_format() == format::json) {
    nlohmann::ordered_json j = prefix.json();
    j["ok"] = o.ok;
    if (!o.ok) {
      j["error"] = o.error;
    }
    for (const auto& item : (o.ok ? o.fields : o.evidence).json().items()) {
      j[item.key()] = item.value();
    }
    std::cout << j.dump() << '\n';
    return;
  }
  std::string line = prefix.text();
  line += (line.empty() ? "" : "  ") + std::string(o.ok ? "ok" : "FAIL " + o.error);
  const std::string body = (o.ok ? o.fields : o.evidence).text();
  if (!body.empty()) {
    line += "  " + body;
  }
  std::cout << line << '\n';
}

void print_record(const record& r) {
  if (output_format() == format::json) {
    std::cout << r.json().dump() << '\n';
  } else {
    std::cout << "# " << r.text() << '\n';
  }
}

int finish(const outcome& o) {
  print(o);
  std::cout.flush();
  return o.ok ? 0 : 1;
}

namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') {
    return c - '0';
  }
  if (c >= 'a' && c <= 'f') {
    return c - 'a' + 10;
  }
  if (c >= 'A' && c <= 'F') {
    return c - 'A' + 10;
  }
  return -1;
}

std::string trim(const std::string& s) {
  std::size_t b = 0;
  std::size_t e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b])) != 0) {
    ++b;
  }
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])) != 0) {
    --e;
  }
  return s.substr(b, e - b);
}

}  // namespace

std::optional<std::vector<std::uint8_t>> parse_hex(const std::string& text, std::string& error) {
  std::vector<std::uint8_t> out;
  std::string digits;
  // Tokens separated by white space (or ':' / '-'); each token may carry a 0x prefix and must
  // have an even number of digits.
  std::string token;
  auto flush = [&]() -> bool {
    if (token.empty()) {
      return true;
    }
    std::string t = token;
    token.clear();
    if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
      t = t.substr(2);
    }
    if (t.size() % 2 != 0) {
      error = "invalid_hex";
      return false;
    }
    for (std::size_t i = 0; i < t.size(); i += 2) {
      const int hi = hex_digit(t[i]);
      const int lo = hex_digit(t[i + 1]);
      if (hi < 0 || lo < 0) {
        error = "invalid_hex";
        return false;
      }
      out.push_back(static_cast<std::uint8_t>(hi * 16 + lo));
    }
    return true;
  };
  for (const char c : text) {
    if (std::isspace(static_cast<unsigned char>(c)) != 0 || c == ':' || c == '-') {
      if (!flush()) {
        return std::nullopt;
      }
    } else {
      token += c;
    }
  }
  if (!flush()) {
    return std::nullopt;
  }
  if (out.empty()) {
    error = "empty_input";
    return std::nullopt;
  }
  return out;
}

std::optional<std::vector<std::uint8_t>> parse_bits(const std::string& text, std::string& error) {
  std::vector<std::uint8_t> out;
  for (const char c : text) {
    if (c == '0' || c == '1') {
      out.push_back(static_cast<std::uint8_t>(c - '0'));
    } else if (c != ' ' && c != '_' && c != '\t') {
      error = "invalid_bits";
      return std::nullopt;
    }
  }
  if (out.empty()) {
    error = "empty_input";
    return std::nullopt;
  }
  return out;
}

std::optional<std::uint64_t> parse_uint(const std::string& text) {
  const std::string t = trim(text);
  if (t.empty()) {
    return std::nullopt;
  }
  std::uint64_t v = 0;
  std::size_t i = 0;
  unsigned base = 10;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    base = 16;
    i = 2;
  }
  for (; i < t.size(); ++i) {
    const int d = base == 16 ? hex_digit(t[i]) : (t[i] >= '0' && t[i] <= '9' ? t[i] - '0' : -1);
    if (d < 0) {
      return std::nullopt;
    }
    const std::uint64_t next = v * base + static_cast<std::uint64_t>(d);
    if (next / base != v) {
      return std::nullopt;  // overflow
    }
    v = next;
  }
  return v;
}

std::string to_hex(const std::uint8_t* data, std::size_t size) {
  static const char digits[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < size; ++i) {
    out += digits[data[i] >> 4U];
    out += digits[data[i] & 0x0FU];
  }
  return out;
}

int run_inputs(const std::string& input, const std::function<outcome(const std::string&)>& handle) {
  bool all_ok = true;
  auto one = [&](const std::string& text) {
    const outcome o = handle(text);
    print(o);
    all_ok = all_ok && o.ok;
  };
  if (input == "-") {
    std::string line;
    while (std::getline(std::cin, line)) {
      if (!line.empty() && line.back() == '\r') {
        line.pop_back();
      }
      if (trim(line).empty()) {
        continue;
      }
      one(line);
    }
  } else {
    one(input);
  }
  std::cout.flush();
  return all_ok ? 0 : 1;
}

}  // namespace cli
