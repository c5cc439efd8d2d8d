// Device types the Modbus server must refuse at compile time (modbus/server.hpp): compiled once
// per case with -DCASE_<name> by cmake/checks/compile_fails.cmake, which expects each case to
// fail with its own static_assert message and no other, and the file without a case to compile
// (the valid devices, near misses of the names among them, are compiled with every case).
#include <motionbus/modbus/server.hpp>

#include <cstdint>

namespace mb = motionbus;
namespace md = motionbus::modbus;

namespace {

bool fits(std::size_t address, std::size_t quantity) {
  return address + quantity <= 8U;
}

// A valid writer: holding registers 0..7 written.
struct registers {
  std::uint16_t regs[8] = {};
  std::uint8_t write_registers(std::uint16_t address, mb::span<const std::uint16_t> values) {
    if (!fits(address, values.size())) {
      return 0x02;
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      regs[address + i] = values[i];
    }
    return 0;
  }
};

// A valid reader: input registers 0..7, all zero.
struct reader {
  std::uint8_t read_registers(std::uint8_t, std::uint16_t address,
                              mb::span<std::uint16_t> out) const {
    if (!fits(address, out.size())) {
      return 0x02;
    }
    for (std::uint16_t& r : out) {
      r = 0;
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
#elif defined(CASE_functions_empty)
struct device : registers {
  static constexpr md::function_set functions = md::functions_of();  // serves nothing
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
struct device : reader {
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
#elif defined(CASE_check_registers_not_const)
struct device : registers, reader {
  // near miss: a check that could change the device
  std::uint8_t check_registers(std::uint8_t, std::uint16_t, std::uint16_t) { return 0; }
};
#elif defined(CASE_file_record_signature)
struct device : registers {
  // near miss: the records as registers, not the PDU's big-endian bytes
  std::uint8_t read_file_record(std::uint16_t, std::uint16_t, mb::span<std::uint16_t>) { return 0; }
};
#elif defined(CASE_check_file_record_not_const)
struct device : registers {
  std::uint8_t write_file_record(std::uint16_t, std::uint16_t, mb::byte_view) { return 0; }
  // near miss: a check that could change the device
  std::uint8_t check_file_record(std::uint16_t, std::uint16_t, std::uint16_t) { return 0; }
};
#else
struct device : registers {
  static constexpr md::function_set functions = md::functions_of(0x06, 0x10);
};
static_assert(md::served_functions<device>() == md::functions_of(0x06, 0x10), "06 and 10");
#endif

// Big-endian accessors next to helpers named like the singular accessors, one public and one
// private: the singular names are near misses only where no accessor of their kind exists.
class be_with_helpers {
 public:
  std::uint8_t read_registers_be(std::uint8_t, std::uint16_t address, std::uint16_t quantity,
                                 mb::mutable_byte_view out) const {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      const std::uint16_t v = read_register(static_cast<std::uint16_t>(address + i));
      out[2U * i] = static_cast<std::uint8_t>(v >> 8U);
      out[2U * i + 1U] = static_cast<std::uint8_t>(v & 0xFFU);
    }
    return 0;
  }
  std::uint8_t write_registers_be(std::uint16_t address, std::uint16_t quantity,
                                  mb::byte_view data) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::size_t i = 0; i < quantity; ++i) {
      write_register(address + i, md::register_at(data, i));
    }
    return 0;
  }
  std::uint16_t read_register(std::uint16_t address) const { return regs_[address]; }

 private:
  void write_register(std::size_t address, std::uint16_t value) { regs_[address] = value; }
  std::uint16_t regs_[8] = {};
};
static_assert(md::served_functions<be_with_helpers>() ==
                  md::functions_of(0x03, 0x04, 0x06, 0x10, 0x16, 0x17),
              "the big-endian accessors, the helpers aside");

// An accessor overloaded with a helper of its name, a templated accessor, and a helper named
// like the singular of an accessor the device has.
struct overloaded {
  bool coils[8] = {};
  bool read_bits(std::uint16_t address) const { return coils[address]; }
  std::uint8_t read_bits(std::uint8_t, std::uint16_t address, std::uint16_t quantity,
                         mb::mutable_byte_view packed) const {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      if (read_bits(static_cast<std::uint16_t>(address + i))) {
        packed[i / 8U] = static_cast<std::uint8_t>(packed[i / 8U] | (1U << (i % 8U)));
      }
    }
    return 0;
  }
  template <class Packed>
  std::uint8_t write_coils(std::uint16_t address, std::uint16_t quantity, Packed packed) {
    if (!fits(address, quantity)) {
      return 0x02;
    }
    for (std::uint16_t i = 0; i < quantity; ++i) {
      write_coil(address + i, md::bit_at(packed, i));
    }
    return 0;
  }
  void write_coil(std::size_t address, bool on) { coils[address] = on; }
};
static_assert(md::served_functions<overloaded>() == md::functions_of(0x01, 0x02, 0x05, 0x0F),
              "the overloaded and the templated accessor");

// Accessors inherited from two bases.
struct inherited : registers, reader {};
static_assert(md::served_functions<inherited>() ==
                  md::functions_of(0x03, 0x04, 0x06, 0x10, 0x16, 0x17),
              "the inherited accessors");

template <class Device>
int serve_with(const std::uint8_t* adu, std::size_t n, std::uint8_t* out) {
  Device d;
  const auto r = md::serve_rtu(d, 1, mb::byte_view(adu, n), mb::mutable_byte_view(out, 256));
  return r.ok() ? static_cast<int>(r.value()) : -1;
}

}  // namespace

int serve(const std::uint8_t* adu, std::size_t n, std::uint8_t* out) {
  return serve_with<device>(adu, n, out);
}

// the valid devices above, compiled with every case: the server and its checks instantiated
int serve_each(const std::uint8_t* adu, std::size_t n, std::uint8_t* out) {
  return serve_with<be_with_helpers>(adu, n, out) + serve_with<overloaded>(adu, n, out) +
         serve_with<inherited>(adu, n, out);
}
