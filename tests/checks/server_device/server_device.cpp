// Device types the Modbus server must refuse at compile time (modbus/server.hpp): compiled once
// per case with -DCASE_<name> by cmake/checks/compile_fails.cmake, which expects each case to
// fail with its static_assert message, and the file without a case (a valid device) to compile.
#include <motionbus/modbus/server.hpp>

#include <cstdint>

namespace mb = motionbus;
namespace md = motionbus::modbus;

namespace {

// A valid device: holding registers 0..7 read and written.
struct registers {
  std::uint16_t regs[8] = {};
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> values) {
    if (address + values.size() > 8U) {
      return 0x02;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      regs[address + i] = values[i];
    }
    return 0;
  }
};

#if defined(CASE_no_accessor)
struct device {};  // no accessor the server recognises
#elif defined(CASE_unservable_function)
struct device : registers {
  // 03 needs a register reader, which this device lacks
  static constexpr md::function_set functions = md::functions_of(0x03, 0x06, 0x10);
};
#elif defined(CASE_span_reference)
struct device : registers {
  // near miss: the span by non-const reference
  std::uint8_t read_registers(std::uint8_t, std::uint16_t, mb::span<std::uint16_t>& out) {
    out[0] = 0;
    return 0;
  }
};
#elif defined(CASE_non_const_span)
struct device {
  // near miss: the values as a span of non-const registers
  std::uint8_t write_registers(std::uint16_t, mb::span<std::uint16_t>) { return 0; }
};
#elif defined(CASE_singular_name)
struct device : registers {
  // near miss: read_register for read_registers
  std::uint8_t read_register(std::uint8_t, std::uint16_t, mb::span<std::uint16_t> out) {
    out[0] = 0;
    return 0;
  }
};
#elif defined(CASE_wrong_return)
struct device : registers {
  // near miss: returns bool, not the exception code
  bool write_coils(std::uint16_t, std::uint16_t, mb::byte_view) { return true; }
};
#elif defined(CASE_functions_not_static)
struct device : registers {
  md::function_set functions = md::functions_of(0x06);  // near miss: not static constexpr
};
#elif defined(CASE_admit_not_const)
struct device : registers {
  // near miss: a check that could change the device
  std::uint8_t admit(mb::byte_view) { return 0; }
};
#else
struct device : registers {
  static constexpr md::function_set functions = md::functions_of(0x06, 0x10);
};
static_assert(md::served_functions<device>() == md::functions_of(0x06, 0x10), "06 and 10");
#endif

}  // namespace

int serve(const std::uint8_t* adu, std::size_t n, std::uint8_t* out) {
  device d;
  const auto r = md::serve_rtu(d, 1, mb::byte_view(adu, n), mb::mutable_byte_view(out, 256));
  return r.ok() ? static_cast<int>(r.value()) : -1;
}
