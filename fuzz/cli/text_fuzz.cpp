// The CLI's input parsers (tools/motionbus/cli.cpp) against models written here from their
// documented grammar: parse_hex (bytes as hex tokens separated by white space, ':' or '-',
// each with an optional 0x and an even number of digits), parse_bits ('0' and '1', spaces,
// tabs and underscores ignored), parse_uint (decimal or 0x hex, surrounding white space
// ignored, no overflow: std::from_chars is the model). The first byte selects the parser, the
// rest is the text. Oracles: the same answer as the model (bytes, bits, value or a named error),
// and for a success the round trip (to_hex / the decimal or hex text parsed back).
#include <cctype>
#include <charconv>
#include <cstdio>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "../fuzz_check.hpp"
#include "cli.hpp"

namespace {

bool separator(char c) {
  return std::isspace(static_cast<unsigned char>(c)) != 0 || c == ':' || c == '-';
}

int nibble(char c) {
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

// The model of parse_hex: the bytes, or nullopt and the error's name.
std::optional<std::vector<std::uint8_t>> hex_model(const std::string& text, std::string& error) {
  std::vector<std::uint8_t> out;
  std::size_t i = 0;
  while (i < text.size()) {
    if (separator(text[i])) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && !separator(text[j])) {
      ++j;
    }
    std::string token = text.substr(i, j - i);
    i = j;
    if (token.size() > 2 && token[0] == '0' && (token[1] == 'x' || token[1] == 'X')) {
      token.erase(0, 2);
    }
    if (token.size() % 2 != 0) {
      error = "invalid_hex";
      return std::nullopt;
    }
    for (std::size_t k = 0; k < token.size(); k += 2) {
      if (nibble(token[k]) < 0 || nibble(token[k + 1]) < 0) {
        error = "invalid_hex";
        return std::nullopt;
      }
      out.push_back(static_cast<std::uint8_t>(nibble(token[k]) << 4 | nibble(token[k + 1])));
    }
  }
  if (out.empty()) {
    error = "empty_input";
    return std::nullopt;
  }
  return out;
}

void check_hex(const std::string& text) {
  std::string error;
  std::string model_error;
  const auto got = cli::parse_hex(text, error);
  const auto want = hex_model(text, model_error);
  MOTIONBUS_FUZZ_CHECK(got.has_value() == want.has_value());
  if (!got) {
    MOTIONBUS_FUZZ_CHECK(error == model_error);
    return;
  }
  MOTIONBUS_FUZZ_CHECK(*got == *want);
  std::string again_error;
  const auto again = cli::parse_hex(cli::to_hex(got->data(), got->size()), again_error);
  MOTIONBUS_FUZZ_CHECK(again && *again == *got);
}

void check_bits(const std::string& text) {
  std::string error;
  const auto got = cli::parse_bits(text, error);
  std::vector<std::uint8_t> want;
  bool valid = true;
  for (const char c : text) {
    if (c == '0' || c == '1') {
      want.push_back(c == '1' ? 1 : 0);
    } else if (c != ' ' && c != '\t' && c != '_') {
      valid = false;
    }
  }
  if (!valid) {
    MOTIONBUS_FUZZ_CHECK(!got && error == "invalid_bits");
  } else if (want.empty()) {
    MOTIONBUS_FUZZ_CHECK(!got && error == "empty_input");
  } else {
    MOTIONBUS_FUZZ_CHECK(got && *got == want);
  }
}

void check_uint(const std::string& text) {
  const auto got = cli::parse_uint(text);
  std::size_t b = 0;
  std::size_t e = text.size();
  while (b < e && std::isspace(static_cast<unsigned char>(text[b])) != 0) {
    ++b;
  }
  while (e > b && std::isspace(static_cast<unsigned char>(text[e - 1])) != 0) {
    --e;
  }
  const std::string t = text.substr(b, e - b);
  std::optional<std::uint64_t> want;
  const bool hex = t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X');
  const std::string digits = hex ? t.substr(2) : t;
  std::uint64_t v = 0;
  const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v, hex ? 16 : 10);
  if (!digits.empty() && r.ec == std::errc{} && r.ptr == digits.data() + digits.size()) {
    want = v;
  }
  MOTIONBUS_FUZZ_CHECK(got == want);
  if (got) {
    MOTIONBUS_FUZZ_CHECK(cli::parse_uint(std::to_string(*got)) == got);
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%llX", static_cast<unsigned long long>(*got));
    MOTIONBUS_FUZZ_CHECK(cli::parse_uint(buf) == got);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  switch (data[0] % 3) {
    case 0: check_hex(text); break;
    case 1: check_bits(text); break;
    default: check_uint(text); break;
  }
  return 0;
}
