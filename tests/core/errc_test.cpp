// Error codes: every code's name (the CLI prints it) and the ranges of errc.hpp's enum.
#include "motionbus/core/errc.hpp"

#include <doctest/doctest.h>

#include <cstring>

using namespace motionbus;

TEST_CASE("every error code has a distinct snake_case name") {
  // Every value of the underlying type: the named ones must be snake_case and distinct.
  const char* names[256] = {};
  int named = 0;
  for (unsigned v = 0; v < 256U; ++v) {
    const char* name = to_string(static_cast<errc>(v));
    if (std::strcmp(name, "unknown") == 0) {
      continue;
    }
    ++named;
    names[v] = name;
    for (const char* c = name; *c != '\0'; ++c) {
      CHECK(((*c >= 'a' && *c <= 'z') || *c == '_'));
    }
    for (unsigned u = 0; u < v; ++u) {
      CHECK((names[u] == nullptr || std::strcmp(name, names[u]) != 0));
    }
  }
  CHECK(named >= 9 + 10 + 11 + 11);  // generic, T-format, Modbus, BiSS-C
  CHECK(std::strcmp(to_string(errc::biss_no_ack), "no_ack") == 0);
  CHECK(std::strcmp(to_string(static_cast<errc>(250)), "unknown") == 0);
}

TEST_CASE("every named code lies in its protocol's range of errc.hpp") {
  // generic 0..31, T-format 32..63, Modbus 64..127, BiSS-C 128..191; 192..255 unused
  int generic = 0;
  int tformat = 0;
  int modbus = 0;
  int biss = 0;
  for (unsigned v = 0; v < 256U; ++v) {
    if (std::strcmp(to_string(static_cast<errc>(v)), "unknown") == 0) {
      continue;
    }
    CHECK(v < 192U);
    generic += v < 32U ? 1 : 0;
    tformat += v >= 32U && v < 64U ? 1 : 0;
    modbus += v >= 64U && v < 128U ? 1 : 0;
    biss += v >= 128U && v < 192U ? 1 : 0;
  }
  CHECK(generic == 9);
  CHECK(tformat == 10);
  CHECK(modbus == 8 + 3 + 3);  // 64..71, Modbus ASCII's 80..82, the FC14/15 sub-request fields
  CHECK(biss == 11);
  CHECK(std::strcmp(to_string(errc::tformat_parity), "parity") == 0);  // the prefix is dropped
  CHECK(std::strcmp(to_string(errc::modbus_quantity), "illegal_quantity") == 0);
  CHECK(std::strcmp(to_string(errc::biss_layout), "invalid_layout") == 0);
  CHECK(std::strcmp(to_string(errc::modbus_ascii_end), "missing_crlf") == 0);
}
