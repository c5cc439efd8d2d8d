// Shared pieces of the motionbus CLI.
#include "cli.hpp"

#include <cctype>
#include <cstdio>
#include <iostream>
#include <utility>

namespace cli {

std::string json_quote(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20U) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x",
                        static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

json_object& json_object::add(const std::string& key, std::int64_t value) {
  fields_.emplace_back(key, std::to_string(value));
  return *this;
}
json_object& json_object::add(const std::string& key, const std::string& value) {
  fields_.emplace_back(key, json_quote(value));
  return *this;
}
json_object& json_object::add(const std::string& key, const char* value) {
  return add(key, std::string(value));
}
json_object& json_object::add_bool(const std::string& key, bool value) {
  fields_.emplace_back(key, value ? "true" : "false");
  return *this;
}
json_object& json_object::add(const std::string& key, const std::vector<std::int64_t>& values) {
  std::string list = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    list += (i == 0 ? "" : ",") + std::to_string(values[i]);
  }
  fields_.emplace_back(key, list + "]");
  return *this;
}
json_object& json_object::add(const std::string& key, const std::vector<std::string>& values) {
  std::string list = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    list += (i == 0 ? "" : ",") + json_quote(values[i]);
  }
  fields_.emplace_back(key, list + "]");
  return *this;
}
std::string json_object::str() const {
  std::string out = "{";
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    out += (i == 0 ? "" : ",") + json_quote(fields_[i].first) + ":" + fields_[i].second;
  }
  return out + "}";
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

bool options::has(const std::string& name) const {
  for (const auto& f : flags) {
    if (f == name) {
      return true;
    }
  }
  return values.count(name) != 0;
}

std::optional<std::string> options::get(const std::string& name) const {
  const auto it = values.find(name);
  if (it == values.end()) {
    return std::nullopt;
  }
  return it->second;
}

options parse_options(const std::vector<std::string>& args, std::size_t first,
                      const std::vector<std::string>& with_value,
                      const std::vector<std::string>& switches) {
  options o;
  for (std::size_t i = first; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.size() < 3 || a.compare(0, 2, "--") != 0) {
      throw usage_error{"unexpected argument '" + a + "'"};
    }
    std::string name = a.substr(2);
    std::optional<std::string> inline_value;
    const std::size_t eq = name.find('=');
    if (eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    bool known = false;
    for (const auto& v : with_value) {
      if (v == name) {
        known = true;
        if (inline_value) {
          o.values[name] = *inline_value;
        } else if (i + 1 < args.size()) {
          o.values[name] = args[++i];
        } else {
          throw usage_error{"option --" + name + " needs a value"};
        }
      }
    }
    for (const auto& s : switches) {
      if (s == name && !inline_value) {
        known = true;
        o.flags.push_back(name);
      }
    }
    if (!known) {
      throw usage_error{"unknown option '" + a + "'"};
    }
  }
  return o;
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

void print(const outcome& o) {
  if (o.ok) {
    json_object out;
    out.add_bool("ok", true);
    std::string body = o.fields.str();
    std::string head = out.str();
    // splice: {"ok":true} + {fields...}
    if (body.size() > 2) {
      head.pop_back();
      head += "," + body.substr(1);
    }
    std::cout << head << '\n';
  } else {
    json_object out;
    out.add_bool("ok", false).add("error", o.error);
    std::cout << out.str() << '\n';
  }
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

std::uint64_t option_number(const options& opts, const std::string& name, std::uint64_t fallback,
                            std::uint64_t max) {
  const auto v = opts.get(name);
  if (!v) {
    return fallback;
  }
  const auto n = parse_uint(*v);
  if (!n || *n > max) {
    throw usage_error{"--" + name + " needs a number up to " + std::to_string(max)};
  }
  return *n;
}

}  // namespace cli
