// Runs the codecs in a program whose global operator new and malloc family abort: any heap use
// by the library ends the process with a non-zero status. Linked with -Wl,--wrap=malloc (and
// calloc/realloc/free), so calls from this program's own code are caught while the C runtime's
// start-up is left alone. Built a second time with MOTIONBUS_NO_HEAP_SELF_TEST, which allocates
// on purpose: that run must fail, proving the trap works.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

#include "motionbus/motionbus.hpp"

namespace {
// Exit status 99 marks heap use (a plain exit, so ctest's WILL_FAIL sees it as a failure).
[[noreturn]] void trap() {
  std::_Exit(99);
}
}  // namespace

extern "C" {
[[noreturn]] void* __wrap_malloc(std::size_t) {
  trap();
}
[[noreturn]] void* __wrap_calloc(std::size_t, std::size_t) {
  trap();
}
[[noreturn]] void* __wrap_realloc(void*, std::size_t) {
  trap();
}
void __wrap_free(void* p) {
  if (p != nullptr) {
    trap();
  }
}
}

void* operator new(std::size_t) {
  trap();
}
void* operator new[](std::size_t) {
  trap();
}
void* operator new(std::size_t, const std::nothrow_t&) noexcept {
  trap();
}
void* operator new[](std::size_t, const std::nothrow_t&) noexcept {
  trap();
}
void operator delete(void*) noexcept {
  trap();
}
void operator delete[](void*) noexcept {
  trap();
}
void operator delete(void*, std::size_t) noexcept {
  trap();
}
void operator delete[](void*, std::size_t) noexcept {
  trap();
}

namespace mb = motionbus;

namespace {

int failures = 0;

void expect(bool condition) {
  if (!condition) {
    ++failures;
  }
}

// Inputs come from the command line's length so the compiler cannot fold the work away.
void run_core(std::uint8_t seed) {
  std::uint8_t buffer[64] = {};
  for (std::size_t i = 0; i < sizeof buffer; ++i) {
    buffer[i] = static_cast<std::uint8_t>(seed + i * 7U);
  }
  const mb::byte_view view(buffer, sizeof buffer);
  expect(mb::crc16_modbus<mb::crc_table_size::byte>::compute(view) ==
         mb::crc16_modbus<mb::crc_table_size::bitwise>::compute(view));
  expect(mb::crc8_tformat<>::compute(view) ==
         mb::crc8_tformat<mb::crc_table_size::nibble>::compute(view));
  mb::crc6_biss<> c6;
  expect(c6.update_stream(view, mb::bit_order::msb_first, 3, 34) == mb::errc::ok);
  mb::crc6_biss<mb::crc_table_size::bitwise> b6;
  expect(b6.update_stream(view, mb::bit_order::msb_first, 3, 34) == mb::errc::ok);
  expect(c6.value() == b6.value());
  expect(mb::crc4_biss<>::compute_bits(seed, 11) ==
         mb::crc4_biss<mb::crc_table_size::bitwise>::compute_bits(seed, 11));

  std::uint8_t out[16] = {};
  mb::bit_writer w(out, mb::bit_order::lsb_first, seed % 8U);
  expect(w.write(0x123456789AULL, 40) == mb::errc::ok);
  mb::bit_reader r(out, mb::bit_order::lsb_first, seed % 8U);
  expect(r.read(40).value() == 0x123456789AULL);
  expect(r.read(200).error() == mb::errc::invalid_argument);
}

}  // namespace

int main(int argc, char**) {
  run_core(static_cast<std::uint8_t>(argc));
#ifdef MOTIONBUS_NO_HEAP_SELF_TEST
  // a call of the replaceable operator itself: a new-expression's allocation may be elided
  // (clang at -O2 does), this call may not
  void* volatile p = ::operator new(sizeof(int));  // must abort
  failures += p == nullptr ? 1 : 0;
#endif
  return failures == 0 ? 0 : 1;
}
